"""Problem files: a :class:`ContactProblem` written as TOML.

A problem file holds the data of (1.5)-(1.9) and the domain with its named sides.  A full example (two
materials, an interface, a curved side, a hole, a symmetry plane, data per region and per side)::

    name = "Two layers on a foundation"       # optional (default: the file name)

    [material]                                # Young's modulus and Poisson ratio (Section 6):
    E = { steel = 200.0, rubber = "2 + x" }   # one value for every region, or a table {region = value}
    nu = 0.3

    [[geometry.region]]                       # a named region inside a counter-clockwise loop:
    name = "steel"                            # side k runs from vertex k to vertex k+1 (the last back to 0)
    vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]]
    labels = ["contact", "right", "interface", "axis"]

    [[geometry.region]]                       # shares the side y = 0.5 with steel: an interface
    name = "rubber"
    vertices = [[0.0, 0.5], [1.0, 0.5], [1.0, 1.0], [0.0, 1.0]]
    labels = ["interface", "right", "top", "axis"]
    arcs = { 2 = [0.5, 1.1] }                 # side 2 is the circular arc through (0.5, 1.1); others straight

    [[geometry.hole]]                         # a circular hole; a hole may also be a loop (vertices, labels,
    centre = [0.5, 0.25]                      # arcs as above), and a region a circle (an inclusion)
    radius = 0.1
    label = "hole"

    [boundaries]                              # the side names of Gamma_D, Gamma_F, Gamma_C and of the
    dirichlet = "top"                         # symmetry sides (u . n = 0, no tangential traction):
    traction = ["right", "hole"]              # one name or a list of names each
    contact = "contact"
    symmetry = "axis"

    [loads]                                   # optional, default 0
    f = { steel = [0.0, -0.1], rubber = [0.0, 0.0] }  # body force (1.5): a pair, or a table {region = pair}
    g = { right = ["-0.5*y", 0.0] }           # traction (1.7): a pair, or {traction side = pair} (others free)
    u_D = [0.0, -0.01]                        # displacement on Gamma_D: a pair, or {dirichlet side = pair}

    [contact]
    c_n = 1000.0                              # normal compliance (1.8): sigma_n = -c_n (u_n - g_a)_+^m_n
    m_n = 1.0                                 # a number (not an expression)
    g_a = "if(x > 0.5, 0.001, 0)"             # initial gap
    c_tau = { contact = 2.0 }                 # friction bound (1.9)
    # m_t = 0.0                               # optional: exponent of the friction bound (default 0)
                                              # each of them: one value, or a table {contact side = value}

One region (named ``omega``) may be written directly in ``[geometry]``, the form of the paper's examples
(``data/example_6_1.toml``); without ``arcs`` and holes it is a :class:`~ngdgfric.problem.Polygon`::

    [geometry]
    vertices = [[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]
    labels = ["contact", "dirichlet", "traction", "traction"]
    # arcs = { 0 = [0.5, 0.0] }               # optional, as in a region; [[geometry.hole]] tables may follow

Without ``[boundaries]`` the names are ``dirichlet``, ``traction`` and ``contact`` and there is no symmetry
side.  Region names and side labels are letters, digits and underscores starting with a letter
(:func:`ngdgfric.domain.check_name`); sides shared by two regions become interfaces whatever their label
(``interface`` reads best).  A loop is either ``vertices`` + ``labels`` (+ ``arcs``, a table {side number =
[x, y]}) or a circle ``centre`` + ``radius`` + ``label``; a region's ``name`` may be left out when there is
only one region (then it is ``omega``).

Every datum (a vector datum component by component) is a number or a string expression in ``x`` and
``y``: numbers, ``pi``, ``+ - * / **``, unary ``-``, the functions of :data:`FUNCTIONS` (one argument:
``sin cos tan exp log sqrt atan abs``, and ``step(t)``, 1 for t > 0 and 0 otherwise), ``min(a, b)``,
``max(a, b)`` and ``if(condition, a, b)`` with one comparison ``<``, ``<=``, ``>`` or ``>=`` as the
condition (``if(x > 1.5, -300, 0)``).  Expressions are parsed with :mod:`ast` and turned into NGSolve
CoefficientFunctions (conditions by ``ngs.IfPos``); nothing is ever passed to ``eval``.  Constant
expressions stay numbers.  Unknown, missing or mistyped keys and bad expressions raise ValueError naming
the file and key.

Shipped problem files (:func:`example_file`): the paper's Examples 6.1 and 6.2 and the scenes
``half_disk``, ``block_with_hole``, ``two_materials_symmetric`` and ``indentation``.
"""

import ast
import math
import operator
import re
import warnings
from pathlib import Path

import ngsolve as ngs

from .domain import Domain, Loop, check_name
from .problem import ContactProblem, Polygon

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

__all__ = ["load_problem", "problem_from_dict", "in_file", "parse_expression", "example_file", "shipped_files",
           "FUNCTIONS", "PAPER_EXAMPLES"]

DATA = Path(__file__).resolve().parent / "data"
PAPER_EXAMPLES = ("6.1", "6.2")  # data/example_6_1.toml, data/example_6_2.toml; other files: by their stem


def _cf_abs(value):
    return ngs.IfPos(value, value, -value)


def _if_positive(value, then, otherwise):
    """``then`` where ``value`` > 0, else ``otherwise``: by Python on numbers, by ``ngs.IfPos`` on
    CoefficientFunctions."""
    if isinstance(value, float):
        return then if value > 0 else otherwise
    return ngs.IfPos(value, then, otherwise)


# name: (on numbers, on CoefficientFunctions); one argument each
FUNCTIONS = {
    "sin": (math.sin, ngs.sin), "cos": (math.cos, ngs.cos), "tan": (math.tan, ngs.tan),
    "exp": (math.exp, ngs.exp), "log": (math.log, ngs.log), "sqrt": (math.sqrt, ngs.sqrt),
    "atan": (math.atan, ngs.atan), "abs": (abs, _cf_abs),
    "step": (lambda t: 1.0 if t > 0 else 0.0, lambda t: ngs.IfPos(t, 1.0, 0.0)),
}
# two arguments, on numbers and CoefficientFunctions alike
BINARY = {"min": lambda a, b: _if_positive(a - b, b, a), "max": lambda a, b: _if_positive(a - b, a, b)}
IF = "if"  # if(condition, a, b); a keyword in Python, so the text calls _IF_NAME instead before parsing
_IF_NAME = "if_"
_IF_CALL = re.compile(r"(?<![\w.])if(?=\s*\()")
_IF_NAME_USED = re.compile(r"(?<![\w.])if_(?!\w)")
ALLOWED_FUNCTIONS = ", ".join(sorted([*FUNCTIONS, *BINARY, IF]))
# a comparison: (on numbers, on CoefficientFunctions as (the difference d of its sides, whether it holds where
# d <= 0 rather than where d > 0) for ngs.IfPos)
COMPARISONS = {ast.Gt: (operator.gt, lambda a, b: a - b, False), ast.Lt: (operator.lt, lambda a, b: b - a, False),
               ast.GtE: (operator.ge, lambda a, b: b - a, True), ast.LtE: (operator.le, lambda a, b: a - b, True)}
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

# section: {key: kind}; kind "scalar" (number or expression), "vector" (pair of those), "number", "sides"
# (one side name or a list), "geometry" (read by _geometry); keys in PER_PART may also be a table
# {part name: value of the kind}, keys in REQUIRED must be present
SCHEMA = {
    "material": {"E": "scalar", "nu": "scalar"},
    "geometry": {"vertices": "geometry", "labels": "geometry", "arcs": "geometry", "region": "geometry",
                 "hole": "geometry"},
    "boundaries": {"dirichlet": "sides", "traction": "sides", "contact": "sides", "symmetry": "sides"},
    "loads": {"f": "vector", "g": "vector", "u_D": "vector"},
    # m_t: optional friction exponent, default 0 (the paper's law)
    "contact": {"c_n": "scalar", "m_n": "number", "g_a": "scalar", "c_tau": "scalar", "m_t": "number"},
}
PER_PART = {"E": "region", "nu": "region", "f": "region", "g": "traction side", "u_D": "dirichlet side",
            "c_n": "contact side", "g_a": "contact side", "c_tau": "contact side", "m_n": "contact side",
            "m_t": "contact side"}
REQUIRED = {"material": ("E", "nu"), "contact": ("c_n", "m_n", "g_a", "c_tau")}
DEFAULTS = {"f": (0.0, 0.0), "g": (0.0, 0.0)}
KEYS = {key: f"{section}.{key}" for section, keys in SCHEMA.items() for key in keys}
# the keys of a [[geometry.region]] / [[geometry.hole]] table: a loop, or a circle
LOOP_KEYS, CIRCLE_KEYS = ("vertices", "labels", "arcs"), ("centre", "radius", "label")


def shipped_files():
    """{name: path} of the problem files in ``ngdgfric/data``: "6.1", "6.2" (the paper's examples,
    ``example_6_1.toml``, ...) and the scenes by their file names (``half_disk``, ...)."""
    files = {}
    for path in sorted(DATA.glob("*.toml")):
        stem = path.stem
        key = stem.removeprefix("example_").replace("_", ".") if stem.startswith("example_") else stem
        files[key] = path
    return files


def example_file(name):
    """Path of the shipped problem file ``name``: "6.1" or "6.2" (``data/example_6_1.toml``, also
    "example_6_1") or a scene ("half_disk": ``data/half_disk.toml``); ValueError naming the choices."""
    files = shipped_files()
    key = str(name)
    if key not in files and key.startswith("example_"):
        key = key.removeprefix("example_").replace("_", ".")
    if key not in files:
        raise ValueError(f"no shipped problem file {name!r}; there are {sorted(files)}")
    return files[key]


def parse_expression(text):
    """A number or a scalar CoefficientFunction of x, y from a safe arithmetic expression.

    ValueError (saying what is not allowed) for anything outside the grammar of the module docstring.
    """
    if len(text) > MAX_LENGTH:
        raise ValueError(f"expression longer than {MAX_LENGTH} characters")
    if _IF_NAME_USED.search(text):
        raise ValueError(f"unknown name {_IF_NAME!r} (the condition function is called if)")
    try:
        with warnings.catch_warnings():  # "invalid decimal literal" for 2x: the SyntaxError that follows says it
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(_IF_CALL.sub(_IF_NAME, text.strip()), mode="eval")
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


def _shown(node):
    """The source of a node as the user wrote it (if(...), not the internal name)."""
    return re.sub(rf"(?<![\w.]){_IF_NAME}\(", f"{IF}(", ast.unparse(node))


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
            raise ValueError(f"{_shown(node)!r} is not a real number")
        return value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        operand = _evaluate(node.operand)
        return -operand if isinstance(node.op, ast.USub) else operand
    if isinstance(node, ast.Call):
        return _call(node)
    if isinstance(node, ast.Compare):
        raise ValueError(f"the comparison {_shown(node)!r} is only allowed as the condition of if(condition, a, b)")
    if isinstance(node, ast.BoolOp):
        raise ValueError(f"{_shown(node)!r}: 'and' and 'or' are not allowed (nest if(...) instead)")
    raise ValueError(f"{_shown(node)!r} is not allowed")


def _call(node):
    """A function call: one of FUNCTIONS, BINARY or if(condition, a, b)."""
    name = node.func.id if isinstance(node.func, ast.Name) else _shown(node.func)
    name = IF if name == _IF_NAME else name
    count = {IF: 3, **dict.fromkeys(BINARY, 2)}.get(name, 1)
    if name not in FUNCTIONS and name not in BINARY and name != IF:
        raise ValueError(f"function {name!r} is not allowed (allowed: {ALLOWED_FUNCTIONS})")
    if node.keywords:
        raise ValueError(f"{name} takes no keyword arguments")
    if any(isinstance(a, ast.Starred) for a in node.args):
        raise ValueError(f"{name}: *arguments are not allowed")
    if len(node.args) != count:
        usage = {IF: "if(condition, a, b)", "min": "min(a, b)", "max": "max(a, b)"}.get(name, f"{name}(t)")
        raise ValueError(f"{name} takes exactly {count} argument{'s' * (count > 1)}, {usage}; got {len(node.args)}")
    if name == IF:
        on_numbers, difference, negated, left, right = _condition(node.args[0])
        then, otherwise = _evaluate(node.args[1]), _evaluate(node.args[2])
        if isinstance(left, float) and isinstance(right, float):
            return then if on_numbers(left, right) else otherwise
        d = difference(left, right)
        return ngs.IfPos(d, otherwise, then) if negated else ngs.IfPos(d, then, otherwise)
    if name in BINARY:
        return BINARY[name](_evaluate(node.args[0]), _evaluate(node.args[1]))
    argument = _evaluate(node.args[0])
    on_number, on_cf = FUNCTIONS[name]
    if isinstance(argument, float):
        try:
            return float(on_number(argument))
        except ValueError as exc:  # math domain error
            raise ValueError(f"{name}({argument:g}): {exc}") from exc
    return on_cf(argument)


def _condition(node):
    """The comparison ``node`` as its row of COMPARISONS and its two sides, evaluated."""
    if isinstance(node, ast.BoolOp):
        raise ValueError(f"{_shown(node)!r}: 'and' and 'or' are not allowed (nest if(...) instead)")
    if not isinstance(node, ast.Compare):
        raise ValueError(f"the condition of if(condition, a, b) must be a comparison such as x > 1 "
                         f"(<, <=, >, >=), got {_shown(node)!r}")
    if len(node.ops) != 1:
        raise ValueError(f"{_shown(node)!r}: one comparison per condition (nest if(...) for a range)")
    if type(node.ops[0]) not in COMPARISONS:
        raise ValueError(f"{_shown(node)!r}: only <, <=, > and >= compare (== and != are fragile on "
                         f"floating-point values)")
    return *COMPARISONS[type(node.ops[0])], _evaluate(node.left), _evaluate(node.comparators[0])


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


class _KeyError(ValueError):
    """A bad value of one key: ``key`` is where it sits in the file (``geometry.region[1].arcs``)."""

    def __init__(self, key, message):
        super().__init__(message)
        self.key = key


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
            if keys[key] == "geometry":
                continue
            try:
                values[key] = _value(keys[key], value, key in PER_PART)
            except _KeyError as exc:
                fail(f"{section}.{key}.{exc.key}", str(exc))
            except OverflowError:
                fail(f"{section}.{key}", "number too large (not a finite float)")
            except ValueError as exc:
                fail(f"{section}.{key}", str(exc))
    try:
        geometry = _geometry(data.get("geometry", {}))
    except _KeyError as exc:
        fail(exc.key, str(exc))
    try:
        if isinstance(geometry, tuple):  # one polygon: its errors are Polygon's, named by in_file
            geometry = Polygon(*geometry)
        return ContactProblem(geometry=geometry, name=name, **values)
    except ValueError as exc:
        raise ValueError(in_file(source, exc)) from exc


def in_file(source, error):
    """The message of a problem's ValueError as the file says it: "nu must be ..." from ``source``
    becomes "<source>: material.nu must be ..."."""
    message = str(error)
    field = message.split(" ", 1)[0].split("[", 1)[0].removesuffix(":")
    if field in KEYS:
        message = f"{KEYS[field].rsplit('.', 1)[0]}.{message}"
    elif message.startswith("side name "):  # one side in two boundary parts
        message = f"boundaries: {message}"
    elif message.startswith("geometry has no side labelled ") and message.endswith(" boundary)"):
        message = f"boundaries.{message.rsplit('(', 1)[1].split()[0]}: {message}"
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


def _number(value):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"must be a number, got {value!r}")
    return float(value)


def _value(kind, value, per_part):
    """A datum of ``kind``; with ``per_part``, a table {part: datum} is a dict of them (errors name the part)."""
    if per_part and isinstance(value, dict):
        parts = {}
        for part, item in value.items():
            try:
                parts[part] = _convert(kind, item)
            except OverflowError:
                raise _KeyError(part, "number too large (not a finite float)") from None
            except ValueError as exc:
                raise _KeyError(part, str(exc)) from None
        return parts
    return _convert(kind, value)


def _convert(kind, value):
    if kind == "scalar":
        return _scalar(value)
    if kind == "number":
        return _number(value)
    if kind == "vector":
        if not (isinstance(value, list) and len(value) == 2):
            raise ValueError(f"must be a pair [x-component, y-component]{' or a table' * isinstance(value, dict)}"
                             f", got {value!r}")
        return tuple(_scalar(v) for v in value)
    # sides
    if isinstance(value, str) and value:
        return value
    if isinstance(value, list) and all(isinstance(v, str) and v for v in value):
        return tuple(value)
    raise ValueError(f"must be a side name or a list of side names, got {value!r}")


def _points(value):
    if not (isinstance(value, list) and all(isinstance(p, list) and len(p) == 2 for p in value)):
        raise ValueError(f"must be a list of [x, y] pairs, got {value!r}")
    if any(isinstance(c, bool) or not isinstance(c, (int, float)) for p in value for c in p):
        raise ValueError(f"coordinates must be numbers, got {value!r}")
    return tuple((float(a), float(b)) for a, b in value)


def _point(value):
    if not (isinstance(value, list) and len(value) == 2) or \
            any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in value):
        raise ValueError(f"must be a point [x, y] of two numbers, got {value!r}")
    return float(value[0]), float(value[1])


def _labels(value):
    if not (isinstance(value, list) and all(isinstance(v, str) and v for v in value)):
        raise ValueError(f"must be a list of side names, got {value!r}")
    return tuple(value)


def _arcs(value):
    """{side number: point} from the table {"k" = [x, y]}."""
    if not isinstance(value, dict):
        raise ValueError(f"must be a table {{side number = [x, y]}} (a point each arc passes through), "
                         f"got {value!r}")
    arcs = {}
    for side, point in value.items():
        if not (side.isascii() and side.isdigit()):
            raise _KeyError(side, "not a side number (0 for the side from vertices[0] to vertices[1], ...)")
        try:
            arcs[int(side)] = _point(point)
        except ValueError as exc:
            raise _KeyError(side, str(exc)) from None
    return arcs


def _in(key, convert, value):
    """``convert(value)``, errors named by ``key``."""
    try:
        return convert(value)
    except _KeyError as exc:
        raise _KeyError(f"{key}.{exc.key}", str(exc)) from None
    except OverflowError:
        raise _KeyError(key, "number too large (not a finite float)") from None
    except ValueError as exc:
        raise _KeyError(key, str(exc)) from None


def _loop(where, table, allowed):
    """A :class:`Loop` from a region or hole table (a loop or a circle, module docstring); ``allowed``: its keys
    (a region's ``name`` is read by the caller)."""
    if not isinstance(table, dict):
        raise _KeyError(where, f"must be a table ([[{where.split('[')[0]}]]), got {table!r}")
    for key in sorted(set(table) - set(allowed)):
        raise _KeyError(f"{where}.{key}", f"unknown key (allowed: {', '.join(allowed)})")
    circle = [key for key in CIRCLE_KEYS if key in table]
    loop = [key for key in LOOP_KEYS if key in table]
    if circle and loop:
        raise _KeyError(where, f"give either vertices and labels (and arcs) or centre, radius and label (a circle), "
                               f"not {circle[0]} with {loop[0]}")
    if circle:
        for key in CIRCLE_KEYS:
            if key not in table:
                raise _KeyError(f"{where}.{key}", "missing (a circle needs centre, radius and label)")
        centre = _in(f"{where}.centre", _point, table["centre"])
        radius = _in(f"{where}.radius", _number, table["radius"])
        if not (isinstance(table["label"], str) and table["label"]):
            raise _KeyError(f"{where}.label", f"must be a side name, got {table['label']!r}")
        return _in(where, lambda _: Loop.circle(centre, radius, table["label"]), None)
    for key in ("vertices", "labels"):
        if key not in table:
            raise _KeyError(f"{where}.{key}", "missing (a loop needs vertices and labels, a circle centre, radius "
                                              "and label)")
    vertices = _in(f"{where}.vertices", _points, table["vertices"])
    labels = _in(f"{where}.labels", _labels, table["labels"])
    arcs = _in(f"{where}.arcs", _arcs, table.get("arcs", {}))
    return _in(where, lambda _: Loop(vertices, labels, arcs), None)


def _geometry(table):
    """The geometry of the [geometry] table: (vertices, labels) of a polygon (made by the caller, whose
    errors name them as before), or a :class:`Domain`."""
    regions, holes = table.get("region"), table.get("hole", [])
    for key, value in (("region", regions), ("hole", holes)):
        if value is not None and not isinstance(value, list):
            raise _KeyError(f"geometry.{key}", f"must be a list of tables ([[geometry.{key}]]), got {value!r}")
    if regions is not None:
        given = [key for key in LOOP_KEYS if key in table]
        if given:
            raise _KeyError(f"geometry.{given[0]}", "give one region in [geometry] (vertices, labels, arcs) or "
                                                    "[[geometry.region]] tables, not both")
        if not regions:
            raise _KeyError("geometry.region", "no region")
    else:
        for key in ("vertices", "labels"):
            if key not in table:
                raise _KeyError(f"geometry.{key}", "missing (or give [[geometry.region]] tables)")
        vertices = _in("geometry.vertices", _points, table["vertices"])
        labels = _in("geometry.labels", _labels, table["labels"])
        if "arcs" not in table and not holes:
            return vertices, labels
    hole_loops = [_loop(f"geometry.hole[{k}]", hole, LOOP_KEYS + CIRCLE_KEYS) for k, hole in enumerate(holes)]
    if regions is None:
        arcs = _in("geometry.arcs", _arcs, table.get("arcs", {}))
        named = {"omega": _in("geometry", lambda _: Loop(vertices, labels, arcs), None)}
    else:
        named = {}
        for k, region in enumerate(regions):
            where = f"geometry.region[{k}]"
            name = region.get("name", "omega" if len(regions) == 1 else None) if isinstance(region, dict) else None
            if isinstance(region, dict) and name is None:
                raise _KeyError(f"{where}.name", "missing (a region needs a name when there are several)")
            if isinstance(region, dict) and not isinstance(name, str):
                raise _KeyError(f"{where}.name", f"must be a string, got {name!r}")
            if isinstance(region, dict):
                _in(f"{where}.name", lambda v: check_name("region", v), name)
            if name in named:
                raise _KeyError(f"{where}.name", f"region {name!r} is given twice")
            named[name] = _loop(where, region, ("name",) + LOOP_KEYS + CIRCLE_KEYS)
    return _in("geometry", lambda _: Domain(named, hole_loops), None)
