"""Problem files: a :class:`ContactProblem` written as TOML.

A problem file holds the data of (1.5)-(1.9) and the labelled polygon::

    name = "Example 6.1"                    # optional (default: the file name)

    [material]                              # Young's modulus and Poisson ratio (Section 6)
    E = 2000.0
    nu = 0.4

    [geometry]                              # counter-clockwise; side k runs from vertex k to k+1
    vertices = [[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]
    labels = ["contact", "dirichlet", "traction", "traction"]

    [boundaries]                            # optional: the names of Gamma_D, Gamma_F, Gamma_C
    dirichlet = "dirichlet"
    traction = "traction"
    contact = "contact"

    [loads]                                 # optional, default 0
    f = [0.0, 0.0]                          # body force (1.5)
    g = ["200*(5 - y)", -190.0]             # traction on Gamma_F (1.7)

    [contact]
    c_n = 1.0                               # normal compliance (1.8)
    m_n = 1.0
    g_a = 0.05                              # initial gap
    c_tau = 450.0                           # friction bound (1.9)
    # m_t = 0.0                             # optional: exponent of the friction bound (default 0)

Every datum (a vector datum component by component) is a number or a string expression in
``x`` and ``y``: numbers, ``pi``, ``+ - * / **``, unary ``-`` and the functions of
:data:`FUNCTIONS`.  Expressions are parsed with :mod:`ast` and turned into NGSolve
CoefficientFunctions; nothing is ever passed to ``eval``.  Constant expressions stay numbers.
Unknown, missing or mistyped keys and bad expressions raise ValueError naming the file and key.
"""

import ast
import math
import operator
import warnings
from pathlib import Path

import ngsolve as ngs

from .problem import ContactProblem, Polygon

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

__all__ = ["load_problem", "problem_from_dict", "in_file", "parse_expression", "example_file", "FUNCTIONS"]

DATA = Path(__file__).resolve().parent / "data"


def _cf_abs(value):
    return ngs.IfPos(value, value, -value)


# name: (on numbers, on CoefficientFunctions)
FUNCTIONS = {
    "sin": (math.sin, ngs.sin), "cos": (math.cos, ngs.cos), "tan": (math.tan, ngs.tan),
    "exp": (math.exp, ngs.exp), "log": (math.log, ngs.log), "sqrt": (math.sqrt, ngs.sqrt),
    "atan": (math.atan, ngs.atan), "abs": (abs, _cf_abs),
}
VARIABLES = {"x": ngs.x, "y": ngs.y, "pi": math.pi}


def _power(base, exponent):
    """base ** exponent; an integer exponent on a CoefficientFunction by repeated multiplication
    (NGSolve's vectorised pow computes exp(e log b), NaN for b < 0: (x - 1)**2 was NaN for x < 1)."""
    if isinstance(base, ngs.CoefficientFunction) and isinstance(exponent, float) and exponent.is_integer() \
            and 0 < abs(exponent) <= 64:
        result, factor, n = None, base, int(abs(exponent))
        while n:
            if n & 1:
                result = factor if result is None else result * factor
            factor, n = factor * factor, n >> 1
        return result if exponent > 0 else 1 / result
    return operator.pow(base, exponent)


OPERATORS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
             ast.Pow: _power}
MAX_LENGTH = 1000

# section: {key: kind}; kind "scalar" (number or expression), "vector" (pair of those), "number",
# "name", "points", "names"; keys in REQUIRED must be present
SCHEMA = {
    "material": {"E": "scalar", "nu": "scalar"},
    "geometry": {"vertices": "points", "labels": "names"},
    "boundaries": {"dirichlet": "name", "traction": "name", "contact": "name"},
    "loads": {"f": "vector", "g": "vector"},
    # m_t: optional friction exponent, default 0 (the paper's law)
    "contact": {"c_n": "scalar", "m_n": "number", "g_a": "scalar", "c_tau": "scalar", "m_t": "number"},
}
REQUIRED = {"material": ("E", "nu"), "geometry": ("vertices", "labels"), "contact": ("c_n", "m_n", "g_a", "c_tau")}
DEFAULTS = {"f": (0.0, 0.0), "g": (0.0, 0.0)}
KEYS = {key: f"{section}.{key}" for section, keys in SCHEMA.items() for key in keys}


def example_file(name):
    """Path of the shipped problem file of Example ``name`` ("6.1" or "6.2": ``data/example_6_1.toml``, ...)."""
    key = str(name).removeprefix("example_").replace("_", ".")
    shipped = sorted(path.stem.removeprefix("example_").replace("_", ".") for path in DATA.glob("example_*.toml"))
    if key not in shipped:
        raise ValueError(f"no shipped problem file {name!r}; there are {shipped}")
    return DATA / f"example_{key.replace('.', '_')}.toml"


def parse_expression(text):
    """A number or a scalar CoefficientFunction of x, y from a safe arithmetic expression.

    ValueError (saying what is not allowed) for anything outside the grammar of the module docstring.
    """
    if len(text) > MAX_LENGTH:
        raise ValueError(f"expression longer than {MAX_LENGTH} characters")
    try:
        with warnings.catch_warnings():  # "invalid decimal literal" for 2x: the SyntaxError that follows says it
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, RecursionError, MemoryError) as exc:
        raise ValueError("not a valid expression") from exc
    try:
        value = _evaluate(tree.body)
    except ZeroDivisionError as exc:
        raise ValueError("division by zero") from exc
    except (OverflowError, RecursionError) as exc:
        raise ValueError("overflow (number too large or expression too deep)") from exc
    if isinstance(value, complex) or (isinstance(value, float) and not math.isfinite(value)):
        raise ValueError(f"evaluates to {value}, not a finite real number")
    return value


def _evaluate(node):
    if isinstance(node, ast.Constant):
        if isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            value = float(node.value)  # floats only: 10**10**10 overflows instead of hanging
            if math.isfinite(value):
                return value
        raise ValueError(f"constant {node.value!r} is not a finite real number")
    if isinstance(node, ast.Name):
        if node.id not in VARIABLES:
            raise ValueError(f"unknown name {node.id!r} (allowed: x, y, pi)")
        return VARIABLES[node.id]
    if isinstance(node, ast.BinOp) and type(node.op) in OPERATORS:
        value = OPERATORS[type(node.op)](_evaluate(node.left), _evaluate(node.right))
        if isinstance(value, complex):
            raise ValueError(f"{ast.unparse(node)!r} is not a real number")
        return value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        operand = _evaluate(node.operand)
        return -operand if isinstance(node.op, ast.USub) else operand
    if isinstance(node, ast.Call):
        name = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
        if name not in FUNCTIONS:
            raise ValueError(f"function {name!r} is not allowed (allowed: {', '.join(sorted(FUNCTIONS))})")
        if len(node.args) != 1 or node.keywords:
            raise ValueError(f"{name} takes exactly one argument")
        argument = _evaluate(node.args[0])
        on_number, on_cf = FUNCTIONS[name]
        if isinstance(argument, float):
            try:
                return float(on_number(argument))
            except ValueError as exc:  # math domain error
                raise ValueError(f"{name}({argument:g}): {exc}") from exc
        return on_cf(argument)
    raise ValueError(f"{ast.unparse(node)!r} is not allowed")


def load_problem(path):
    """The :class:`ContactProblem` of a TOML problem file (format in the module docstring)."""
    path = Path(path)
    if path.exists() and not path.is_file():  # a folder, or a pipe that would block the read for ever
        raise ValueError(f"{path}: not a regular file")
    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    except FileNotFoundError:
        raise
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the problem file: {exc.strerror or exc}") from exc
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a UTF-8 text file (byte {exc.start}: {exc.reason})") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: invalid TOML: {exc}") from exc
    return problem_from_dict(data, source=str(path), default_name=path.stem)


def problem_from_dict(data, source="<dict>", default_name="contact problem"):
    """The :class:`ContactProblem` of an already parsed problem file; ``source`` prefixes error messages."""
    def fail(key, message):
        raise ValueError(f"{source}: {key}: {message}")

    unknown = sorted(set(data) - set(SCHEMA) - {"name"})
    if unknown:
        fail(unknown[0], f"unknown key (allowed: name, {', '.join(f'[{s}]' for s in SCHEMA)})")
    name = data.get("name", default_name)
    if not isinstance(name, str):
        fail("name", f"must be a string, got {name!r}")
    values = dict(DEFAULTS)
    for section, keys in SCHEMA.items():
        table = data.get(section, {})
        if not isinstance(table, dict):
            fail(section, "must be a table [" + section + "]")
        for key in sorted(set(table) - set(keys)):
            fail(f"{section}.{key}", f"unknown key (allowed in [{section}]: {', '.join(keys)})")
        for key in REQUIRED.get(section, ()):
            if key not in table:
                fail(f"{section}.{key}", "missing")
        for key, value in table.items():
            try:
                values[key] = _convert(keys[key], value)
            except OverflowError:
                fail(f"{section}.{key}", "number too large (not a finite float)")
            except ValueError as exc:
                fail(f"{section}.{key}", str(exc))
    vertices, labels = values.pop("vertices"), values.pop("labels")
    try:
        geometry = Polygon(vertices, labels)
        return ContactProblem(geometry=geometry, name=name, **values)
    except ValueError as exc:
        raise ValueError(in_file(source, exc)) from exc


def in_file(source, error):
    """The message of a problem's ValueError as the file says it: "nu must be ..." from ``source``
    becomes "<source>: material.nu must be ..."."""
    message = str(error)
    field = message.split(" ", 1)[0].split("[", 1)[0]
    if field in KEYS:
        message = f"{KEYS[field].rsplit('.', 1)[0]}.{message}"
    return f"{source}: {message}"


def _scalar(value):
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ValueError(f"must be a number or an expression string, got {value!r}")
    if isinstance(value, str):
        try:
            return parse_expression(value)
        except ValueError as exc:
            raise ValueError(f"bad expression {value!r}: {exc}") from exc
    return float(value)


def _convert(kind, value):
    if kind == "scalar":
        return _scalar(value)
    if kind == "number":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"must be a number, got {value!r}")
        return float(value)
    if kind == "vector":
        if not (isinstance(value, list) and len(value) == 2):
            raise ValueError(f"must be a pair [x-component, y-component], got {value!r}")
        return tuple(_scalar(v) for v in value)
    if kind == "name":
        if not (isinstance(value, str) and value):
            raise ValueError(f"must be a non-empty string, got {value!r}")
        return value
    if kind == "names":
        if not (isinstance(value, list) and all(isinstance(v, str) and v for v in value)):
            raise ValueError(f"must be a list of boundary names, got {value!r}")
        return tuple(value)
    # points
    if not (isinstance(value, list) and all(isinstance(p, list) and len(p) == 2 for p in value)):
        raise ValueError(f"must be a list of [x, y] pairs, got {value!r}")
    if any(isinstance(c, bool) or not isinstance(c, (int, float)) for p in value for c in p):
        raise ValueError(f"coordinates must be numbers, got {value!r}")
    return tuple((float(a), float(b)) for a, b in value)
