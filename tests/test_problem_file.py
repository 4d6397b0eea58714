"""Property tests of problem files and expressions (ngdgfric.problem_file): whatever the input,
either a valid problem or a ValueError naming the file and key, never another exception."""

import math
import operator
import re
from pathlib import Path

import ngsolve as ngs
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import ngdgfric as ndf
from ngdgfric.domain import Domain
from ngdgfric.problem_file import FUNCTIONS, example_file, load_problem, parse_expression, problem_from_dict, tomllib

PROPERTY = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# ---------------------------------------------------------------- expressions

TOKENS = ["x", "y", "pi", "1", "0", "2.5", "1e308", "-", "+", "*", "/", "**", "(", ")", " ", ",", "sqrt", "log",
          "exp", "abs", "sin", "__import__", "'os'", ".", "[", "]", "lambda", ":", "nan", "inf", "1e400", "x.y",
          "min", "max", "step", "if", "if_", ">", "<=", "==", " and ", " if ", " else "]


@PROPERTY
@given(st.lists(st.sampled_from(TOKENS), max_size=25).map("".join))
def test_any_token_soup_is_an_expression_or_a_value_error(text):
    try:
        value = parse_expression(text)
    except ValueError:
        return
    assert isinstance(value, ngs.CoefficientFunction) or (isinstance(value, float) and math.isfinite(value))


def expressions():
    """(text, python function of x, y) of random valid expressions; Python's own arithmetic is the oracle."""
    leaves = st.sampled_from([("x", lambda x, y: x), ("y", lambda x, y: y), ("pi", lambda x, y: math.pi)]) | \
        st.floats(-10, 10, allow_nan=False).map(lambda c: (repr(c), lambda x, y, c=c: c))

    def combine(children):
        binary = st.tuples(children, st.sampled_from(["+", "-", "*"]), children).map(
            lambda t: (f"({t[0][0]} {t[1]} {t[2][0]})",
                       lambda x, y, a=t[0][1], op=t[1], b=t[2][1]: {"+": a(x, y) + b(x, y), "-": a(x, y) - b(x, y),
                                                                   "*": a(x, y) * b(x, y)}[op]))
        unary = st.tuples(st.sampled_from(["sin", "cos", "atan", "abs"]), children).map(
            lambda t: (f"{t[0]}({t[1][0]})", lambda x, y, f=FUNCTIONS[t[0]][0], a=t[1][1]: f(a(x, y))))
        square = children.map(lambda t: (f"({t[0]})**2", lambda x, y, a=t[1]: a(x, y) ** 2))
        extreme = st.tuples(st.sampled_from(["min", "max"]), children, children).map(
            lambda t: (f"{t[0]}({t[1][0]}, {t[2][0]})",
                       lambda x, y, f={"min": min, "max": max}[t[0]], a=t[1][1], b=t[2][1]: f(a(x, y), b(x, y))))
        step = children.map(lambda t: (f"step({t[0]})",
                                       lambda x, y, a=t[1]: 1.0 if _margin(a(x, y), 0.0) > 0 else 0.0))
        compare = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}
        condition = st.tuples(children, st.sampled_from(sorted(compare)), children, children, children).map(
            lambda t: (f"if({t[0][0]} {t[1]} {t[2][0]}, {t[3][0]}, {t[4][0]})",
                       lambda x, y, a=t[0][1], op=compare[t[1]], b=t[2][1], p=t[3][1], q=t[4][1]:
                       p(x, y) if op(_margin(a(x, y), b(x, y)), b(x, y)) else q(x, y)))
        return binary | unary | square | extreme | step | condition

    return st.recursive(leaves, combine, max_leaves=8)


MARGINS = []  # |a - b| of the comparisons the oracle made: near 0, round-off may pick the other branch


def _margin(a, b):
    MARGINS.append(abs(a - b))
    return a


UNIT_SQUARE = ndf.uniform_mesh(ndf.example_6_2(), 1)  # alive while its mesh points are used (else a segfault)


@PROPERTY
@given(expressions(), st.floats(0, 1), st.floats(0, 1))
def test_valid_expressions_evaluate_as_python_does(expression, px, py):
    text, oracle = expression
    value = parse_expression(text)
    point = UNIT_SQUARE(px, py)
    px, py = ngs.x(point), ngs.y(point)  # as NGSolve sees the point (after mapping to its element and back)
    MARGINS.clear()
    expected = float(oracle(px, py))
    assume(min(MARGINS, default=1.0) > 1e-9)
    found = value if isinstance(value, float) else value(point)
    assert found == pytest.approx(expected, rel=1e-12, abs=1e-12 * (1 + abs(expected)))


# ---------------------------------------------------------------- problem files

SHIPPED = example_file("6.1").read_text()


@PROPERTY
@given(data=st.data())
def test_mutated_problem_files_load_or_fail_naming_the_file(data, tmp_path_factory):
    """Random edits of the shipped file (delete, duplicate or replace a piece of text)."""
    text = SHIPPED
    for _ in range(data.draw(st.integers(1, 3))):
        start = data.draw(st.integers(0, len(text)))
        end = data.draw(st.integers(start, min(len(text), start + 12)))
        piece = data.draw(st.sampled_from(["", text[start:end] * 2, "nan", "inf", "-", "1e999", "]", "\"x\"", "0",
                                           "[", "=", "\n", "\xff", "9" * 400, "true", "-1"]))
        text = text[:start] + piece + text[end:]
    path = tmp_path_factory.mktemp("files") / "mutated.toml"
    path.write_text(text, encoding="utf-8", errors="surrogateescape")
    try:
        problem = load_problem(path)
    except ValueError as exc:
        assert str(exc).startswith(f"{path}: ")
        return
    assert isinstance(problem, ndf.ContactProblem)


def values():
    numbers = st.floats(allow_nan=True, allow_infinity=True) | st.integers(-10**400, 10**400) | st.booleans()
    scalars = numbers | st.text(max_size=20) | st.sampled_from(["x", "sqrt(x - 2)", "log(x)", "1/(x - x)", "nan"])
    return st.recursive(scalars, lambda children: st.lists(children, max_size=5) |
                        st.dictionaries(st.text(max_size=5), children, max_size=3), max_leaves=10)


def check_accepted_or_named(data):
    """The parsed problem file ``data`` (read as random.toml) gives a ContactProblem, or a ValueError whose
    message starts with the file's name and says more."""
    try:
        problem = problem_from_dict(data, source="random.toml")
    except ValueError as exc:
        assert re.match(r"random\.toml: \S", str(exc))
        return
    assert isinstance(problem, ndf.ContactProblem)


@PROPERTY
@given(st.sampled_from(["material", "geometry", "loads", "contact", "boundaries"]), st.text(max_size=8), values())
def test_any_value_for_any_key_is_accepted_or_named(section, key, value):
    data = tomllib.loads(SHIPPED)
    keys = sorted(data.get(section, {}))
    key = keys[len(key) % len(keys)] if keys and len(key) % 3 else key  # mostly existing keys, sometimes new ones
    data.setdefault(section, {})[key] = value
    check_accepted_or_named(data)


# ---------------------------------------------------------------- polygons

@PROPERTY
@given(st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4)), min_size=0, max_size=8))
def test_accepted_polygons_are_meshed_with_their_area(points):
    """A polygon is refused with a ValueError, or it is simple and Netgen meshes exactly its area."""
    labels = ("contact", "dirichlet") + ("traction",) * max(len(points) - 2, 0)
    try:
        polygon = ndf.Polygon(points, labels[:len(points)])
    except ValueError:
        return
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0.0, 0.0), g=(0.0, 0.0), c_n=1.0, m_n=1.0, g_a=0.0, c_tau=1.0,
                                 geometry=polygon)
    mesh = ndf.netgen_mesh(problem, 1.0)
    assert ngs.Integrate(ngs.CF(1), mesh) == pytest.approx(polygon.signed_area, rel=1e-12)


@pytest.mark.parametrize("text, x, y, value", [
    ("0.05 - 0.01*x", 0.3, 0.7, 0.05 - 0.003),
    ("sin(pi*x) * exp(-y**2)", 0.3, 0.7, math.sin(math.pi * 0.3) * math.exp(-0.49)),
    ("sqrt(x) + log(1 + y) - atan(x/y) + abs(x - y) + cos(y) + tan(x)", 0.3, 0.7,
     math.sqrt(0.3) + math.log(1.7) - math.atan(0.3 / 0.7) + 0.4 + math.cos(0.7) + math.tan(0.3)),
    ("-2**x", 0.5, 0.5, -math.sqrt(2)),
])
def test_expressions(text, x, y, value):
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.5))
    assert parse_expression(text)(mesh(x, y)) == pytest.approx(value, rel=1e-12)


@pytest.mark.parametrize("text", ["__import__('os')", "x.__class__", "open('f')", "lambda: 1", "x if y else 1",
                                  "z + 1", "'a'", "[x]", "1/0", "10**10**10", "(-8)**(1/3)", "log(-1)", "sin(x, y)",
                                  "x +", "True", "1e400"])
def test_bad_expressions(text):
    with pytest.raises(ValueError):
        parse_expression(text)


def test_constant_expressions_stay_numbers():
    assert parse_expression("2*pi/4") == pytest.approx(math.pi / 2)
    assert isinstance(parse_expression("sqrt(2)"), float)


def python_value(text, x, y):
    """The value of an expression as Python reads it, with step(t) = 1 for t > 0 else 0 and if(c, a, b)."""
    names = {"x": x, "y": y, "step": lambda t: float(t > 0), "min": min, "max": max,
             "if_": lambda c, a, b: a if c else b}
    return eval(re.sub(r"\bif\s*\(", "if_(", text), names)


@pytest.mark.parametrize("text", [
    "step(x - 0.5)", "min(x, y)", "min(x, 0.1)", "max(x, y)", "max(2, y)", "if(x > 0.5, -300, 0)", "if(x >= y, x, y)",
    "if(x < y, 1, 2)", "if(x <= 0.2, 1, 2)", "if (y > 0.5, if(x < 0.5, 1, 2), 3*x)", "min(y / max(1 - y, 0.05), 10)",
    "1 + step(x) * max(min(x, y), -1)"])
def test_expression_functions_on_coefficient_functions(text):
    """step, min, max and if on x, y give CoefficientFunctions with the values Python gives, on both sides of
    every branch."""
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.5))
    cf = parse_expression(text)
    assert isinstance(cf, ngs.CoefficientFunction)
    for x, y in [(0.7, 0.2), (0.3, 0.2), (0.3, 0.7), (0.8, 0.7), (0.1, 0.5), (0.1, 0.95), (0.45, 0.55)]:
        assert cf(mesh(x, y)) == pytest.approx(python_value(text, x, y), rel=1e-14, abs=1e-14), (x, y)


@pytest.mark.parametrize("text, value", [
    ("step(2)", 1.0), ("step(0)", 0.0), ("step(-1e-300)", 0.0), ("min(2, -3)", -3.0), ("max(2, -3)", 2.0),
    ("if(1 > 0, 2, 3)", 2.0), ("if(1 < 0, 2, 3)", 3.0), ("if(1 >= 1, 2, 3)", 2.0), ("if(1 <= 0.5, 2, 3)", 3.0),
    ("if(pi > 3, sqrt(4), log(1))", 2.0), ("max(min(5, 2*pi), -1)", 5.0), ("min(7, 2*pi)", 2 * math.pi),
])
def test_expression_functions_on_numbers_stay_numbers(text, value):
    found = parse_expression(text)
    assert isinstance(found, float) and found == pytest.approx(value, rel=1e-15)


def test_equality_in_a_condition_on_coefficient_functions():
    # x - x and 0*y are exactly 0 at every point: >= and <= hold, > and < do not, step(0) = 0
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.5))
    for text, value in (("if(x - x >= 0*y, 1, 2)", 1), ("if(x - x <= 0*y, 1, 2)", 1), ("if(x - x > 0*y, 1, 2)", 2),
                        ("if(x - x < 0*y, 1, 2)", 2), ("step(x - x)", 0)):
        assert parse_expression(text)(mesh(0.3, 0.6)) == value, text


@pytest.mark.parametrize("text, message", [
    ("min(x)", "min takes exactly 2 arguments"), ("max(x, y, 1)", "max takes exactly 2 arguments"),
    ("step()", "step takes exactly 1 argument"), ("if(x > 1, 2)", "if takes exactly 3 arguments"),
    ("if(x, 1, 2)", "must be a comparison"), ("if(0 < x < 1, 1, 2)", "one comparison per condition"),
    ("if(x == 1, 1, 2)", "only <, <=, > and >= compare"), ("if(x != 1, 1, 2)", "only <, <=, > and >= compare"),
    ("x > 1", "only allowed as the condition of if"), ("1 + (x < y)", "only allowed as the condition"),
    ("if(x > 1 or y > 1, 1, 2)", "'and' and 'or' are not allowed"), ("not x", "is not allowed"),
    ("min(a=1, b=2)", "min takes no keyword arguments"), ("max(*x)", "*arguments are not allowed"),
    ("if_(x > 1, 1, 2)", "unknown name 'if_'"), ("x if y > 1 else 2", "is not allowed"),
    ("if(x > 1, 1/0, 2)", "division by zero"), ("if(1 > 0, 1, log(-1))", "log(-1)"),
    ("clip(x, 0, 1)", "allowed: abs, atan, cos, exp, if, log, max, min, sin, sqrt, step, tan"),
    ("if(x > 1, 1, 2)(3)", "is not allowed"), ("step", "unknown name 'step'"),
])
def test_bad_uses_of_the_expression_functions(text, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        parse_expression(text)


# ---------------------------------------------------------------- the full schema

def docstring_example():
    """The first TOML example of the module docstring (so the documentation cannot rot)."""
    from ngdgfric import problem_file

    block = problem_file.__doc__.split("::\n\n", 1)[1]
    lines = []
    for line in block.splitlines():
        if line and not line.startswith("    "):
            break
        lines.append(line[4:])
    return "\n".join(lines)


def test_the_documented_example_loads_with_every_part():
    problem = problem_from_dict(tomllib.loads(docstring_example()), source="doc.toml")
    geometry = problem.geometry
    assert isinstance(geometry, Domain) and geometry.region_names == ("steel", "rubber")
    steel, rubber = dict(geometry.regions).values()
    assert steel.vertices == ((0.0, 0.0), (1.0, 0.0), (1.0, 0.5), (0.0, 0.5))
    assert steel.labels == ("contact", "right", "interface", "axis") and steel.arcs == ()
    assert rubber.arcs == ((2, (0.5, 1.1)),)
    (hole,) = geometry.holes
    assert hole.labels == ("hole",) * 4 and all(side.radius == pytest.approx(0.1) for side in hole.sides())
    assert set(geometry.side_names) == {"contact", "right", "axis", "top", "hole"}
    assert (problem.dirichlet, problem.traction, problem.contact, problem.symmetry) \
        == ("top", ("right", "hole"), "contact", ("axis",))
    assert problem.E["steel"] == 200.0 and problem.nu == 0.3
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.5))
    assert problem.E["rubber"](mesh(0.5, 0.2)) == pytest.approx(2.5)
    assert problem.f == {"steel": (0.0, -0.1), "rubber": (0.0, 0.0)}
    assert list(problem.g) == ["right"] and problem.g["right"][1] == 0.0
    assert problem.g["right"][0](mesh(1.0, 0.4)) == pytest.approx(-0.2)
    assert problem.u_D == (0.0, -0.01)
    assert (problem.c_n, problem.m_n, problem.c_tau, problem.m_t) == (1000.0, 1.0, {"contact": 2.0}, 0.0)
    assert [problem.g_a(mesh(x, 0.0)) for x in (0.25, 0.75)] == [0.0, 0.001]
    # and it is a problem the library solves: on the mesh of its own geometry, every datum per part resolved
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.25))
    assert ndf.kkt_residuals(sol)["equilibrium"] < 1e-9


def test_old_files_load_unchanged():
    for name, corners in (("6.1", ((0, 0.05), (1, 1.05))), ("6.2", ((0, 0), (1, 1)))):
        problem = load_problem(example_file(name))
        assert isinstance(problem.geometry, ndf.Polygon) and problem.geometry.is_rectangle
        assert problem.geometry.bounds == (*corners[0], *corners[1])
        assert (problem.dirichlet, problem.traction, problem.contact, problem.symmetry, problem.u_D) \
            == ("dirichlet", "traction", "contact", (), (0.0, 0.0))


ONE_REGION = """
[material]
E = {E}
nu = 0.3
[geometry]
vertices = [[-1.0, 1.0], [1.0, 1.0]]
labels = ["arc", "top"]
arcs = {{ 0 = [0.0, 0.0] }}
{more}
[boundaries]
dirichlet = "top"
contact = ["arc"]
traction = "inner"
[loads]
u_D = {u_D}
[contact]
c_n = {{ arc = 10.0 }}
m_n = 1.0
g_a = {{ arc = "y" }}
c_tau = {{ arc = 0.0 }}
"""


def test_one_region_in_geometry_with_an_arc_a_hole_and_data_per_part():
    text = ONE_REGION.format(E='{ omega = "1 + x**2" }', u_D='{ top = [0.0, -0.01] }', more="""
[[geometry.hole]]
vertices = [[-0.1, 0.5], [0.1, 0.5], [0.1, 0.7], [-0.1, 0.7]]
labels = ["inner", "inner", "inner", "inner"]
arcs = { 2 = [0.0, 0.75] }
""")
    problem = problem_from_dict(tomllib.loads(text), source="one.toml")
    geometry = problem.geometry
    assert isinstance(geometry, Domain) and geometry.region_names == ("omega",)
    (name, loop), = geometry.regions
    arc = loop.side(0)
    assert arc.centre == pytest.approx((0.0, 1.0)) and arc.radius == pytest.approx(1.0)
    assert geometry.holes[0].arcs == ((2, (0.0, 0.75)),)
    assert geometry.area == pytest.approx(math.pi / 2 - 0.04 - geometry.holes[0].side(2).segment_area())
    assert (problem.contact, problem.traction) == (("arc",), "inner")
    assert problem.u_D == {"top": (0.0, -0.01)} and problem.c_n == {"arc": 10.0} and problem.c_tau == {"arc": 0.0}
    assert set(problem.E) == {"omega"} and isinstance(problem.g_a["arc"], ngs.CoefficientFunction)


def test_circles_are_holes_and_inclusions():
    text = """
[material]
E = { matrix = 1.0, fibre = 10.0 }
nu = { matrix = 0.3, fibre = 0.2 }
[[geometry.region]]
name = "matrix"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
labels = ["contact", "side", "top", "side"]
[[geometry.region]]
name = "fibre"
centre = [0.5, 0.5]
radius = 0.2
label = "interface"
[[geometry.hole]]
centre = [1.5, 0.5]
radius = 0.25
label = "hole"
[boundaries]
dirichlet = "top"
traction = "hole"
symmetry = "side"
[contact]
c_n = 1.0
m_n = 1.0
g_a = 0.0
c_tau = 1.0
"""
    problem = problem_from_dict(tomllib.loads(text), source="circles.toml")
    geometry = problem.geometry
    assert geometry.region_names == ("matrix", "fibre") and len(geometry.holes) == 1
    assert geometry.area == pytest.approx(2 - math.pi * 0.25**2, rel=1e-12)
    assert set(geometry.side_names) == {"contact", "side", "top", "hole"}  # the fibre's circle is an interface
    assert problem.symmetry == ("side",) and problem.nu == {"matrix": 0.3, "fibre": 0.2}
    assert problem.traction == "hole" and problem.g == (0.0, 0.0)  # g defaults to zero


def test_boundaries_may_be_lists_and_a_region_may_be_left_unnamed():
    text = ONE_REGION.format(E="1.0", u_D="[0.0, 0.0]", more="").replace(
        "[geometry]\nvertices = [[-1.0, 1.0], [1.0, 1.0]]\nlabels = [\"arc\", \"top\"]\narcs",
        "[[geometry.region]]\nvertices = [[-1.0, 1.0], [1.0, 1.0]]\nlabels = [\"arc\", \"top\"]\narcs")
    problem = problem_from_dict(tomllib.loads(text), source="unnamed.toml")
    assert problem.geometry.region_names == ("omega",)
    assert problem_from_dict(tomllib.loads(text.replace('dirichlet = "top"', 'dirichlet = ["top"]')),
                             source="x").dirichlet == ("top",)


BAD_FILES = tomllib.loads((Path(__file__).resolve().parent / "data" / "bad_problem_files.toml").read_text())["case"]


@pytest.mark.parametrize("case", [case for case in BAD_FILES if "api" not in case], ids=lambda case: case["name"])
def test_bad_problem_files_are_refused_when_loaded_with_the_command_lines_message(case, tmp_path):
    """tests/data/bad_problem_files.toml (also run through the command line by tests/test_cli.py): the
    loader's message is the command line's."""
    text = example_file("6.1").read_text()
    assert case["old"] in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(case["old"], case["new"]))
    with pytest.raises(ValueError) as error:
        load_problem(path)
    assert str(error.value).startswith(f"{path}: ") and case["cli"] in str(error.value)


def test_every_key_of_the_schema_has_a_bad_file_case():
    from ngdgfric.problem_file import CIRCLE_KEYS, LOOP_KEYS, SCHEMA

    fragments = " ".join(case["cli"] for case in BAD_FILES)
    for section, keys in SCHEMA.items():
        for key in keys:
            assert f"{section}.{key}" in fragments, f"no bad problem file names {section}.{key}"
    for key in ("name", *LOOP_KEYS, *CIRCLE_KEYS):
        assert re.search(rf"geometry\.(region|hole)\[\d+\]\.{key}\b", fragments), f"no bad case of a loop's {key}"


def test_unknown_keys_are_named_everywhere():
    base = tomllib.loads(docstring_example())
    for path in (("material",), ("loads",), ("boundaries",), ("contact",), ("geometry",), ("geometry", "region", 1),
                 ("geometry", "hole", 0)):
        data = tomllib.loads(docstring_example())
        table = data
        for key in path:
            table = table[key]
        table["colour"] = "red"
        shown = ".".join(str(key) for key in path).replace(".1", "[1]").replace(".0", "[0]")
        with pytest.raises(ValueError, match=re.escape(f"x.toml: {shown}.colour: unknown key")):
            problem_from_dict(data, source="x.toml")
    assert problem_from_dict(base, source="x.toml").name == "Two layers on a foundation"


def loop_values(key):
    """Values for ``key`` of a region or hole table: mostly of the right shape (deep checks), sometimes anything."""
    numbers = st.floats(allow_nan=True, allow_infinity=True) | st.integers(-3, 3) | st.booleans() | \
        st.sampled_from([0.05, 0.1, 0.3, 1e-12, 1e300])
    coordinate = st.sampled_from([0.0, 1.0, 0.25, 0.5, 0.75, 1.1, -0.1, 0.45])
    point = st.lists(coordinate, min_size=2, max_size=2)
    names = st.sampled_from(["contact", "top", "right", "axis", "hole", "interface", "a-b", "", "steel"])
    anything = numbers | point | st.lists(point, max_size=4) | names | st.lists(names, max_size=5) | \
        st.dictionaries(st.sampled_from(["0", "1", "x", "-1", ""]), numbers | point, max_size=2) | \
        st.lists(numbers, max_size=3)
    shaped = {"name": names, "vertices": st.lists(point, min_size=2, max_size=6),
              "labels": st.lists(names, min_size=2, max_size=6),
              "arcs": st.dictionaries(st.sampled_from(["0", "1", "2", "3", "4"]), point, max_size=2),
              "centre": point, "radius": numbers, "label": names}.get(key, anything)
    return st.one_of(shaped, shaped, shaped, anything)


@pytest.mark.slow
@PROPERTY
@given(st.data())
def test_mutated_regions_and_holes_are_accepted_or_named(data):
    """The documented example with one to three keys of its regions and hole replaced or deleted."""
    problem = tomllib.loads(docstring_example())
    geometry = problem["geometry"]
    keys = {"region": ["name", "vertices", "labels", "arcs", "arcs", "vertices", "centre", "x"],
            "hole": ["centre", "radius", "label", "centre", "radius", "vertices", "name"]}
    for _ in range(data.draw(st.integers(1, 3))):
        part, k = data.draw(st.sampled_from([("region", 0), ("region", 1), ("hole", 0)]))
        table = geometry[part][k]
        key = data.draw(st.sampled_from(keys[part]))
        if key in table and data.draw(st.booleans()):
            del table[key]
        else:
            table[key] = data.draw(loop_values(key))
    check_accepted_or_named(problem)


def test_how_deep_an_expression_may_nest_does_not_depend_on_the_callers_stack():
    # 990 unary minus signs parse from the top of a stack; they used to fail (or let a RecursionError
    # escape) when the caller was a few hundred frames deep, as under pytest
    text = "-" * 990 + "x"

    def nested(depth):
        return nested(depth - 1) if depth else parse_expression(text)

    for depth in (0, 400, 800):
        assert nested(depth)(UNIT_SQUARE(0.25, 0.5)) == pytest.approx(0.25)


# ---------------------------------------------------------------- contact pairs

PAIRS = """
name = "two blocks"
[material]
E = 1.0
nu = 0.3
[[geometry.region]]
name = "lower"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
labels = ["bottom", "right1", "c1", "left1"]
[[geometry.region]]
name = "upper"
vertices = [[0.0, 1.0], [1.0, 1.0], [1.0, 1.5], [0.0, 1.5]]
labels = ["c2", "right2", "top", "left2"]
[boundaries]
dirichlet = ["top"]
symmetry = ["bottom", "left1", "left2"]
traction = ["right1", "right2"]
contact = []
[loads]
u_D = { top = [0.0, -0.01] }
[[contact.pair]]
side = "c2"
other = "c1"
c_n = 50.0
"""


def two_blocks(**pair):
    """The problem of PAIRS built in Python, its pair with ``pair`` changed."""
    lower = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "right1", "c1", "left1"])
    upper = ndf.Loop([(0, 1), (1, 1), (1, 1.5), (0, 1.5)], ["c2", "right2", "top", "left2"])
    return ndf.ContactProblem(
        E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
        geometry=Domain({"lower": lower, "upper": upper}), dirichlet=("top",), symmetry=("bottom", "left1", "left2"),
        traction=("right1", "right2"), contact=(), pairs=[ndf.ContactPair("c2", "c1", **{"c_n": 50.0, **pair})],
        u_D={"top": (0, -0.01)})


def test_contact_pairs_load_equal_to_the_problem_made_in_python_and_solve_the_same(tmp_path):
    path = tmp_path / "pairs.toml"
    path.write_text(PAIRS)
    loaded, made = load_problem(path), two_blocks()
    assert loaded == made and loaded.name == "two blocks"
    assert loaded.pairs == (ndf.ContactPair("c2", "c1", c_n=50.0),) and loaded.contact == ()
    solutions = [ndf.solve(problem, ndf.netgen_mesh(problem, {"lower": 1 / 3, "upper": 1 / 5}), method="sipg",
                           order=1) for problem in (made, loaded)]
    u, v = (sol.u.vec.FV().NumPy() for sol in solutions)
    assert len(u) == len(v) and abs(u).max() > 1e-3
    assert abs(u - v).max() <= 1e-12 * abs(u).max()


def test_every_key_of_a_contact_pair_is_read():
    data = tomllib.loads(PAIRS)
    data["contact"]["pair"][0].update(m_n=2, c_tau=0.3, m_t=1.0, g_a=-0.001, reach=0.05)
    data["contact"].update(c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0)  # the law may be given with contact = [] too
    expected = two_blocks(m_n=2.0, c_tau=0.3, m_t=1.0, g_a=-0.001, reach=0.05)
    assert problem_from_dict(data, source="pairs.toml") == expected


PAIR_ERRORS = [  # (changes of the pair table, None: delete; its error after "pairs.toml: ")
    ({"colour": "red"}, "contact.pair[0].colour: unknown key (allowed: side, other, c_n, m_n, c_tau, m_t, g_a, reach)"),
    ({"c_n": None}, "contact.pair[0].c_n: missing"),
    ({"other": None}, "contact.pair[0].other: missing"),
    ({"side": 3}, "contact.pair[0].side: must be a side name, got 3"),
    ({"other": ""}, "contact.pair[0].other: must be a side name, got ''"),
    ({"c_tau": "0.3*x"}, "contact.pair[0].c_tau: must be a number, got '0.3*x'"),
    ({"reach": True}, "contact.pair[0].reach: must be a number, got True"),
    ({"c_n": -1.0}, "contact.pair[0].c_n: must be >= 0, got -1.0"),
    ({"m_n": 0.5}, "contact.pair[0].m_n: must be >= 1, got 0.5"),
    ({"m_t": -1.0}, "contact.pair[0].m_t: must be >= 0, got -1.0"),
    ({"g_a": math.nan}, "contact.pair[0].g_a: must be a finite number, got nan"),
    ({"c_tau": math.inf}, "contact.pair[0].c_tau: must be a finite number, got inf"),
    ({"reach": 0.0}, "contact.pair[0].reach: must be > 0, got 0.0"),
    ({"reach": -1.0}, "contact.pair[0].reach: must be > 0, got -1.0"),
    ({"other": "c2"}, "contact.pair[0]: a contact pair needs two sides, got 'c2' twice"),
    ({"other": "nowhere"}, "contact.pair[0]: the geometry has no side 'nowhere'"),
    ({"other": "right1"}, "sides 'c1' and 'c2' of two bodies touch but are not a contact pair"),
]


@pytest.mark.parametrize("changes, message", PAIR_ERRORS, ids=[message.split(":")[0] + "-" + ",".join(changes)
                                                               for changes, message in PAIR_ERRORS])
def test_bad_contact_pairs_are_named_by_their_table(changes, message):
    data = tomllib.loads(PAIRS)
    pair = data["contact"]["pair"][0]
    for key, value in changes.items():
        if value is None:
            del pair[key]
        else:
            pair[key] = value
    with pytest.raises(ValueError) as error:
        problem_from_dict(data, source="pairs.toml")
    assert str(error.value).startswith(f"pairs.toml: {message}"), str(error.value)


def test_a_pair_within_one_body_is_named_by_its_table():
    data = tomllib.loads(PAIRS)  # two sides of one region
    data["boundaries"].update(traction=["right2"], symmetry=["bottom", "left2"])
    data["contact"]["pair"].insert(0, {"side": "left1", "other": "right1", "c_n": 1.0})
    with pytest.raises(ValueError, match=re.escape("pairs.toml: contact.pair[0]: sides 'left1' and 'right1' belong "
                                                   "to one body (regions 'lower'): a pair joins two bodies")):
        problem_from_dict(data, source="pairs.toml")
    data = tomllib.loads(PAIRS)  # two regions joined by an interface
    data["geometry"]["region"][0]["labels"][2] = data["geometry"]["region"][1]["labels"][0] = "interface"
    data["boundaries"]["traction"] = []
    data["contact"]["pair"] = [{"side": "right1", "other": "right2", "c_n": 1.0}]
    with pytest.raises(ValueError, match=re.escape("pairs.toml: contact.pair[0]: sides 'right1' and 'right2' belong "
                                                   "to one body (regions 'lower', 'upper')")):
        problem_from_dict(data, source="pairs.toml")


def test_a_pair_side_in_a_boundary_part_is_named():
    data = tomllib.loads(PAIRS)
    data["contact"]["pair"].append({"side": "right2", "other": "right1", "c_n": 1.0})
    with pytest.raises(ValueError, match=re.escape("pairs.toml: boundaries: side name 'right2' is in both traction "
                                                   "and pair")):
        problem_from_dict(data, source="pairs.toml")


def test_a_side_in_two_pairs_is_named_by_the_second_pair():
    data = tomllib.loads(PAIRS)
    data["contact"]["pair"].append({"side": "c1", "other": "right2", "c_n": 1.0})
    with pytest.raises(ValueError, match=re.escape("pairs.toml: contact.pair[1]: side 'c1' is in contact.pair[0] too")):
        problem_from_dict(data, source="pairs.toml")


@pytest.mark.parametrize("value, message", [
    (1.0, "contact.pair: must be a list of tables ([[contact.pair]]"),
    ([1.0], "contact.pair: must be a list of tables"),
    ({"side": "c2"}, "contact.pair: must be a list of tables"),
])
def test_contact_pairs_must_be_tables(value, message):
    data = tomllib.loads(PAIRS)
    data["contact"]["pair"] = value
    with pytest.raises(ValueError, match=re.escape(f"pairs.toml: {message}")):
        problem_from_dict(data, source="pairs.toml")


def test_the_contact_law_may_be_left_out_only_without_contact_sides():
    data = tomllib.loads(PAIRS)
    del data["contact"]["pair"]
    with pytest.raises(ValueError, match=re.escape("pairs.toml: sides 'c1' and 'c2' of two bodies touch but are not "
                                                   "a contact pair")):
        problem_from_dict(data, source="pairs.toml")  # no pairs: the blocks touch
    upper = data["geometry"]["region"][1]
    upper["vertices"] = [[x, y + 0.5] for x, y in upper["vertices"]]
    with pytest.raises(ValueError, match=re.escape("pairs.toml: boundaries.contact needs at least one side name")):
        problem_from_dict(data, source="pairs.toml")  # no pairs, blocks apart: an empty contact list is refused
    data = tomllib.loads(PAIRS)
    data["boundaries"]["contact"] = "c1"
    with pytest.raises(ValueError, match=re.escape("pairs.toml: contact.c_n: missing")):
        problem_from_dict(data, source="pairs.toml")
