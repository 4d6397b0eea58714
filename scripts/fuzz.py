"""Fuzz ngdgfric with bad input through the Python API and the command line; write results/fuzz.md.

Every case runs in a fresh process of its own (cwd: a temporary folder holding the case's files),
with a timeout and a cap on its address space:

* API cases run ``python -c SNIPPET``: the snippet imports ngdgfric, sets up what it needs
  (outside the check) and makes one call.  A ValueError (or FileNotFoundError for a missing file)
  is the contract: it prints ``NAMED-ERROR <Type>: <message>`` and exits 3; any other exception
  propagates (traceback, exit 1: "wrong exception type"); a call that returns prints ``SILENT``
  ("silent answer").
* CLI cases run ``python -m ngdgfric ...``.  Bad input must end with exit code 2 and exactly one
  stderr line ``ngdgfric: error: ...``, no traceback.

A negative return code is a "signal", a case killed at the timeout (its whole process group) a
"hang".  A case may name words (``expect``) one of which the error message must contain (case
insensitive, as a whole word), else "unnamed error"; output-safety cases also check that the
error came before any computing, or that an earlier result was left unchanged.  The cases marked
"issue case" are the ones listed in the issue; the rest are generated systematically (every datum
x every bad value, via the API and via a TOML problem file on the command line, bad command-line
numbers, bad files, expressions, meshes, references).

The report starts with counts per verdict and lists the cases that are not a "named error"; the
exit code is 0 iff every case run is a "named error".  Regenerate results/fuzz.md with

    python scripts/fuzz.py [--workers 2] [--timeout 30] [--only SUBSTRING] [--quick] [--out results]

``--quick`` runs only the cases of the problem-file schema (``schema_cases``: regions, holes, arcs,
symmetry sides, data per region and per side, u_D and the expression functions step, min, max, if).
"""

import argparse
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from ngdgfric.files import write_text

REPO = Path(__file__).resolve().parent.parent
RESULTS = REPO / "results"

NAMED = "named error"
UNNAMED = "unnamed error"
SIGNAL = "signal"
HANG = "hang"
SILENT = "silent answer"
TRACEBACK = "traceback"
WRONG_TYPE = "wrong exception type"
EXIT_1 = "solver failure reported as exit 1 (should be 2 for bad input)"
LATE = "error only after computing"
CHANGED = "earlier result changed"
OTHER = "other"
VERDICTS = (SIGNAL, HANG, SILENT, TRACEBACK, WRONG_TYPE, UNNAMED, EXIT_1, LATE, CHANGED, OTHER, NAMED)

# files of a case: relative path -> str or bytes (contents), DIR, FIFO or ("symlink", target)
DIR, FIFO = ("dir",), ("fifo",)


@dataclass
class Case:
    """One bad input.  API: ``snippet`` (the checked call) after ``setup``; CLI: ``argv`` of
    ``python -m ngdgfric`` after the untimed ``commands`` (argv lists, run the same way)."""

    id: str
    interface: str  # "api" or "cli"
    description: str
    snippet: str = ""
    setup: str = ""
    argv: tuple = ()
    files: dict = field(default_factory=dict)
    commands: tuple = ()
    expect: tuple = ()  # the message must contain one of these words (case insensitive)
    issue: bool = False
    check: str = ""  # "quiet": no output before the error; "unchanged": files under out/ unchanged


# ----------------------------------------------------------------------------------------- cases

PREAMBLE = """\
import dataclasses, math, os, sys
import numpy as np
import ngsolve as ngs
import ngdgfric as ndf
nan, inf = float("nan"), float("inf")
x, y = ngs.x, ngs.y
p = ndf.example_6_1()
def solve(q, h=0.25):
    return ndf.solve(q, ndf.uniform_mesh(q, h))
"""

# Example 6.1 as a problem file (ngdgfric/data/example_6_1.toml without comments); raw TOML values
BASE_TOML = {
    "material": {"E": "2000.0", "nu": "0.4"},
    "geometry": {"vertices": "[[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]",
                 "labels": '["contact", "dirichlet", "traction", "traction"]'},
    "loads": {"f": "[0.0, 0.0]", "g": '["200*(5 - y)", -190.0]'},
    "contact": {"c_n": "1.0", "m_n": "1.0", "g_a": "0.05", "c_tau": "450.0"},
}

SCALARS = {"E": "material", "nu": "material", "c_n": "contact", "m_n": "contact", "g_a": "contact",
           "c_tau": "contact", "m_t": "contact"}
COMPONENTS = {"f0": ("f", 0), "f1": ("f", 1), "g0": ("g", 0), "g1": ("g", 1)}
DATA = list(SCALARS) + list(COMPONENTS)
NEGATIVE = {"E": ["-1", "0"], "nu": ["0.5", "-1"], "c_n": ["-1"], "m_n": ["0.5"], "c_tau": ["-1"], "m_t": ["-1"]}
HUGE_INT = "1" + "0" * 400

GEOMETRY_WORDS = ("vertices", "vertex", "polygon", "side", "sides", "geometry", "self-intersecting", "intersect",
                  "intersects", "intersecting", "area", "coordinates", "coordinate")
SIZE_WORDS = ("elements", "element", "triangles", "triangle", "DOFs", "DOF", "ndof", "size", "vertices")
MAX_NDOF_WORDS = ("max-ndof", "max_ndof", "DOFs")
OUT_SOLVE = "out/6_1_sipg_p1"


def toml(changes=None, top=""):
    """The problem file of Example 6.1 with ``changes`` {"section.key": raw TOML value, or None to delete}."""
    sections = {name: dict(values) for name, values in BASE_TOML.items()}
    for dotted, raw in (changes or {}).items():
        section, key = dotted.split(".")
        if raw is None:
            sections[section].pop(key, None)
        else:
            sections.setdefault(section, {})[key] = raw
    lines = ['name = "fuzz case"'] + ([top] if top else [])
    for section, values in sections.items():
        lines += ["", f"[{section}]"] + [f"{key} = {value}" for key, value in values.items()]
    return "\n".join(lines) + "\n"


def datum_toml(datum, raw):
    """TOML change setting ``datum`` (a key of SCALARS or COMPONENTS) to the raw TOML value."""
    if datum in SCALARS:
        return {f"{SCALARS[datum]}.{datum}": raw}
    vector, k = COMPONENTS[datum]
    other = {"f": ["0.0", "0.0"], "g": ['"200*(5 - y)"', "-190.0"]}[vector]
    parts = list(other)
    parts[k] = raw
    return {f"loads.{vector}": f"[{parts[0]}, {parts[1]}]"}


def datum_api(datum, code):
    """Snippet: the problem with ``datum`` set to the Python expression ``code``, then solved."""
    if datum in SCALARS:
        return f"q = dataclasses.replace(p, {datum}={code})\nsolve(q)"
    vector, k = COMPONENTS[datum]
    pair = [f"p.{vector}[0]", f"p.{vector}[1]"]
    pair[k] = code
    return f"q = dataclasses.replace(p, {vector}=({pair[0]}, {pair[1]}))\nsolve(q)"


def as_words(expect):
    return (expect,) if isinstance(expect, str) else tuple(expect)


def datum_name(datum):
    return COMPONENTS[datum][0] if datum in COMPONENTS else datum


def slug(value):
    return value.replace("-", "minus").replace(" ", "")


def api(id, description, snippet, setup="", expect=(), issue=False, files=None):
    return Case(f"api-{id}", "api", description, snippet=snippet, setup=setup, expect=tuple(expect), issue=issue,
                files=files or {})


def cli(id, description, argv, files=None, expect=(), issue=False, commands=(), check=""):
    return Case(f"cli-{id}", "cli", description, argv=tuple(argv), files=files or {}, expect=tuple(expect),
                issue=issue, commands=tuple(tuple(c) for c in commands), check=check)


def cli_toml(id, description, text, expect=(), issue=False, mesh=("--h", "0.5"), command="solve"):
    """CLI case: ``ngdgfric solve case.toml --h 0.5`` with ``text`` (str or bytes) in case.toml."""
    return cli(id, description, [command, "case.toml", *mesh], files={"case.toml": text}, expect=expect, issue=issue)


def data_cases():
    """Every datum x every bad value, through the API (dataclasses.replace + solve) and a TOML file."""
    cases = []
    for datum in DATA:
        name = datum_name(datum)
        shown = f"{name}[{COMPONENTS[datum][1]}]" if datum in COMPONENTS else datum
        # issue: g_a = nan; c_n, c_tau, g_a = +-inf; f, g components NaN or inf
        for value in ("nan", "inf", "-inf"):
            issue = (datum == "g_a" and value == "nan") or (datum in ("c_n", "c_tau", "g_a") and "inf" in value) \
                or (datum in COMPONENTS and value in ("nan", "inf"))
            cases.append(api(f"{datum}-{slug(value)}", f"{shown} = {value}", datum_api(datum, value),
                             expect=[name], issue=issue))
            cases.append(cli_toml(f"toml-{datum}-{slug(value)}", f"{shown} = {value} in the problem file",
                                  toml(datum_toml(datum, value)), expect=[name], issue=issue))
        for value in NEGATIVE.get(datum, ()):
            cases.append(api(f"{datum}-{slug(value)}", f"{shown} = {value} (out of range)", datum_api(datum, value),
                             expect=[name]))
            cases.append(cli_toml(f"toml-{datum}-{slug(value)}",
                                  f"{shown} = {value} (out of range) in the problem file",
                                  toml(datum_toml(datum, value)), expect=[name]))
        cases.append(api(f"{datum}-string", f"{shown} = 'abc' (a string)", datum_api(datum, '"abc"'), expect=[name]))
        cases.append(api(f"{datum}-bool", f"{shown} = True (a boolean)", datum_api(datum, "True"), expect=[name]))
        cases.append(cli_toml(f"toml-{datum}-bool", f"{shown} = true (a boolean) in the problem file",
                              toml(datum_toml(datum, "true")), expect=[name]))
        cases.append(cli_toml(f"toml-{datum}-table", f"{shown} = {{ a = 1 }} (a table) in the problem file",
                              toml(datum_toml(datum, "{ a = 1 }")), expect=[name]))
        issue = datum == "E"  # issue: E = 1 followed by 400 zeros
        cases.append(cli_toml(f"toml-{datum}-huge-int", f"{shown} = 1 followed by 400 zeros (an integer) in the "
                                                         "problem file", toml(datum_toml(datum, HUGE_INT)),
                              expect=[name], issue=issue))
    return cases


# expressions that are NaN, infinite or out of range on the domain (x in [0, 1], y in [0.05, 1.05]):
# slug: (expression for the problem file, the same as a Python expression of ngs.x, ngs.y)
BAD_FUNCTIONS = {
    "div-zero": ("1/(x - x)", "1/(x - x)"),
    "exp1000": ("exp(1000*x)", "ngs.exp(1000*x)"),
    "sqrt-neg": ("sqrt(x - 2)", "ngs.sqrt(x - 2)"),
    "log-x": ("log(x)", "ngs.log(x)"),
    "neg-const": ("-2000 + 0*x", "-2000 + 0*x"),
    "neg-half": ("2000*(0.5 - x)", "2000*(0.5 - x)"),
}
FUNCTION_CASES = [("E", "div-zero"), ("E", "exp1000"), ("f0", "div-zero"), ("f0", "exp1000"), ("g0", "div-zero"),
                  ("g0", "exp1000"), ("c_n", "div-zero"), ("c_n", "exp1000"), ("c_tau", "div-zero"),
                  ("c_tau", "exp1000"), ("g_a", "div-zero"), ("g_a", "exp1000"), ("g_a", "sqrt-neg"),
                  ("g_a", "log-x"), ("E", "neg-const"), ("E", "neg-half")]


def function_cases():
    """Coefficient functions bad somewhere on the domain (all from the issue): built and solved."""
    cases = []
    for datum, kind in FUNCTION_CASES:
        text, code = BAD_FUNCTIONS[kind]
        name = datum_name(datum)
        shown = f"{name}[{COMPONENTS[datum][1]}]" if datum in COMPONENTS else datum
        cases.append(api(f"{datum}-cf-{kind}", f"{shown} = {code} (CoefficientFunction), solved",
                         datum_api(datum, code), expect=[name], issue=True))
        cases.append(cli_toml(f"toml-{datum}-expr-{kind}", f'{shown} = "{text}" in the problem file',
                              toml(datum_toml(datum, json.dumps(text))), expect=[name], issue=True))
    for datum in ("E", "c_n", "g_a", "c_tau"):
        cases.append(api(f"{datum}-cf-nan", f"{datum} = CoefficientFunction(nan), solved",
                         datum_api(datum, "ngs.CoefficientFunction(nan)"), expect=[datum]))
    # found by the review: complex data (g_a = 0.001j was solved as 0), and c_n < 0 only within 1e-6 of
    # the contact rule's first Gauss point on h = 1/4 (missed by rules of one degree; solver failure, exit 1)
    for datum in ("E", "g_a", "c_tau"):
        cases.append(api(f"{datum}-cf-complex", f"{datum} = CoefficientFunction(0.001j), solved",
                         datum_api(datum, "ngs.CF(0.001j)"), expect=[datum]))
    gauss = "(x - 0.25 * (0.5 - 3**0.5 / 6))**2 - 1e-12"
    cases.append(api("c_n-cf-contact-gauss-point", "c_n < 0 only at a contact Gauss point, solved",
                     datum_api("c_n", gauss), expect=["c_n"]))
    cases.append(cli_toml("toml-c_n-expr-contact-gauss-point", "c_n < 0 only at a contact Gauss point in the "
                          "problem file, solve --h 0.25", toml(datum_toml("c_n", json.dumps(
                              "(x - 0.25*(0.5 - 3**0.5/6))**2 - 1e-12"))), expect=["c_n"], mesh=("--h", "0.25")))
    return cases


# slug: (text, Python code making the text when too long for a command line, description)
EXPRESSIONS = {
    "import": ("__import__('os').system('touch pwned')", None, "forbidden name __import__"),
    "attribute": ("x.__class__", None, "attribute access"),
    "lambda": ("(lambda: 1)()", None, "lambda"),
    "list": ("[x, y]", None, "a list"),
    "string": ("'abc'", None, "a string constant"),
    "conditional": ("y if x else 1", None, "conditional expression"),
    "two-args": ("sin(x, y)", None, "function with two arguments"),
    "keyword": ("sin(x=1)", None, "keyword argument"),
    "empty": ("", None, "empty string"),
    "blank": ("   ", None, "blank string"),
    "nan-name": ("nan", None, "the name nan"),
    "nesting-5000": ("(" * 5000 + "x" + ")" * 5000, "'(' * 5000 + 'x' + ')' * 5000", "5000 nested parentheses"),
    "nesting-150": ("(" * 150 + "x" + ")" * 150, None, "150 nested parentheses"),
    "unary-990": ("-" * 990 + "x", None, "990 unary minus signs"),
    "long-200k": ("+".join(["x"] * 100_000), "'+'.join(['x'] * 100000)", "x+x+...+x, 200 000 characters"),
    "pow-1e10": ("x**1e10", None, "x**1e10 (E = 0 for x < 1)"),
    "tower": ("10**10**10", None, "10**10**10"),
    "const-1e400": ("1e400", None, "constant 1e400"),
    "complex": ("(-1)**0.5", None, "complex (-1)**0.5"),
    "div-zero-const": ("1/0", None, "1/0"),
    "zero-neg-pow": ("0**-1", None, "0**-1"),
    "log0": ("log(0)", None, "log(0)"),
    "exp-overflow": ("exp(1000)", None, "exp(1000)"),
    "digits-999": ("9" * 999, None, "a number of 999 digits"),
}


def expression_cases():
    """Bad expression strings for E: parse_expression (then solve) in the API, a problem file on the CLI."""
    cases = []
    for kind, (text, code, description) in EXPRESSIONS.items():
        code = code or repr(text)
        snippet = f"q = dataclasses.replace(p, E=ndf.problem_file.parse_expression({code}))\nsolve(q)"
        expect = ["E"] if kind == "pow-1e10" else []  # the others fail in the parser, which knows no key
        cases.append(api(f"expr-{kind}", f"E = parse_expression of {description}", snippet, expect=expect))
        cases.append(cli_toml(f"toml-expr-{kind}", f"E = {description} in the problem file",
                              toml({"material.E": json.dumps(text)}), expect=["E"]))
    return cases


R = [(0, 0.05), (1, 0.05), (1, 1.05), (0, 1.05)]
L4 = ("contact", "dirichlet", "traction", "traction")
L5 = ("contact", "contact", "dirichlet", "traction", "traction")
NAN, INF = float("nan"), float("inf")
# slug: (description, vertices, labels, issue, expect)
POLYGONS = {
    "duplicate": ("duplicate vertex (1, 0.05) twice", [R[0], R[1], R[1], R[2], R[3]], L5, True, GEOMETRY_WORDS),
    "nan": ("a NaN vertex coordinate", [R[0], (1, NAN), R[2], R[3]], L4, True, GEOMETRY_WORDS),
    "inf": ("an infinite vertex coordinate", [R[0], (INF, 0.05), R[2], R[3]], L4, True, GEOMETRY_WORDS),
    "near-duplicate": ("near-duplicate vertices (1, 0.05) and (1 + 1e-12, 0.05)",
                       [R[0], R[1], (1 + 1e-12, 0.05), R[2], R[3]], L5, True, GEOMETRY_WORDS),
    "bowtie": ("self-intersecting bow-tie (0,0) (3,0) (0,1) (1,1), positive signed area",
               [(0, 0), (3, 0), (0, 1), (1, 1)], L4, True, GEOMETRY_WORDS),
    "too-few": ("two vertices", [(0, 0), (1, 0)], ("contact", "dirichlet"), False, GEOMETRY_WORDS),
    "empty": ("no vertices", [], (), False, GEOMETRY_WORDS),
    "label-count": ("4 vertices, 3 labels", R, L4[:3], False, ("labels", "label")),
    "unknown-label": ("side label 'tracton' (a typo)", R, ("contact", "dirichlet", "traction", "tracton"), False,
                      ("tracton",)),
    "no-dirichlet": ("no side labelled dirichlet", R, ("contact", "traction", "traction", "traction"), False,
                     ("dirichlet",)),
    "clockwise": ("clockwise vertices", [R[3], R[2], R[1], R[0]], ("traction", "dirichlet", "contact", "traction"),
                  False, GEOMETRY_WORDS),
    "collinear": ("all vertices on a line", [(0, 0), (0.5, 0), (1, 0)], ("contact", "dirichlet", "traction"), False,
                  GEOMETRY_WORDS),
    "sliver": ("rectangle 1 x 1e-300 (area 1e-300)", [(0, 0), (1, 0), (1, 1e-300), (0, 1e-300)], L4, False,
               GEOMETRY_WORDS + SIZE_WORDS),
    # found by the review: valid but thin (Netgen busy for minutes, deaf to Ctrl-C), far from the origin
    "thin-strip": ("a 1 x 1e-5 strip", [(0, 0.05), (1, 0.05), (1, 0.05 + 1e-5), (0, 0.05 + 1e-5)], L4, False,
                   ("Netgen", "polygon")),
    "far-from-origin": ("the unit square moved to (1e7, 1e7)", [(a + 1e7, b + 1e7) for a, b in R], L4, False,
                        ("polygon", "origin")),
    "huge": ("square of side 1e300", [(0, 0), (1e300, 0), (1e300, 1e300), (0, 1e300)], L4, False,
             GEOMETRY_WORDS + SIZE_WORDS),
    "string-coordinate": ("a coordinate 'a'", [R[0], ("a", 0.05), R[2], R[3]], L4, False, GEOMETRY_WORDS),
    "three-coordinates": ("vertices with three coordinates", [(a, b, 0) for a, b in R], L4, False, GEOMETRY_WORDS),
}


def _number(value):
    if isinstance(value, str):
        return json.dumps(value)
    if value != value:
        return "nan"
    if value in (INF, -INF):
        return ("-" if value < 0 else "") + "inf"
    return repr(value)


def polygon_text(vertices, labels, language):
    if language == "python":
        points = ", ".join("(" + ", ".join(_number(c) for c in v) + ")" for v in vertices)
        return f"[{points}]", repr(tuple(labels))
    points = ", ".join("[" + ", ".join(_number(c) for c in v) + "]" for v in vertices)
    return f"[{points}]", json.dumps(list(labels))


def geometry_cases():
    cases = []
    for kind, (description, vertices, labels, issue, expect) in POLYGONS.items():
        v, lab = polygon_text(vertices, labels, "python")
        snippet = f"geo = ndf.Polygon({v}, {lab})\nq = dataclasses.replace(p, geometry=geo)\nndf.netgen_mesh(q, 0.2)"
        cases.append(api(f"polygon-{kind}", f"Polygon: {description}; netgen_mesh(maxh 0.2)", snippet,
                         expect=expect, issue=issue))
        v, lab = polygon_text(vertices, labels, "toml")
        cases.append(cli_toml(f"toml-polygon-{kind}", f"[geometry] {description}; solve --maxh 0.5",
                              toml({"geometry.vertices": v, "geometry.labels": lab}), expect=expect, issue=issue,
                              mesh=("--maxh", "0.5")))
    for value in ("inf", "nan"):
        snippet = (f'geo = ndf.Polygon.rectangle(0, 0.05, {value}, 1.05, bottom="contact", right="dirichlet", '
                   'top="traction", left="traction")\n'
                   'q = dataclasses.replace(p, geometry=geo)\nndf.uniform_mesh(q, 0.5)')
        cases.append(api(f"rectangle-{value}", f"Polygon.rectangle with x1 = {value}; uniform_mesh(h 0.5)", snippet,
                         expect=("x1", "rectangle") + GEOMETRY_WORDS))
    # a ContactProblem whose geometry or boundary names are wrong
    cases.append(api("problem-geometry-string", "ContactProblem(geometry='square')",
                     "dataclasses.replace(p, geometry='square')", expect=["geometry"]))
    cases.append(api("problem-same-names", "dirichlet and contact boundary names equal",
                     "dataclasses.replace(p, dirichlet='contact')", expect=["dirichlet", "contact", "names"]))
    cases.append(api("problem-E-vector", "E = a 2-vector CoefficientFunction",
                     "solve(dataclasses.replace(p, E=ngs.CF((1, 2))))", expect=["E"]))
    cases.append(api("problem-f-three", "f = (1, 2, 3)", "solve(dataclasses.replace(p, f=(1.0, 2.0, 3.0)))",
                     expect=["f"]))
    cases.append(api("problem-f-cf3", "f = a 3-vector CoefficientFunction",
                     "solve(dataclasses.replace(p, f=ngs.CF((1, 2, 3))))", expect=["f"]))
    cases.append(api("problem-g-string", "g = 'abc'", "solve(dataclasses.replace(p, g='abc'))", expect=["g"]))
    return cases


def mesh_cases():
    cases = [
        api("uniform-mesh-1e-5", "uniform_mesh(p, 1e-5): 4e10 triangles", "ndf.uniform_mesh(p, 1e-5)",
            expect=SIZE_WORDS, issue=True),
        api("netgen-mesh-1e-9", "netgen_mesh(p, 1e-9)", "ndf.netgen_mesh(p, 1e-9)", expect=SIZE_WORDS, issue=True),
        api("uniform-mesh-1e-300", "uniform_mesh(p, 1e-300)", "ndf.uniform_mesh(p, 1e-300)", expect=SIZE_WORDS),
        api("netgen-mesh-1e-300", "netgen_mesh(p, 1e-300)", "ndf.netgen_mesh(p, 1e-300)", expect=SIZE_WORDS),
    ]
    for value in ("0", "-1", "nan", "inf", '"0.5"', "True", "0.3"):
        cases.append(api(f"uniform-mesh-h-{slug(value.strip(chr(34)))}", f"uniform_mesh(p, {value})",
                         f"ndf.uniform_mesh(p, {value})", expect=["h"]))
    cases.append(api("uniform-mesh-diagonal", "uniform_mesh(p, 0.5, diagonal='x')",
                     "ndf.uniform_mesh(p, 0.5, diagonal='x')", expect=["diagonal"]))
    for value in ("0", "-1", "nan", "inf", '"0.5"', "True"):
        cases.append(api(f"netgen-mesh-maxh-{slug(value.strip(chr(34)))}", f"netgen_mesh(p, {value})",
                         f"ndf.netgen_mesh(p, {value})", expect=["maxh"]))
    # a mesh of another problem with the same boundary names (issue)
    others = {
        "shifted": ("the rectangle (2, 3) x (3, 4)", "(2, 3, 3, 4)"),
        "scaled": ("the rectangle (0, 2) x (0.05, 2.05)", "(0, 0.05, 2, 2.05)"),
    }
    for kind, (description, box) in others.items():
        setup = (f"geo = ndf.Polygon.rectangle(*{box}, bottom='contact', right='dirichlet', top='traction', "
                 "left='traction')\nmesh = ndf.uniform_mesh(dataclasses.replace(p, geometry=geo), 0.5)")
        cases.append(api(f"solve-other-mesh-{kind}", f"solve Example 6.1 on a uniform mesh of {description}, same "
                                                      "labels", "ndf.solve(p, mesh)", setup=setup, expect=["mesh"],
                         issue=True))
    cases.append(api("solve-other-mesh-6-2", "solve Example 6.1 on a uniform mesh of Example 6.2 (same labels)",
                     "ndf.solve(p, mesh)", setup="p2 = ndf.example_6_2()\nmesh = ndf.uniform_mesh(p2, 0.5)",
                     expect=["mesh"], issue=True))
    # bad arguments of solve
    bad_arguments = [("order-0", "order=0", "order"), ("order-1.5", "order=1.5", "order"),
                     ("order-minus1", "order=-1", "order"), ("order-string", "order='1'", "order"),
                     ("order-1000", "order=1000", ("order",) + SIZE_WORDS), ("method-foo", "method='foo'", "method"),
                     ("eta-minus1", "eta=-1.0", "eta"), ("eta-0", "eta=0.0", "eta"), ("eta-nan", "eta=nan", "eta"),
                     ("solver-foo", "solver='foo'", "solver"), ("solver-tol-minus1", "solver_tol=-1.0", "solver_tol"),
                     ("solver-tol-nan", "solver_tol=nan", "solver_tol"),
                     ("solver-tol-0", "solver_tol=0.0", "solver_tol"), ("maxit-0", "maxit=0", "maxit"),
                     ("unknown-option", "foo=1", "foo")]
    for kind, argument, expect in bad_arguments:
        cases.append(api(f"solve-{kind}", f"solve(p, mesh, {argument})", f"ndf.solve(p, mesh, {argument})",
                         setup="mesh = ndf.uniform_mesh(p, 0.5)", expect=as_words(expect)))
    cases.append(api("solve-mesh-string", "solve(p, 'not a mesh')", "ndf.solve(p, 'not a mesh')", expect=["mesh"]))
    cases.append(api("solve-mesh-none", "solve(p, None)", "ndf.solve(p, None)", expect=["mesh"]))
    return cases


REFERENCE_SETUP = """\
sol = ndf.solve(p, ndf.uniform_mesh(p, 0.5))
ndf.save_reference(sol, "ref.npz", 0.0)
d = dict(np.load("ref.npz"))
"""


def reference_cases():
    """load_reference of damaged .npz files, made inside the snippet from a reference on h = 0.5."""
    tampered = {  # slug: (description, change of d, issue)
        "triangle-index-oob": ("a triangle vertex number 10**6 (out of range)", 'd["triangles"][0, 0] = 10**6', True),
        "triangle-index-negative": ("a triangle vertex number -7", 'd["triangles"][0, 0] = -7', False),
        "missing-u": ("no coefficient array u", 'del d["u"]', False),
        "u-nan": ("NaN coefficients", 'd["u"][:] = nan', False),
        "orders-negative": ("element orders -1", 'd["orders"][:] = -1', False),
        "orders-huge": ("element orders 50", 'd["orders"][:] = 50', False),
        "labels-unknown": ("boundary labels 'foo'", 'd["labels"] = np.full(d["labels"].shape, "foo")', False),
        "points-nan": ("NaN vertex coordinates", 'd["points"][0, 0] = nan', False),
        "object-array": ("labels stored as a pickled object array",
                         'd["labels"] = np.array(list(d["labels"]), dtype=object)', False),
        "eta-string": ("eta_h stored as a string", 'd["eta_h"] = np.array("abc")', False),
    }
    cases = []
    for kind, (description, change, issue) in tampered.items():
        setup = REFERENCE_SETUP + change + '\nnp.savez("bad.npz", **d)'
        cases.append(api(f"reference-{kind}", f"load_reference of an .npz with {description}",
                         'ndf.load_reference("bad.npz", p)', setup=setup, expect=["bad.npz"], issue=issue))
    files = {
        "truncated": ("the first half of a reference file", 'data = open("ref.npz", "rb").read()\n'
                      'open("bad.npz", "wb").write(data[: len(data) // 2])', True),
        "garbage": ("garbage bytes", 'open("bad.npz", "wb").write(bytes(range(256)) * 64)', True),
        "empty": ("an empty file", 'open("bad.npz", "wb").close()', False),
        "directory": ("a directory", 'os.mkdir("bad.npz")', False),
    }
    for kind, (description, make, issue) in files.items():
        cases.append(api(f"reference-{kind}", f"load_reference of {description}", 'ndf.load_reference("bad.npz", p)',
                         setup=REFERENCE_SETUP + make, expect=["bad.npz"], issue=issue))
    cases.append(api("reference-6-2-for-6-1", "load_reference of a reference of Example 6.2 for Example 6.1",
                     'ndf.load_reference("ref62.npz", p)',
                     setup="p2 = ndf.example_6_2()\nsol2 = ndf.solve(p2, ndf.uniform_mesh(p2, 0.5))\n"
                           'ndf.save_reference(sol2, "ref62.npz", 0.0)', expect=["ref62.npz"], issue=True))
    cases.append(api("reference-missing", "load_reference of a missing file", 'ndf.load_reference("nothere.npz", p)',
                     expect=["nothere.npz"]))
    return cases


def file_cases():
    """Problem files that are missing, empty, binary, directories, not UTF-8, not TOML, or badly structured."""
    body = toml().split("\n", 1)[1]  # without the name line
    special = {  # slug: (description, file name, contents, issue)
        "missing": ("a missing problem file", "missing.toml", None, False),
        "empty": ("an empty problem file", "empty.toml", "", False),
        "binary": ("a binary problem file (bytes 0..255)", "binary.toml", bytes(range(256)) * 4, False),
        "directory": ("a directory as problem file", "dir.toml", DIR, False),
        "non-utf8": ('a problem file with the bytes \\xff\\xfe in a string', "nonutf8.toml",
                     b'name = "\xff\xfe"\n' + body.encode(), True),
        "symlink-loop": ("a symbolic link to itself", "loop.toml", ("symlink", "loop.toml"), False),
        "fifo": ("a named pipe (FIFO) as problem file", "fifo.toml", FIFO, False),
    }
    syntax = {
        "unclosed-bracket": ("unclosed bracket", toml({"geometry.vertices": "[[0.0, 0.05], [1.0, 0.05]"})),
        "no-value": ("key without a value", toml({"material.E": ""})),
        "duplicate-key": ("key E given twice", toml().replace("E = 2000.0", "E = 2000.0\nE = 1000.0")),
        "unterminated-string": ("unterminated string", toml().replace('name = "fuzz case"', 'name = "fuzz case')),
        "garbage-line": ("a line that is not TOML", toml(top="this is not toml")),
    }
    cases = []
    for kind, (description, name, contents, issue) in special.items():
        files = {} if contents is None else {name: contents}
        expect = [name]
        cases.append(api(f"load-{kind}", f"load_problem of {description}", f"ndf.load_problem({name!r})",
                         files=files, expect=expect, issue=issue))
        cases.append(cli(f"file-{kind}", description, ["solve", name, "--h", "0.5"], files=files, expect=expect,
                         issue=issue))
    for kind, (description, text) in syntax.items():
        cases.append(api(f"load-syntax-{kind}", f"load_problem: TOML syntax error, {description}",
                         'ndf.load_problem("bad.toml")', files={"bad.toml": text}, expect=["bad.toml"]))
        cases.append(cli(f"file-syntax-{kind}", f"TOML syntax error: {description}",
                         ["solve", "bad.toml", "--h", "0.5"], files={"bad.toml": text}, expect=["bad.toml"]))
    structure = {  # slug: (description, text, expect)
        "unknown-top-key": ("unknown top-level key foo", toml(top="foo = 1"), ["foo"]),
        "unknown-key": ("unknown key material.Young", toml({"material.Young": "1.0"}), ["Young"]),
        "unknown-section": ("unknown section [extra]", toml({"extra.a": "1"}), ["extra"]),
        "misspelled-section": ("section [contacts] instead of [contact]",
                               toml().replace("[contact]", "[contacts]"), ["contacts", "contact"]),
        "missing-E": ("no E", toml({"material.E": None}), ["E"]),
        "missing-vertices": ("no vertices", toml({"geometry.vertices": None}), ["vertices"]),
        "missing-contact": ("no [contact] section", toml().split("[contact]")[0], ["contact", "c_n"]),
        "f-one-component": ("f = [1.0]", toml({"loads.f": "[1.0]"}), ["f"]),
        "f-three-components": ("f = [1.0, 2.0, 3.0]", toml({"loads.f": "[1.0, 2.0, 3.0]"}), ["f"]),
        "vertices-string": ('vertices = "square"', toml({"geometry.vertices": '"square"'}), ["vertices"]),
        "labels-numbers": ("labels = [1, 2, 3, 4]", toml({"geometry.labels": "[1, 2, 3, 4]"}), ["labels"]),
        "name-number": ("name = 5", toml().replace('name = "fuzz case"', "name = 5"), ["name"]),
        "material-number": ("material = 5 instead of a table", toml().replace("[material]\nE = 2000.0\nnu = 0.4",
                                                                              "material = 5"), ["material"]),
        "boundary-empty": ('[boundaries] dirichlet = ""', toml({"boundaries.dirichlet": '""'}), ["dirichlet"]),
        "boundary-same": ('[boundaries] dirichlet = "contact"', toml({"boundaries.dirichlet": '"contact"'}),
                          ["dirichlet", "contact", "boundaries"]),
        "expr-in-nu": ('nu = "0.4 + 0.2*x" (an expression that reaches 0.6)', toml({"material.nu": '"0.4 + 0.2*x"'}),
                       ["nu"]),
    }
    for kind, (description, text, expect) in structure.items():
        cases.append(cli_toml(f"toml-{kind}", f"problem file: {description}", text, expect=expect))
    return cases


def argument_cases():
    """Bad command-line options on tiny meshes."""
    size = [  # (slug, argv, issue)
        ("size-solve-h-1e-5", ["solve", "6.1", "--h", "1e-5"], True),
        ("size-solve-maxh-1e-9", ["solve", "6.1", "--maxh", "1e-9"], True),
        ("size-uniform-levels-14", ["uniform", "6.1", "--levels", "14"], True),
        ("size-adaptive-h-1e-5", ["adaptive", "6.1", "--h", "1e-5", "--levels", "1"], False),
        ("size-adaptive-maxh-1e-9", ["adaptive", "6.1", "--maxh", "1e-9", "--levels", "1"], False),
        ("size-solve-order-1000", ["solve", "6.1", "--h", "0.5", "--order", "1000"], False),
    ]
    cases = [cli(kind, "mesh or space far too large", argv, expect=SIZE_WORDS + ("order",), issue=issue)
             for kind, argv, issue in size]
    solve = ["solve", "6.1", "--h", "0.5"]
    uniform = ["uniform", "6.1", "--levels", "2"]
    adaptive = ["adaptive", "6.1", "--h", "0.5", "--levels", "2"]
    bad = [  # (slug, argv, expect)
        ("order-0", solve + ["--order", "0"], "order"),
        ("order-minus1", solve + ["--order", "-1"], "order"),
        ("order-1.5", solve + ["--order", "1.5"], "order"),
        ("order-abc", solve + ["--order", "abc"], "order"),
        ("order-1e400", solve + ["--order", "1e400"], "order"),
        ("h-minus1", ["solve", "6.1", "--h", "-1"], "h"),
        ("h-0", ["solve", "6.1", "--h", "0"], "h"),
        ("h-nan", ["solve", "6.1", "--h", "nan"], "h"),
        ("h-inf", ["solve", "6.1", "--h", "inf"], "h"),
        ("h-0.3", ["solve", "6.1", "--h", "0.3"], "h"),
        ("h-abc", ["solve", "6.1", "--h", "abc"], "h"),
        ("maxh-inf", ["solve", "6.1", "--maxh", "inf"], "maxh"),
        ("maxh-nan", ["solve", "6.1", "--maxh", "nan"], "maxh"),
        ("maxh-0", ["solve", "6.1", "--maxh", "0"], "maxh"),
        ("h-and-maxh", ["solve", "6.1", "--h", "0.5", "--maxh", "0.5"], "maxh"),
        ("uniform-levels-0", ["uniform", "6.1", "--levels", "0"], "levels"),
        ("uniform-levels-1", ["uniform", "6.1", "--levels", "1"], "levels"),
        ("uniform-levels-1.5", ["uniform", "6.1", "--levels", "1.5"], "levels"),
        ("adaptive-levels-0", ["adaptive", "6.1", "--h", "0.5", "--levels", "0"], "levels"),
        ("adaptive-theta-2", adaptive + ["--theta", "2"], "theta"),
        ("adaptive-theta-0", adaptive + ["--theta", "0"], "theta"),
        ("adaptive-theta-nan", adaptive + ["--theta", "nan"], "theta"),
        ("adaptive-max-ndof-0", adaptive + ["--max-ndof", "0"], MAX_NDOF_WORDS),
        ("adaptive-max-order-0", adaptive + ["--hp", "--max-order", "0"], "max-order"),
        ("adaptive-tol-minus1", adaptive + ["--tol", "-1"], "tol"),
        ("adaptive-weights-foo", adaptive + ["--weights", "foo"], "weights"),
        ("method-foo", solve + ["--method", "foo"], "method"),
        ("uniform-method-foo", uniform + ["--method", "sipg", "foo"], "method"),
        ("eta-minus1", solve + ["--eta", "-1"], "eta"),
        ("eta-0", solve + ["--eta", "0"], "eta"),
        ("eta-nan", solve + ["--eta", "nan"], "eta"),
        ("eta-inf", solve + ["--eta", "inf"], "eta"),
        ("solver-tol-0", solve + ["--solver-tol", "0"], "solver-tol"),
        ("solver-tol-minus1", solve + ["--solver-tol", "-1"], "solver-tol"),
        ("solver-tol-nan", solve + ["--solver-tol", "nan"], "solver-tol"),
        ("solver-foo", solve + ["--solver", "foo"], "solver"),
        ("scale-minus1", solve + ["--scale", "-1"], "scale"),
        ("scale-inf", solve + ["--scale", "inf"], "scale"),
        ("solve-max-ndof-10", solve + ["--max-ndof", "10"], MAX_NDOF_WORDS),
        ("solve-max-ndof-0", solve + ["--max-ndof", "0"], MAX_NDOF_WORDS),
        ("uniform-max-ndof-10", ["uniform", "6.1", "--levels", "3", "--max-ndof", "10"], MAX_NDOF_WORDS),
        ("unknown-option", solve + ["--foo"], "foo"),
        ("unknown-example", ["solve", "6.3", "--h", "0.5"], "6.3"),
        ("empty-problem", ["solve", "", "--h", "0.5"], "problem"),
        ("no-problem", ["solve"], "PROBLEM"),
        ("no-command", [], "COMMAND"),
        ("unknown-command", ["frobnicate", "6.1"], "frobnicate"),
    ]
    cases += [cli(f"arg-{kind}", f"bad command line ({as_words(expect)[0]})", argv, expect=as_words(expect))
              for kind, argv, expect in bad]
    return cases


def output_file(argv, suffix):
    """The file with ``suffix`` that ``ngdgfric ARGV --out out`` writes for Example 6.1 (the command line's own
    naming, so that a blocked output file follows a change of the defaults)."""
    from ngdgfric import cli

    args = cli.build_parser().parse_args([*argv, "--out", "out"])
    return next(str(path) for path in cli.outputs(args, "6_1") if path.suffix == suffix)


def output_cases():
    """Output safety (issue): unwritable output folders fail before computing; files that cannot be
    written are errors; an earlier adaptive result is not truncated by a rerun."""
    commands = {"solve": ["solve", "6.1", "--h", "0.5"], "uniform": ["uniform", "6.1", "--levels", "2"],
                "adaptive": ["adaptive", "6.1", "--h", "0.5", "--levels", "2"]}
    cases = []
    for command, argv in commands.items():
        cases.append(cli(f"out-proc-{command}", f"{command} --out /proc/nonexistent/out (cannot be created)",
                         argv + ["--out", "/proc/nonexistent/out"], expect=["/proc/nonexistent/out"], issue=True,
                         check="quiet"))
        cases.append(cli(f"out-under-file-{command}", f"{command} --out afile/sub, afile a regular file",
                         argv + ["--out", "afile/sub"], files={"afile": "x\n"}, expect=["afile/sub", "afile"],
                         issue=True, check="quiet"))
        cases.append(cli(f"out-is-file-{command}", f"{command} --out outfile, outfile a regular file",
                         argv + ["--out", "outfile"], files={"outfile": "x\n"}, expect=["outfile"], check="quiet"))
    blocked = [  # (slug, argv, path made a directory, issue)
        ("vtu", commands["solve"], f"{OUT_SOLVE}.vtu", True),
        ("csv", commands["solve"], f"{OUT_SOLVE}.csv", False),
        ("png", commands["solve"], f"{OUT_SOLVE}.png", False),
        ("uniform-md", commands["uniform"], "out/6_1_uniform.md", False),
        ("adaptive-csv", commands["adaptive"], output_file(commands["adaptive"], ".csv"), False),
    ]
    for kind, argv, path, issue in blocked:
        cases.append(cli(f"out-blocked-{kind}", f"{argv[0]} into out/ where {path} is a directory (cannot be written)",
                         argv + ["--out", "out"], files={path: DIR}, expect=[Path(path).suffix[1:], Path(path).name],
                         issue=issue))
    rerun = commands["adaptive"] + ["--out", "out"]
    cases.append(cli("out-adaptive-rerun", "adaptive rerun into out/ holding the result of the same run (must refuse, "
                                           "earlier files unchanged)", rerun, commands=[rerun],
                     expect=["out", Path(output_file(rerun, ".csv")).name, "overwrite", "exists"], issue=True,
                     check="unchanged"))
    return cases


# ------------------------------------------------ the problem-file schema: regions, holes, arcs, data per part

SQUARE = "[[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]"
SQUARE_LABELS = '["contact", "dirichlet", "traction", "traction"]'
LOWER = "[[0.0, 0.05], [1.0, 0.05], [1.0, 0.5], [0.0, 0.5]]"
UPPER = "[[0.0, 0.5], [1.0, 0.5], [1.0, 1.05], [0.0, 1.05]]"
LOWER_LABELS = '["contact", "dirichlet", "interface", "traction"]'
UPPER_LABELS = '["interface", "dirichlet", "traction", "traction"]'


def inline(*tables):
    """A TOML array of inline tables from dicts of raw TOML values."""
    return "[" + ", ".join("{ " + ", ".join(f"{key} = {value}" for key, value in table.items() if value is not None)
                           + " }" for table in tables) + "]"


def regions(*tables):
    """Changes replacing [geometry] vertices / labels by the region tables ``tables``."""
    return {"geometry.vertices": None, "geometry.labels": None, "geometry.region": inline(*tables)}


def holes(*tables):
    """Changes adding the hole tables ``tables`` to Example 6.1's square."""
    return {"geometry.hole": inline(*tables)}


def two_regions(lower=None, upper=None):
    return regions({"name": '"lower"', "vertices": LOWER, "labels": LOWER_LABELS, **(lower or {})},
                   {"name": '"upper"', "vertices": UPPER, "labels": UPPER_LABELS, **(upper or {})})


def circle(centre="[0.5, 0.5]", radius="0.1", label='"traction"', **more):
    return {"centre": centre, "radius": radius, "label": label, **more}


def arcs(raw):
    return {"geometry.arcs": raw}


# slug: (description, changes of the Example 6.1 file, words one of which the error must contain); all
# through the command line (solve --maxh 0.5) and the API (load_problem, netgen_mesh, solve)
SCHEMA_CASES = {
    # regions
    "region-string": ('region = "omega"', {"geometry.vertices": None, "geometry.labels": None,
                                            "geometry.region": '"omega"'}, ["region"]),
    "region-numbers": ("region = [1, 2]", {"geometry.vertices": None, "geometry.labels": None,
                                           "geometry.region": "[1, 2]"}, ["region"]),
    "region-empty": ("region = []", {"geometry.vertices": None, "geometry.labels": None, "geometry.region": "[]"},
                     ["region"]),
    "region-and-vertices": ("[geometry] vertices and a region table", {
        "geometry.region": inline({"vertices": SQUARE, "labels": SQUARE_LABELS})}, ["vertices", "region"]),
    "region-unnamed-of-two": ("two regions, the second without a name", two_regions(upper={"name": None}),
                              ["name"]),
    "region-same-name": ("two regions named lower", two_regions(upper={"name": '"lower"'}), ["name"]),
    "region-name-space": ('region name "steel plate"', two_regions(lower={"name": '"steel plate"'}), ["name"]),
    "region-name-number": ("region name 5", two_regions(lower={"name": "5"}), ["name"]),
    "region-name-interface": ('region name "interface"', two_regions(lower={"name": '"interface"'}), ["name"]),
    "region-unknown-key": ('region key colour = "red"', two_regions(lower={"colour": '"red"'}), ["colour"]),
    "region-no-labels": ("region without labels", two_regions(upper={"labels": None}), ["labels"]),
    "region-label-count": ("region with 3 labels for 4 sides", two_regions(
        upper={"labels": '["interface", "dirichlet", "traction"]'}), ["labels", "label"]),
    "region-label-hyphen": ('side label "top-side"', two_regions(
        upper={"labels": '["interface", "dirichlet", "top-side", "traction"]'}), ["label"]),
    "region-nan-vertex": ("region vertex (nan, 0.5)", two_regions(
        lower={"vertices": "[[0.0, 0.05], [1.0, 0.05], [1.0, 0.5], [nan, 0.5]]"}), ["vertices", "region"]),
    "region-vertex-strings": ('region vertices ["a", "b"]', two_regions(lower={"vertices": '["a", "b"]'}),
                              ["vertices"]),
    "region-clockwise": ("clockwise region", two_regions(
        lower={"vertices": "[[0.0, 0.5], [1.0, 0.5], [1.0, 0.05], [0.0, 0.05]]"}), ["region", "counter-clockwise"]),
    "region-twice-the-same-loop": ("two regions with the same loop", two_regions(
        upper={"vertices": LOWER, "labels": LOWER_LABELS}), ["region", "geometry", "domain"]),
    "region-circle-radius-zero": ("circular inclusion of radius 0", regions(
        {"name": '"matrix"', "vertices": SQUARE, "labels": SQUARE_LABELS},
        {"name": '"fibre"', **circle(radius="0", label='"interface"')}), ["radius"]),
    "region-circle-and-vertices": ("a region with centre, radius and vertices", regions(
        {"vertices": SQUARE, "labels": SQUARE_LABELS, "centre": "[0.5, 0.5]"}), ["centre", "vertices", "circle"]),
    # holes
    "hole-outside": ("a hole outside the region", holes(circle(centre="[3.0, 0.5]")), ["hole"]),
    "hole-radius-negative": ("a hole of radius -0.1", holes(circle(radius="-0.1")), ["radius"]),
    "hole-radius-bool": ("a hole of radius true", holes(circle(radius="true")), ["radius"]),
    "hole-radius-string": ('a hole of radius "0.1"', holes(circle(radius='"0.1"')), ["radius"]),
    "hole-radius-huge": ("a hole of radius 1e300", holes(circle(radius="1e300")), ["hole", "radius"]),
    "hole-radius-tiny": ("a hole of radius 1e-12", holes(circle(radius="1e-12")), ["hole", "radius"]),
    "hole-radius-inf": ("a hole of radius inf", holes(circle(radius="inf")), ["hole", "radius"]),
    "hole-centre-nan": ("a hole centred at (nan, 0.5)", holes(circle(centre="[nan, 0.5]")), ["centre"]),
    "hole-centre-three": ("a hole centre with 3 coordinates", holes(circle(centre="[0.5, 0.5, 0.0]")), ["centre"]),
    "hole-no-label": ("a hole circle without a label", holes(circle(label=None)), ["label"]),
    "hole-label-list": ('a hole circle with label = ["a", "b"]', holes(circle(label='["a", "b"]')), ["label"]),
    "hole-center-spelling": ("a hole with center instead of centre", holes(
        {"center": "[0.5, 0.5]", "radius": "0.1", "label": '"traction"'}), ["center"]),
    "hole-circle-and-loop": ("a hole with centre and vertices", holes(
        circle(vertices="[[0.4, 0.4], [0.6, 0.4], [0.5, 0.6]]")), ["hole"]),
    "hole-no-condition": ('a hole labelled "hole" (no boundary condition)', holes(circle(label='"hole"')),
                          ["hole"]),
    "hole-not-array": ("hole = a table, not an array of tables", {"geometry.hole": "{ centre = [0.5, 0.5] }"},
                       ["hole"]),
    "hole-loop-no-labels": ("a hole loop without labels", holes({"vertices": "[[0.4, 0.4], [0.6, 0.4], [0.5, 0.6]]"}),
                            ["labels"]),
    "holes-overlapping": ("two overlapping holes", holes(
        circle(centre="[0.5, 0.5]", radius="0.2"), circle(centre="[0.6, 0.5]", radius="0.2")),
        ["hole", "holes", "Netgen"]),
    "hole-touching-the-side": ("a hole touching the bottom side", holes(circle(centre="[0.5, 0.25]", radius="0.2")),
                               ["hole", "holes", "Netgen"]),
    # arcs
    "arcs-key-word": ("arcs = { bottom = [0.5, 0.0] }", arcs("{ bottom = [0.5, 0.0] }"), ["arcs"]),
    "arcs-key-negative": ('arcs = { "-1" = [0.5, 0.0] }', arcs('{ "-1" = [0.5, 0.0] }'), ["arcs"]),
    "arcs-key-out-of-range": ("arcs = { 9 = [0.5, 0.0] }", arcs("{ 9 = [0.5, 0.0] }"), ["arcs"]),
    "arcs-key-huge": ("arcs = { 99999999999999999999 = [0.5, 0.0] }", arcs("{ 99999999999999999999 = [0.5, 0.0] }"),
                      ["arcs"]),
    "arcs-list": ("arcs = [[0, 0.5, 0.0]]", arcs("[[0, 0.5, 0.0]]"), ["arcs"]),
    "arcs-point-nan": ("an arc through (nan, 0.0)", arcs("{ 0 = [nan, 0.0] }"), ["arcs"]),
    "arcs-point-string": ('an arc through "down"', arcs('{ 0 = "down" }'), ["arcs"]),
    "arcs-point-inf": ("an arc through (0.5, -inf)", arcs("{ 0 = [0.5, -inf] }"), ["arcs"]),
    "arcs-collinear": ("an arc through a point of its chord", arcs("{ 0 = [0.5, 0.05] }"), ["arc", "line"]),
    "arcs-nearly-flat": ("an arc 1e-13 off its chord", arcs("{ 0 = [0.5, 0.0500000000001] }"), ["arc", "line"]),
    "arcs-through-an-end": ("an arc through its own end point", arcs("{ 0 = [1.0, 0.05] }"), ["arc", "line"]),
    "arcs-crossing": ("an arc that crosses the loop", arcs("{ 1 = [0.1, 0.55] }"), ["loop", "crosses"]),
    "arcs-long-way": ("an arc the long way round (a clockwise loop)", arcs("{ 0 = [0.5, 1.5] }"),
                      ["counter-clockwise", "geometry"]),
    # boundaries
    "symmetry-number": ("symmetry = 5", {"boundaries.symmetry": "5"}, ["symmetry"]),
    "symmetry-empty-name": ('symmetry = ""', {"boundaries.symmetry": '""'}, ["symmetry"]),
    "symmetry-list-number": ('symmetry = ["axis", 1]', {"boundaries.symmetry": '["axis", 1]'}, ["symmetry"]),
    "symmetry-also-traction": ('symmetry = "traction" (also the traction side)', {"boundaries.symmetry": '"traction"'},
                               ["symmetry", "traction"]),
    "contact-empty-list": ("contact = []", {"boundaries.contact": "[]"}, ["contact"]),
    "dirichlet-absent-names": ('dirichlet = ["clamped"], traction the rest', {
        "boundaries.dirichlet": '["clamped"]', "boundaries.traction": '["traction", "dirichlet"]'}, ["dirichlet"]),
    "traction-table": ("traction = { a = 1 }", {"boundaries.traction": "{ a = 1 }"}, ["traction"]),
    "boundaries-unknown-key": ('[boundaries] symetry = "traction"', {"boundaries.symetry": '"traction"'},
                               ["symetry"]),
    # data per region and per side
    "E-table-unknown-region": ("E = { steel = 2000.0 }", {"material.E": "{ steel = 2000.0 }"}, ["E"]),
    "E-table-empty": ("E = {}", {"material.E": "{}"}, ["E"]),
    "E-table-nan": ("E = { omega = nan }", {"material.E": "{ omega = nan }"}, ["E"]),
    "E-table-bool": ("E = { omega = true }", {"material.E": "{ omega = true }"}, ["E"]),
    "E-table-nested": ("E = { omega = { a = 1 } }", {"material.E": "{ omega = { a = 1 } }"}, ["E"]),
    "E-table-expression": ('E = { omega = "2000 +" }', {"material.E": '{ omega = "2000 +" }'}, ["E"]),
    "E-table-negative-somewhere": ('E = { omega = "2000*(0.5 - x)" } (found on the mesh)',
                                   {"material.E": '{ omega = "2000*(0.5 - x)" }'}, ["E"]),
    "E-table-of-two-regions-one-missing": ("two regions, E for one", {
        **two_regions(), "material.E": "{ lower = 2000.0 }"}, ["E"]),
    "nu-table-0.7": ("nu = { omega = 0.7 }", {"material.nu": "{ omega = 0.7 }"}, ["nu"]),
    "f-table-short": ("f = { omega = [1.0] }", {"loads.f": "{ omega = [1.0] }"}, ["f"]),
    "f-table-unknown": ("f = { steel = [0.0, 1.0] }", {"loads.f": "{ steel = [0.0, 1.0] }"}, ["f"]),
    "g-table-string": ('g = { traction = "abc" }', {"loads.g": '{ traction = "abc" }'}, ["g"]),
    "g-table-unknown-side": ("g = { contact = [1.0, 0.0] }", {"loads.g": "{ contact = [1.0, 0.0] }"}, ["g"]),
    "g-table-overflow": ('g = { traction = ["exp(1000*x)", 0.0] } (found on the mesh)',
                         {"loads.g": '{ traction = ["exp(1000*x)", 0.0] }'}, ["g"]),
    "u_D-short": ("u_D = [0.01]", {"loads.u_D": "[0.01]"}, ["u_D"]),
    "u_D-nan": ("u_D = [nan, 0.0]", {"loads.u_D": "[nan, 0.0]"}, ["u_D"]),
    "u_D-bool": ("u_D = [true, 0.0]", {"loads.u_D": "[true, 0.0]"}, ["u_D"]),
    "u_D-string": ('u_D = "down"', {"loads.u_D": '"down"'}, ["u_D"]),
    "u_D-huge-int": ("u_D = [1 followed by 400 zeros, 0.0]", {"loads.u_D": f"[{HUGE_INT}, 0.0]"}, ["u_D"]),
    "u_D-table-unknown": ("u_D = { traction = [0.0, 0.01] }", {"loads.u_D": "{ traction = [0.0, 0.01] }"},
                          ["u_D"]),
    "u_D-table-inf": ("u_D = { dirichlet = [inf, 0.0] }", {"loads.u_D": "{ dirichlet = [inf, 0.0] }"}, ["u_D"]),
    "u_D-expression-inf": ('u_D = ["1/(x - 1)", 0.0] (infinite on the Dirichlet side, found on the mesh)',
                           {"loads.u_D": '["1/(x - 1)", 0.0]'}, ["u_D"]),
    "c_n-table-empty": ("c_n = {}", {"contact.c_n": "{}"}, ["c_n"]),
    "c_n-table-negative": ("c_n = { contact = -1.0 }", {"contact.c_n": "{ contact = -1.0 }"}, ["c_n"]),
    "g_a-table-nan": ("g_a = { contact = nan }", {"contact.g_a": "{ contact = nan }"}, ["g_a"]),
    "g_a-table-unknown": ("g_a = { top = 0.0 }", {"contact.g_a": "{ top = 0.0 }"}, ["g_a"]),
    "c_tau-table-negative": ("c_tau = { contact = -1.0 }", {"contact.c_tau": "{ contact = -1.0 }"}, ["c_tau"]),
    "c_tau-table-negative-somewhere": ('c_tau = { contact = "if(x > 0.5, -1, 1)" } (found on the mesh)',
                                       {"contact.c_tau": '{ contact = "if(x > 0.5, -1, 1)" }'}, ["c_tau"]),
    "m_n-table-below-1": ("m_n = { contact = 0.5 }", {"contact.m_n": "{ contact = 0.5 }"}, ["m_n"]),
    "m_n-table-expression": ('m_n = { contact = "1 + x" }', {"contact.m_n": '{ contact = "1 + x" }'}, ["m_n"]),
    "m_t-table-negative": ("m_t = { contact = -1.0 }", {"contact.m_t": "{ contact = -1.0 }"}, ["m_t"]),
    "m_t-table-unknown-side": ("m_t = { top = 0.0 }", {"contact.m_t": "{ top = 0.0 }"}, ["m_t"]),
}
# the expression functions step, min, max, if: bad uses in g_a (slug: expression)
SCHEMA_EXPRESSIONS = {
    "if-two-arguments": "if(x > 0.5, 0.05)", "if-four-arguments": "if(x > 0.5, 1, 2, 3)",
    "if-no-comparison": "if(x, 0.05, 0)", "if-keyword": "if(x > 0.5, a=1, b=2)", "if-starred": "if(*x)",
    "if-chained": "if(0.2 < x < 0.5, 0.05, 0)", "if-equality": "if(x == 0.5, 0.05, 0)",
    "if-not-equal": "if(x != 0.5, 0.05, 0)", "if-and": "if(x > 0.2 and x < 0.5, 0.05, 0)",
    "if-or": "if(x > 0.2 or y > 1, 0.05, 0)", "if-not": "if(not x > 0.5, 0.05, 0)",
    "if-internal-name": "if_(x > 0.5, 0.05, 0)", "if-python-conditional": "0.05 if x > 0.5 else 0",
    "if-no-call": "if", "comparison-outside-if": "0.05*(x > 0.5)", "if-branch-div-zero": "if(x > 2, 1/0, 0.05)",
    "if-branch-inf-on-domain": "if(x > 0.5, 1/(x - x), 0.05)", "if-branch-nan-on-domain": "if(x < 0.5, 0.05, "
                                                                                          "sqrt(0.7 - x))",
    "if-nested-too-long": "if(x > 0.5, " * 100 + "0" + ", 0)" * 100,
    "min-one-argument": "min(x)", "min-three-arguments": "min(x, y, 0)", "max-keyword": "max(a=x, b=y)",
    "max-no-argument": "max()", "step-two-arguments": "step(x, y)", "step-no-argument": "step()",
    "step-string": "step('x')", "min-of-a-list": "min([x, y])",
}


def schema_cases():
    """The problem-file schema beyond one polygon (regions, holes, arcs, symmetry, data per region and side, u_D,
    the expression functions): each bad file through the command line and through load_problem + solve."""
    snippet = 'q = ndf.load_problem("case.toml")\nndf.solve(q, ndf.netgen_mesh(q, 0.5))'
    items = [(slug, description, changes, expect) for slug, (description, changes, expect) in SCHEMA_CASES.items()]
    items += [(f"expr-{slug}", f"g_a = {text!r}", {"contact.g_a": json.dumps(text)}, ["g_a"])
              for slug, text in SCHEMA_EXPRESSIONS.items()]
    cases = []
    for slug, description, changes, expect in items:
        text = toml(changes)
        cases.append(cli_toml(f"schema-{slug}", f"problem file: {description}", text, expect=expect,
                              mesh=("--maxh", "0.5")))
        cases.append(api(f"schema-{slug}", f"load_problem + solve: {description}", snippet,
                         files={"case.toml": text}, expect=expect))
    # the same objects made in Python
    square = "ngs_square = Loop([(0, 0.05), (1, 0.05), (1, 1.05), (0, 1.05)], ['contact', 'dirichlet', " \
             "'traction', 'traction'])\nfrom ngdgfric.domain import Domain\n"
    python = {  # slug: (call, expect)
        "loop-arc-side-9": ("Loop([(0, 0), (1, 0), (0, 1)], ['a', 'b', 'c'], arcs={9: (0.5, -0.5)})", ["arcs"]),
        "loop-arc-side-bool": ("Loop([(0, 0), (1, 0), (0, 1)], ['a', 'b', 'c'], arcs={True: (0.5, -0.5)})",
                               ["arcs"]),
        "loop-arc-point-nan": ("Loop([(0, 0), (1, 0), (0, 1)], ['a', 'b', 'c'], arcs={0: (nan, -0.5)})", ["arcs"]),
        "loop-labels-string": ("Loop([(0, 0), (1, 0), (0, 1)], 'abc')", ["labels"]),
        "circle-radius-negative": ("Loop.circle((0, 0), -1.0, 'a')", ["radius"]),
        "circle-radius-nan": ("Loop.circle((0, 0), nan, 'a')", ["radius"]),
        "circle-centre-inf": ("Loop.circle((inf, 0), 1.0, 'a')", ["centre"]),
        "domain-region-name": ("Domain({'steel plate': ngs_square})", ["region"]),
        "domain-hole-outside": ("Domain({'omega': ngs_square}, [Loop.circle((5, 5), 0.1, 'traction')])", ["hole"]),
        "domain-hole-not-loop": ("Domain({'omega': ngs_square}, [((0, 0), 1.0)])", ["holes"]),
        "problem-E-unknown-region": ("dataclasses.replace(p, E={'steel': 1.0})", ["E"]),
        "problem-E-region-missing": ("dataclasses.replace(p, E={})", ["E"]),
        "problem-g-unknown-side": ("dataclasses.replace(p, g={'contact': (1.0, 0.0)})", ["g"]),
        "problem-u_D-nan": ("dataclasses.replace(p, u_D=(nan, 0.0))", ["u_D"]),
        "problem-u_D-three": ("dataclasses.replace(p, u_D=(0.0, 0.0, 1.0))", ["u_D"]),
        "problem-u_D-table-inf": ("dataclasses.replace(p, u_D={'dirichlet': (0.0, inf)})", ["u_D"]),
        "problem-u_D-cf-inf": ("solve(dataclasses.replace(p, u_D=(1 / (x - 1), 0.0)))", ["u_D"]),
        "problem-c_n-table-negative": ("dataclasses.replace(p, c_n={'contact': -1.0})", ["c_n"]),
        "problem-m_n-table-below-1": ("dataclasses.replace(p, m_n={'contact': 0.5})", ["m_n"]),
        "problem-symmetry-number": ("dataclasses.replace(p, symmetry=5)", ["symmetry"]),
        "problem-symmetry-contact": ("dataclasses.replace(p, symmetry='contact')", ["symmetry", "contact"]),
        "problem-contact-empty": ("dataclasses.replace(p, contact=[])", ["contact"]),
    }
    for slug, (call, expect) in python.items():
        cases.append(api(f"schema-{slug}", call, call, setup="from ngdgfric.domain import Loop\n" + square,
                         expect=expect))
    for slug, text in SCHEMA_EXPRESSIONS.items():
        if slug.endswith("-on-domain"):  # valid expressions, bad only where they are evaluated
            continue
        cases.append(api(f"schema-parse-{slug}", f"parse_expression({text[:60]!r})",
                         f"ndf.problem_file.parse_expression({text!r})"))
    return cases


def all_cases():
    return data_cases() + function_cases() + expression_cases() + geometry_cases() + mesh_cases() \
        + reference_cases() + file_cases() + argument_cases() + output_cases() + schema_cases()


CASES = all_cases()
QUICK = "-schema-"  # --quick: the cases of schema_cases()

# --------------------------------------------------------------------------------------- running

# caps the address space, then becomes the real command: python -c LIMIT BYTES ARGS... runs python ARGS...
LIMIT = ("import os, resource, sys\n"
         "n = int(sys.argv[1]); soft, hard = resource.getrlimit(resource.RLIMIT_AS)\n"
         "n = n if hard == resource.RLIM_INFINITY else min(n, hard)\n"
         "resource.setrlimit(resource.RLIMIT_AS, (n, hard))\n"
         "os.execv(sys.executable, [sys.executable, *sys.argv[2:]])")


def environment():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    env.update(PYTHONIOENCODING="utf-8:backslashreplace", MPLBACKEND="Agg", OMP_NUM_THREADS="1",
               MKL_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", NGDGFRIC_BLAS_THREADS="1")
    return env


ENV = environment()


@dataclass
class Outcome:
    returncode: int | None  # None: killed at the timeout
    stdout: str
    stderr: str
    seconds: float


def run_process(args, cwd, timeout, memory_bytes=0):
    """Run ``python args...`` in its own session; at the timeout kill its whole process group.

    (subprocess.run kills only the child at a timeout; Popen + os.killpg kill what it started too.)
    """
    argv = [sys.executable, "-c", LIMIT, str(int(memory_bytes)), *args] if memory_bytes else [sys.executable, *args]
    start = time.perf_counter()
    process = subprocess.Popen(argv, cwd=cwd, env=ENV, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, start_new_session=True)
    try:
        out, err = process.communicate(timeout=timeout)
        code = process.returncode
    except subprocess.TimeoutExpired:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        out, err = process.communicate()
        code = None
    seconds = time.perf_counter() - start
    return Outcome(code, out.decode("utf-8", "backslashreplace"), err.decode("utf-8", "backslashreplace"), seconds)


def api_program(case):
    """The Python program of an API case (see the module docstring)."""
    return "\n".join([
        "import sys, traceback",
        "try:",
        textwrap.indent(PREAMBLE + case.setup, "    "),
        "except BaseException:",
        "    traceback.print_exc()",
        "    print('SETUP-FAILED')",
        "    sys.exit(4)",
        "try:",
        textwrap.indent(case.snippet, "    "),
        "except (ValueError, FileNotFoundError) as exc:",
        "    print('NAMED-ERROR ' + type(exc).__name__ + ': ' + ' '.join(str(exc).split()))",
        "    sys.exit(3)",
        "print('SILENT')",
        "",
    ])


def case_args(case):
    """Arguments of python for the case."""
    return ["-c", api_program(case)] if case.interface == "api" else ["-m", "ngdgfric", *case.argv]


def make_files(folder, files):
    for name, contents in files.items():
        path = Path(folder) / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if contents == DIR:
            path.mkdir()
        elif contents == FIFO:
            os.mkfifo(path)
        elif isinstance(contents, tuple) and contents[0] == "symlink":
            os.symlink(contents[1], path)
        elif isinstance(contents, bytes):
            path.write_bytes(contents)
        else:
            path.write_text(contents)


def snapshot(folder):
    """{relative path: bytes} of the files under folder/out."""
    root = Path(folder) / "out"
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()} \
        if root.is_dir() else {}


def names_datum(message, expect):
    """True if the message contains one of the expected words (case insensitive, not inside a longer word)."""
    if not expect:
        return True
    for word in expect:
        pattern = re.escape(word)
        if re.match(r"\w", word[0]):
            pattern = r"(?<![\w])" + pattern
        if re.match(r"\w", word[-1]):
            pattern += r"(?![\w])"
        if re.search(pattern, message, re.IGNORECASE):
            return True
    return False


def _first(text):
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[0] if lines else ""


def _last(text):
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else ""


def _marker(stdout, prefix):
    found = [line for line in stdout.splitlines() if line.startswith(prefix)]
    return found[-1][len(prefix):].strip() if found else None


def signal_name(code):
    try:
        return signal.Signals(-code).name
    except ValueError:
        return f"signal {-code}"


def classify(case, outcome, timeout):
    """(verdict, what happened) of a finished case."""
    code, out, err = outcome.returncode, outcome.stdout, outcome.stderr
    if code is None:
        return HANG, f"no exit within {timeout:g} s: process group killed; last output: {_last(err) or _last(out)!r}"
    if code < 0:
        return SIGNAL, f"{signal_name(code)} (return code {code}); stderr: {_first(err)!r}"
    if case.interface == "api":
        named = _marker(out, "NAMED-ERROR ")
        if code == 3 and named is not None:
            kind, _, message = named.partition(": ")
            verdict = NAMED if message.strip() and names_datum(message, case.expect) else UNNAMED
            return verdict, f"exit 3: {named}"
        if code == 0 and _marker(out, "SILENT") is not None:
            return SILENT, "exit 0: returned normally"
        if code == 4 and _marker(out, "SETUP-FAILED") is not None:
            return OTHER, f"exit 4: setup of the case failed: {_last(err)}"
        if code == 1 and "Traceback" in err:
            return WRONG_TYPE, f"exit 1: {_last(err)}"
        return OTHER, f"exit {code}: {_last(err) or _last(out)}"
    if code == 0:
        return SILENT, f"exit 0: {_last(out)}"
    if "Traceback" in err:
        return TRACEBACK, f"exit {code}: {_last(err)}"
    lines = [line for line in err.splitlines() if line.strip()]
    errors = [line.strip() for line in lines if line.startswith("ngdgfric: error: ")]
    shown = errors[-1] if errors else _first(err)
    if code == 2:
        if len(lines) == 1 and lines[0].startswith("ngdgfric: error: "):
            message = lines[0][len("ngdgfric: error: "):]
            verdict = NAMED if message.strip() and names_datum(message, case.expect) else UNNAMED
            return verdict, f"exit 2: {lines[0]}"
        return OTHER, f"exit 2 with {len(lines)} stderr lines: {shown!r}"
    if code == 1:
        return EXIT_1, f"exit 1: {shown}"
    return OTHER, f"exit {code}: {shown}" + (f" ({len(lines)} stderr lines)" if len(lines) > 1 else "")


@dataclass
class Result:
    case: Case
    verdict: str
    happened: str
    seconds: float


def run_case(case, timeout=30.0, memory_gb=6.0):
    """Run one case in a fresh temporary folder; its Result."""
    memory = memory_gb * 2**30
    with tempfile.TemporaryDirectory(prefix=f"fuzz-{case.id[:40]}-", ignore_cleanup_errors=True) as folder:
        make_files(folder, case.files)
        for command in case.commands:  # untimed setup of a CLI case
            done = run_process(["-m", "ngdgfric", *command], folder, max(timeout, 120), memory)
            if done.returncode != 0:
                return Result(case, OTHER, f"setup command {' '.join(command)} failed: exit {done.returncode}, "
                                           f"{_last(done.stderr)!r}", 0.0)
        before = snapshot(folder)
        outcome = run_process(case_args(case), folder, timeout, memory)
        verdict, happened = classify(case, outcome, timeout)
        if verdict == NAMED and case.check == "quiet" and outcome.stdout.strip():
            verdict = LATE
            happened += f" (after printing {_first(outcome.stdout)!r})"
        if case.check == "unchanged":
            after = snapshot(folder)
            changed = sorted(name for name in before if after.get(name) != before[name])
            if changed:
                happened += f"; changed or removed: {', '.join(changed)}"
                if verdict == NAMED:
                    verdict = CHANGED
            elif not before:
                happened += "; the setup run wrote nothing to out/"
    return Result(case, verdict, f"{happened}; {outcome.seconds:.1f} s", outcome.seconds)


# -------------------------------------------------------------------------------------- reporting

def _cell(text, limit=300):
    text = " ".join(str(text).split())
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return text.replace("|", "\\|")


def _code(text, limit=160):
    text = " ".join(text.split())
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return "`" + text.replace("`", "'").replace("|", "\\|") + "`"


def shown_input(case):
    if case.interface == "cli":
        command = "ngdgfric " + " ".join(shlex.quote(a) for a in case.argv)
        return f"{_cell(case.description)}<br>{_code(command)}"
    return f"{_cell(case.description)}<br>{_code(case.snippet.replace(chr(10), '; '))}"


def report(results, args, seconds):
    """The Markdown of results/fuzz.md."""
    counts = {verdict: sum(r.verdict == verdict for r in results) for verdict in VERDICTS}
    api_count = sum(r.case.interface == "api" for r in results)
    lines = [
        "# Fuzzing ngdgfric with bad input",
        "",
        "Regenerate with `python scripts/fuzz.py` (scripts/fuzz.py; its docstring says what is checked).",
        "",
        f"{len(results)} cases ({api_count} API, {len(results) - api_count} CLI; "
        f"{sum(r.case.issue for r in results)} from the issue), each in its own process: timeout {args.timeout:g} s, "
        + (f"address space capped at {args.memory:g} GB" if args.memory else "address space not capped")
        + f", {args.workers} in parallel; {seconds:.0f} s in all.",
    ]
    if args.quick:
        lines.append(f"Quick run: only the cases of the problem-file schema (ids containing {QUICK!r}).")
    if args.only:
        lines.append(f"Only the cases whose id contains {' or '.join(map(repr, args.only))}.")
    lines += [
        "",
        "| verdict | cases |",
        "|---|---|",
        f"| signals | {counts[SIGNAL]} |",
        f"| hangs | {counts[HANG]} |",
        f"| silent answers | {counts[SILENT]} |",
        f"| CLI tracebacks | {counts[TRACEBACK]} |",
        f"| API: wrong exception type | {counts[WRONG_TYPE]} |",
        f"| unnamed errors (message does not name the datum) | {counts[UNNAMED]} |",
        f"| CLI: {EXIT_1} | {counts[EXIT_1]} |",
        f"| CLI: {LATE} | {counts[LATE]} |",
        f"| CLI: {CHANGED} | {counts[CHANGED]} |",
        f"| other | {counts[OTHER]} |",
        f"| **named errors** | **{counts[NAMED]}** |",
        "",
    ]
    failing = [r.case.id for r in results if r.verdict != NAMED]
    lines.append(f"Not a named error ({len(failing)}): " + (", ".join(f"`{i}`" for i in failing) or "none") + ".")
    lines += [
        "",
        "Verdicts.  API (`python -c SNIPPET`): *named error*: ValueError (FileNotFoundError for a missing file) "
        "whose message is non-empty and contains one of the expected words; *unnamed error*: such an error "
        "without them; *wrong exception type*: any other exception (traceback, exit 1); *silent answer*: the "
        "call returned.  CLI (`python -m ngdgfric`): *named error*: exit 2 and exactly one stderr line "
        "`ngdgfric: error: ...` naming the datum; *silent answer*: exit 0; *traceback*: `Traceback` on stderr; "
        f"*{EXIT_1}*; *{LATE}*: output printed before the error (the output folder must be checked first); "
        f"*{CHANGED}*: a rerun modified an earlier result.  Both: *signal*: killed by a signal; *hang*: "
        "no exit within the timeout (process group killed).",
        "",
        "| case | interface | issue case | input | what happened | verdict |",
        "|---|---|---|---|---|---|",
    ]
    for r in results:
        verdict = r.verdict if r.verdict == NAMED else f"**{r.verdict}**"
        lines.append(f"| `{r.case.id}` | {r.case.interface} | {'yes' if r.case.issue else ''} | {shown_input(r.case)} "
                     f"| {_cell(r.happened)} | {verdict} |")
    return "\n".join(lines) + "\n"


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=RESULTS, help="folder of fuzz.md (default: results/)")
    parser.add_argument("--workers", type=int, default=2, help="cases run in parallel (default: 2)")
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds before a case is a hang (default: 30)")
    parser.add_argument("--only", action="append", metavar="SUBSTRING",
                        help="run only the cases whose id contains SUBSTRING (repeatable: any of them)")
    parser.add_argument("--quick", action="store_true",
                        help=f"run only the cases of the problem-file schema (ids containing {QUICK!r}: regions, "
                             "holes, arcs, symmetry, data per part, u_D, the expression functions)")
    parser.add_argument("--memory", type=float, default=6.0,
                        help="cap of each case's address space in GB, 0 for none (default: 6)")
    args = parser.parse_args(argv)
    if args.workers < 1 or not args.timeout > 0 or args.memory < 0:
        parser.error("--workers must be >= 1, --timeout > 0 and --memory >= 0")
    return args


def selected(args):
    """The cases that ``args`` (--quick, --only) select, in the order of CASES."""
    return [case for case in CASES if (not args.quick or QUICK in case.id)
            and (not args.only or any(part in case.id for part in args.only))]


def main(argv=None):
    args = parse(argv)
    cases = selected(args)
    if not cases:
        print(f"fuzz: no case id contains {' or '.join(map(repr, args.only or [QUICK]))}", file=sys.stderr)
        return 2
    print(f"{len(cases)} cases, {args.workers} workers, timeout {args.timeout:g} s", flush=True)
    start = time.perf_counter()
    results = {}
    with ThreadPoolExecutor(max_workers=args.workers) as pool:
        futures = {pool.submit(run_case, case, args.timeout, args.memory): case for case in cases}
        for done, future in enumerate(as_completed(futures), 1):
            result = future.result()
            results[result.case.id] = result
            print(f"[{done:3d}/{len(cases)}] {result.case.id}: {result.verdict} ({result.seconds:.1f} s)", flush=True)
    seconds = time.perf_counter() - start
    ordered = [results[c.id] for c in cases]
    path = args.out / "fuzz.md"
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text(path, report(ordered, args, seconds))
    failing = sum(r.verdict != NAMED for r in ordered)
    print(f"{len(ordered) - failing} of {len(ordered)} named errors in {seconds:.0f} s; wrote {path}", flush=True)
    return 0 if failing == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
