"""Property tests of problem files and expressions (ngdgfric.problem_file): whatever the input,
either a valid problem or a ValueError naming the file and key, never another exception."""

import math
import re

import ngsolve as ngs
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ngdgfric as ndf
from ngdgfric.problem_file import FUNCTIONS, example_file, load_problem, parse_expression, problem_from_dict, tomllib

PROPERTY = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# ---------------------------------------------------------------- expressions

TOKENS = ["x", "y", "pi", "1", "0", "2.5", "1e308", "-", "+", "*", "/", "**", "(", ")", " ", ",", "sqrt", "log",
          "exp", "abs", "sin", "__import__", "'os'", ".", "[", "]", "lambda", ":", "nan", "inf", "1e400", "x.y"]


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
        return binary | unary | square

    return st.recursive(leaves, combine, max_leaves=8)


UNIT_SQUARE = ndf.uniform_mesh(ndf.example_6_2(), 1)  # alive while its mesh points are used (else a segfault)


@PROPERTY
@given(expressions(), st.floats(0, 1), st.floats(0, 1))
def test_valid_expressions_evaluate_as_python_does(expression, px, py):
    text, oracle = expression
    value = parse_expression(text)
    expected = oracle(px, py)
    found = value if isinstance(value, float) else value(UNIT_SQUARE(px, py))
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


@PROPERTY
@given(st.sampled_from(["material", "geometry", "loads", "contact", "boundaries"]), st.text(max_size=8), values())
def test_any_value_for_any_key_is_accepted_or_named(section, key, value):
    data = tomllib.loads(SHIPPED)
    keys = sorted(data.get(section, {}))
    key = keys[len(key) % len(keys)] if keys and len(key) % 3 else key  # mostly existing keys, sometimes new ones
    data.setdefault(section, {})[key] = value
    try:
        problem = problem_from_dict(data, source="random.toml")
    except ValueError as exc:
        assert re.match(r"random\.toml: \S", str(exc))
        return
    assert isinstance(problem, ndf.ContactProblem)


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
