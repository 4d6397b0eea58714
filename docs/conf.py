"""Sphinx configuration of the ngdgfric documentation site.

Build (from the repository root; warnings are errors):

    python -m sphinx -W --keep-going -b html docs docs/_build/html

MyST-NB reads the Markdown pages and the notebooks and executes every notebook and MyST
notebook of the gallery at build time, at smoke size (``NGDGFRIC_SMOKE=1``, as
``tests/test_notebooks.py`` runs them: seconds each, and large enough for every figure to show what it claims);
an execution error fails the build.  The API pages come
from the docstrings (autodoc).  The pages of ``results/`` are made here at build time: one stub per
``results/*.md`` that includes the file where it is (``docs/results/`` is generated, not kept in git).
"""

import dataclasses
import functools
import inspect
import os
import re
import sys
from pathlib import Path

from sphinx.errors import PycodeError

import ngdgfric

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"

project = "ngdgfric"
author = "the ngdgfric developers"
copyright = "2026, the ngdgfric developers"
release = ngdgfric.__version__
version = release

# napoleon: the docstrings are NumPy style (Parameters, Returns, Raises, Examples; numpydoc's validation in
# tests/test_docstrings.py); sphinx-mathjax-offline: MathJax 3 copied into the site, so that formulas render
# without network access
extensions = ["myst_nb", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.napoleon",
              "sphinx-mathjax-offline"]
# every cross-reference must resolve (CI builds with -n as well)
nitpicky = True
exclude_patterns = ["_build", "**.ipynb_checkpoints", "README.md"]
suppress_warnings = []

# MyST: $...$ and $$...$$ maths (the notebooks), aligned environments, headings as link targets
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3

# MyST-NB: execute every notebook, smoke-sized, each time the page is rebuilt; any error fails the build
os.environ["NGDGFRIC_SMOKE"] = "1"  # the kernels inherit the environment
# "force": a page is executed whenever Sphinx reads it (a fresh or -E build reads all); no cache that could
# keep outputs of an older ngdgfric, since a cache is keyed on the notebook's code alone
nb_execution_mode = "force"
if os.environ.get("NGDGFRIC_DOCS_EXECUTE") == "0":  # a quick build of the text alone (outputs left empty)
    nb_execution_mode = "off"
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_timeout = 600
nb_merge_streams = True

# autodoc: members in source order, signatures as written
autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_preserve_defaults = True  # defaults as written (``progress=log``), not their repr
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_param = False  # types shown as written, not as cross-references
napoleon_use_rtype = False
napoleon_use_ivar = True
# types of other packages: no inventory to link them to offline (intersphinx would fetch one at build time)
nitpick_ignore_regex = [("py:class", r"(numpy|ngsolve|netgen|matplotlib|pathlib|scipy)\..*")]
# no default options: a class's members are shown where its directive asks (``:members:``)

html_theme = "alabaster"
html_title = f"ngdgfric {release}"
html_static_path = ["_static"]
html_css_files = ["ngdgfric.css"]
# alabaster shows its narrow-screen layout below page_width: keep it at laptop widths
html_theme_options = {"description": "DG methods for 2D frictional contact on NGSolve", "page_width": "1100px",
                      "body_max_width": "none", "fixed_sidebar": True}


def plain_pipes(lines):
    """``lines`` (one docstring) with every ``|`` escaped outside inline literals, roles and literal blocks.

    The docstrings write norms and absolute values as in the paper, ``|u_tau|``, ``|||u - u_h|||_h``,
    which reStructuredText would read as substitution references; they use no substitutions.
    """
    out, literal_indent = [], None
    for line in lines:
        indent = len(line) - len(line.lstrip())
        if literal_indent is not None and (not line.strip() or indent > literal_indent):
            out.append(line)
            continue
        literal_indent = indent if line.rstrip().endswith("::") else None
        parts = line.split("``")
        out.append("``".join(part if k % 2 else _escape_outside_roles(part) for k, part in enumerate(parts)))
    return out


def _escape_outside_roles(text):
    """``text`` with ``|`` escaped except inside interpreted text (``:math:`|u|```)."""
    pieces = re.split(r"(`[^`]*`)", text)
    return "".join(piece if k % 2 else piece.replace("|", r"\|") for k, piece in enumerate(pieces))


def preformatted_blocks(lines):
    """``lines`` (one docstring) with every indented block that follows a blank line made a literal block.

    The docstrings indent tables and formulas (the method table of :mod:`ngdgfric.dg.methods`, the
    averages of :mod:`ngdgfric.dg.material`); reStructuredText would run them together as a quotation.
    A paragraph ending in ``:`` gets ``::``, any other a ``::`` line of its own.  Indented text directly
    under a line (definition lists), list items' own paragraphs and explicit markup stay as they are.
    """
    def indent(line):
        return len(line) - len(line.lstrip())

    out, k = [], 0
    while k < len(lines):
        line = lines[k]
        previous = next((j for j in range(len(out) - 1, -1, -1) if out[j].strip()), None)
        if line.strip() and out and not out[-1].strip() and previous is not None:
            head = out[previous]
            start = previous  # the first line of the paragraph that ends at ``head``
            while start > 0 and out[start - 1].strip() and indent(out[start - 1]) == indent(head):
                start -= 1
            first = out[start].lstrip()
            bullet = re.match(r"([-*+]|\d+[.)]|\(\d+\)) ", first)
            content = indent(out[start]) + (len(bullet.group(0)) if bullet else 0)
            if (indent(line) > content and not head.rstrip().endswith("::") and not first.startswith("..")
                    and not first.startswith(":")):
                if head.rstrip().endswith(":"):
                    out[previous] = head.rstrip() + ":"
                else:
                    out += [" " * indent(out[start]) + "::", ""]
                while k < len(lines) and (not lines[k].strip() or indent(lines[k]) > content):
                    out.append(lines[k])
                    k += 1
                continue
        out.append(line)
        k += 1
    return out


def _escape_pipes(app, what, name, obj, options, lines):
    lines[:] = plain_pipes(preformatted_blocks(lines))


def _public_data_docstring(app, what, name, obj, options, lines):
    """A top-level name of data (``ngdgfric.METHODS``) gets the docstring of its definition (the
    string after the assignment in the module that defines it), not its type's."""
    if what == "data" and name.count(".") == 1 and name.split(".")[1] in public_data_docs():
        lines[:] = [*public_data_docs()[name.split(".")[1]].splitlines(), ""]


@functools.cache
def public_data_docs():
    """{name: docstring} of the names of ``ngdgfric.__all__`` that are data (neither classes nor functions),
    read by Sphinx's source analyser from the module that defines each (already imported by ``ngdgfric``)."""
    from sphinx.pycode import ModuleAnalyzer

    wanted = {name: getattr(ngdgfric, name) for name in ngdgfric.__all__ if not callable(getattr(ngdgfric, name))}
    docs = {}
    for module in sorted(name for name in sys.modules if name == "ngdgfric" or name.startswith("ngdgfric.")):
        try:
            attr_docs = ModuleAnalyzer.for_module(module).find_attr_docs()
        except PycodeError:  # a module without source
            continue
        for (scope, attr), doc in attr_docs.items():
            if not scope and attr in wanted and getattr(sys.modules[module], attr, None) is wanted[attr]:
                docs.setdefault(attr, "\n".join(doc).strip())
    return docs


def user_form(value):
    """``value`` (a default) as a user writes it: ``8e9`` rather than ``8000000000.0``, ``10**6`` for a power of
    ten; None if it is no number."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    if isinstance(value, int):
        exponent = len(str(value)) - 1
        return f"10**{exponent}" if value >= 10**4 and value == 10**exponent else repr(value)
    if value.is_integer() and abs(value) >= 1e4:
        mantissa, exponent = f"{value:e}".split("e")
        return f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"
    return repr(value)


def _constant(obj, default):
    """The value of a default that ``autodoc_preserve_defaults`` replaced by its source text, where that text names
    a constant of the function's module (``MEMORY_BUDGET``); other defaults as they are."""
    text = getattr(default, "name", None)  # sphinx's DefaultValue keeps the text
    if isinstance(text, str) and text.isidentifier():
        return getattr(inspect.unwrap(obj), "__globals__", {}).get(text, default)
    return default


def _user_defaults(app, what, name, obj, options, signature, return_annotation):
    """Signatures with defaults as a user writes them: a module constant (``max_bytes=MEMORY_BUDGET``, as
    ``autodoc_preserve_defaults`` shows it) by its value (``max_bytes=8e9``), a dataclass field's factory
    (``<factory>``) by its call (``dict()``)."""
    if signature is None or not callable(obj):
        return None
    try:
        parameters = inspect.signature(obj).parameters
    except (TypeError, ValueError):
        return None
    fields = {field.name: field for field in dataclasses.fields(obj)} if dataclasses.is_dataclass(obj) else {}
    for parameter in parameters.values():
        shown = None
        if parameter.name in fields and fields[parameter.name].default_factory is not dataclasses.MISSING:
            shown = f"{fields[parameter.name].default_factory.__name__}()"
        elif parameter.default is not inspect.Parameter.empty:
            shown = user_form(_constant(obj, parameter.default))
        if shown is not None:
            pattern = rf"\b{parameter.name}(\s*:\s*[^=,()]+)?\s*=\s*(<factory>|[^,()\[\]\s'\"]+)(?=\s*[,)])"
            signature = re.sub(pattern, lambda match, shown=shown: match.group(0)[:match.start(2) - match.start(0)]
                               + shown, signature)
    return signature, return_annotation


NUMBER = re.compile(r"(?<![\w.])(?:[-+\u2212](?=\d))?(?:\d{1,3}(?:[ \u00a0\u2009\u202f]\d{3})+(?![\d.])"
                    r"|\d+(?:[.,]\d+)*(?:[eE][-+\u2212]?\d+)?(?:\^[-+\u2212]?\d+)?%?)")
"""A number as a reader reads it (sign, decimals, exponent, a power 2^-1, thousands in groups of three), as
tests/test_rendering.py looks for it."""


def _unbroken_numbers(app, doctree):
    """Every number in the text of a table cell put in a ``span.number``, which docs/_static/ngdgfric.css keeps on
    one line: in a narrow column a browser would break ``2.751e-02`` after its hyphen."""
    from docutils import nodes

    def in_text(node, entry):  # not in a literal, a formula, raw HTML or a span already
        while node.parent is not entry:
            node = node.parent
            if node is None or isinstance(node, (nodes.FixedTextElement, nodes.literal, nodes.math, nodes.raw,
                                                 nodes.inline)):
                return False
        return True

    for entry in doctree.findall(nodes.entry):
        for text in list(entry.findall(nodes.Text)):
            if not NUMBER.search(text) or not in_text(text, entry):
                continue
            pieces, end = [], 0
            for match in NUMBER.finditer(text):
                if match.start() > end:
                    pieces.append(nodes.Text(text[end:match.start()]))
                pieces.append(nodes.inline(match.group(0), match.group(0), classes=["number"]))
                end = match.end()
            if end < len(text):
                pieces.append(nodes.Text(text[end:]))
            text.parent.replace(text, pieces)


def setup(app):
    app.connect("doctree-read", _unbroken_numbers)
    app.connect("autodoc-process-signature", _user_defaults)
    app.connect("autodoc-process-docstring", _public_data_docstring)
    app.connect("autodoc-process-docstring", _escape_pipes)


def _write_if_changed(path, text):
    """Write ``text`` to ``path`` unless it already holds it (Sphinx then keeps its cached page)."""
    if not path.exists() or path.read_text() != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


RESULT_GROUPS = {
    "The paper's tables and figures": {
        "table_6_1": "Table 6.1: five methods on uniform meshes, Example 6.1",
        "table_6_2": "Table 6.2: the same for Example 6.2",
        "adaptivity_6_1": "Figures 6.1, 6.2: adaptive against uniform refinement, Example 6.1",
        "adaptivity_6_2": "Figures 6.3, 6.4: the same for Example 6.2",
        "table_investigation": "Which error measure the paper's tables show",
        "reference": "The hp reference solutions the true errors are measured against"},
    "Accuracy: where the methods work and where they fail": {
        "locking": r"Volumetric locking of every method and degree as $\nu \to 1/2$",
        "stability": "Where each method fails: penalties, meshes, materials",
        "effectivity": "The estimators against the true error",
        "hp": "hp-adaptivity against h and uniform refinement",
        "curved": "Rates on curved meshes",
        "hertz": "A Hertz contact against Hertz's theory",
        "two_cylinders": "Two elastic cylinders (two bodies, a contact pair, load control) against Hertz",
        "scenes": "Nine user scenes and a rubber pad",
        "mt": "A friction bound that depends on the penetration ($m_t > 0$)"},
    "Speed": {
        "time_to_accuracy": "Seconds to a true error: adapt against a plain conforming code and every DG method",
        "work_precision": "True error against run time, every method",
        "solver_benchmark": "The contact solve against a linear solve of the same system",
        "equilibration_cost": "The guaranteed bound against a linear solve of the same mesh",
        "long_contact_side": "Many contact points",
        "newton_levels": "Newton's iterations level by level in adaptive runs",
        "pair_benchmark": "The contact solve of a contact pair against a linear solve of the same system",
        "assembly_benchmark": "The cost of assembling each method",
        "linear_solvers": "Sparse direct solvers that install with pip"},
}
"""The results pages of the site's main path, by topic, with the line each shows in the index."""
VERIFICATION = {
    "fuzz": "Every bad input of the fuzz data through the API and the command line, each ending in a named error",
    "solver_robustness": "The default contact solver over 232 cases drawn over the data",
}
"""Test logs: on a page of their own, out of the main path."""


def _results_pages():
    """docs/results/<name>.md for every results/<name>.md (an include of it), docs/results/index.md (the pages by
    topic) and docs/results/verification.md (the test logs).  A results file in neither table fails the build."""
    folder = DOCS / "results"
    names = sorted(path.stem for path in (ROOT / "results").glob("*.md"))
    placed = {name for group in RESULT_GROUPS.values() for name in group} | set(VERIFICATION)
    if set(names) != placed:
        raise ValueError(f"docs/conf.py: results pages not placed in RESULT_GROUPS or VERIFICATION: "
                         f"{sorted(set(names) - placed)}; placed but missing: {sorted(placed - set(names))}")
    for stale in folder.glob("*.md"):
        if stale.stem not in names and stale.stem not in ("index", "verification"):
            stale.unlink()
    for name in names:
        _write_if_changed(folder / f"{name}.md", f"```{{include}} ../../results/{name}.md\n:relative-images:\n```\n")

    def listing(pages):  # Markdown links, whose text may hold $...$ mathematics (a {doc} role's may not)
        return "\n".join(f"- [{text}]({name}.md)" for name, text in pages.items())

    sections = "\n\n".join(f"## {title}\n\n{listing(pages)}" for title, pages in RESULT_GROUPS.items())
    main = "\n".join(name for pages in RESULT_GROUPS.values() for name in pages)
    _write_if_changed(folder / "index.md", f"""# Results

What we measured, and against what: each page is written by a script or a benchmark of the repository (the
command that regenerates it is on the page), and shown here as it is.  The test logs are under
{{doc}}`verification`.

{sections}

```{{toctree}}
:hidden:

{main}
verification
```
""")
    logs = "\n".join(VERIFICATION)
    _write_if_changed(folder / "verification.md", f"""# Verification logs

Logs of the test studies, case by case.

{listing(VERIFICATION)}

```{{toctree}}
:hidden:

{logs}
```
""")


_results_pages()
