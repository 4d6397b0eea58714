"""Problem files: a :class:`~ngdgfric.ContactProblem` written as TOML.

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

Two bodies in contact (:class:`~ngdgfric.ContactPair`): regions that share no interface are bodies of their own, and
each ``[[contact.pair]]`` table names a side of one body and the side of another that it meets (sides of two bodies
that touch must be a pair); ``side``, ``other`` and ``c_n`` are required, ``m_n`` (default 1), ``c_tau`` (0),
``m_t`` (0), ``g_a`` (0, an offset added to the geometric gap) and ``reach`` (default: a tenth of the domain's
diameter) optional, each a number.  With ``contact = []`` in ``[boundaries]`` no side rests on the foundation and the
law of ``[contact]`` may be left out (then ``c_n = 0``, ``m_n = 1``, ``g_a = 0``, ``c_tau = 0``); ``dirichlet = []``
is allowed too when there are pairs.  Errors name the table (``contact.pair[0].c_n``)::

    [boundaries]
    dirichlet = "top"
    symmetry = ["bottom", "left1", "left2"]
    traction = ["right1", "right2"]
    contact = []                              # no side on the foundation

    [[contact.pair]]                          # side c2 of the upper block meets side c1 of the lower
    side = "c2"
    other = "c1"
    c_n = 50.0
    c_tau = 0.3                               # optional: m_n, c_tau, m_t, g_a, reach

One region (named ``omega``) may be written directly in ``[geometry]``, the form of the paper's examples
(the shipped file of Example 6.1); without ``arcs`` and holes it is a :class:`~ngdgfric.Polygon`::

    [geometry]
    vertices = [[0.0, 0.05], [1.0, 0.05], [1.0, 1.05], [0.0, 1.05]]
    labels = ["contact", "dirichlet", "traction", "traction"]
    # arcs = { 0 = [0.5, 0.0] }               # optional, as in a region; [[geometry.hole]] tables may follow

Without ``[boundaries]`` the names are ``dirichlet``, ``traction`` and ``contact`` and there is no symmetry
side.  Region names and side labels are letters, digits and underscores starting with a letter
(``check_name`` of :mod:`ngdgfric.domain`); sides shared by two regions become interfaces whatever their label
(``interface`` reads best).  A loop is either ``vertices`` + ``labels`` (+ ``arcs``, a table {side number =
[x, y]}) or a circle ``centre`` + ``radius`` + ``label``; a region's ``name`` may be left out when there is
only one region (then it is ``omega``).

Every datum (a vector datum component by component) is a number or a string expression in ``x`` and
``y`` (:mod:`ngdgfric.expressions`: numbers, ``pi``, ``+ - * / **``, the functions ``abs``, ``atan``, ``cos``,
``exp``, ``log``, ``sin``, ``sqrt``, ``step``, ``tan`` (``FUNCTIONS``), ``min``, ``max`` and
``if(condition, a, b)``; never passed to ``eval``).  Unknown, missing or mistyped keys and bad expressions raise
ValueError naming the file and key.

Shipped problem files (:func:`ngdgfric.example_file`): the paper's Examples 6.1 and 6.2 and the scenes
``half_disk``, ``block_with_hole``, ``two_materials_symmetric``, ``indentation`` and ``rubber_pad``.
"""

import re
from pathlib import Path

from .domain import Domain, Loop, check_name
from .expressions import FUNCTIONS, parse_expression
from .problem import ContactPair, ContactProblem, Polygon

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

__all__ = ["load_problem", "problem_from_dict", "in_file", "parse_expression", "example_file", "shipped_files",
           "FUNCTIONS", "PAPER_EXAMPLES"]

DATA = Path(__file__).resolve().parent / "data"
PAPER_EXAMPLES = ("6.1", "6.2")  # data/example_6_1.toml, data/example_6_2.toml; other files: by their stem

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
    # pair: the [[contact.pair]] tables (read by _pairs)
    "contact": {"c_n": "scalar", "m_n": "number", "g_a": "scalar", "c_tau": "scalar", "m_t": "number",
                "pair": "pairs"},
}
PER_PART = {"E": "region", "nu": "region", "f": "region", "g": "traction side", "u_D": "dirichlet side",
            "c_n": "contact side", "g_a": "contact side", "c_tau": "contact side", "m_n": "contact side",
            "m_t": "contact side"}
REQUIRED = {"material": ("E", "nu"), "contact": ("c_n", "m_n", "g_a", "c_tau")}
DEFAULTS = {"f": (0.0, 0.0), "g": (0.0, 0.0)}
# the law of [contact] when boundaries.contact = [] (no side on the foundation, bodies in contact through pairs)
NO_CONTACT_SIDE = {"c_n": 0.0, "m_n": 1.0, "g_a": 0.0, "c_tau": 0.0}
KEYS = {key: f"{section}.{key}" for section, keys in SCHEMA.items() for key in keys}
# the keys of a [[geometry.region]] / [[geometry.hole]] table: a loop, or a circle
LOOP_KEYS, CIRCLE_KEYS = ("vertices", "labels", "arcs"), ("centre", "radius", "label")
# the keys of a [[contact.pair]] table (ngdgfric.ContactPair's fields), the first three required
PAIR_KEYS = ("side", "other", "c_n", "m_n", "c_tau", "m_t", "g_a", "reach")
PAIR_REQUIRED = ("side", "other", "c_n")


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
    """The path of a problem file shipped with the package.

    Parameters
    ----------
    name : str
        ``"6.1"`` or ``"6.2"`` (the file ``example_6_1.toml`` in the package's ``data`` folder, also called
        ``"example_6_1"``), or a scene (``"half_disk"``: ``half_disk.toml``).

    Returns
    -------
    pathlib.Path
        The file, for :func:`ngdgfric.load_problem` or as a template of one's own.

    Raises
    ------
    ValueError
        If there is no such file; the message names the choices.

    Examples
    --------
    >>> ndf.example_file("6.1").name
    'example_6_1.toml'
    """
    files = shipped_files()
    key = str(name)
    if key not in files and key.startswith("example_"):
        key = key.removeprefix("example_").replace("_", ".")
    if key not in files:
        raise ValueError(f"no shipped problem file {name!r}; there are {sorted(files)}")
    return files[key]



def load_problem(path):
    """The contact problem of a TOML problem file.

    The format is that of :mod:`ngdgfric.problem_file` (its module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The problem file.

    Returns
    -------
    ContactProblem
        The problem; its ``name`` is the file's ``name`` key, else the file name without ``.toml``.

    Raises
    ------
    FileNotFoundError
        If there is no file at ``path``.
    ValueError
        If the file cannot be read, is not TOML, or has unknown, missing or invalid keys; the message names the
        file and the key.

    Examples
    --------
    >>> problem = ndf.load_problem(ndf.example_file("6.2"))
    >>> problem.name, problem.E, problem.nu
    ('Example 6.2', 2500.0, 0.2)
    """
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
    """The :class:`~ngdgfric.ContactProblem` of an already parsed problem file; ``source`` prefixes error messages."""
    def fail(key, message):
        raise ValueError(f"{source}: {key}: {message}")

    unknown = sorted(set(data) - set(SCHEMA) - {"name"})
    if unknown:
        fail(unknown[0], f"unknown key (allowed: name, {', '.join(f'[{s}]' for s in SCHEMA)})")
    name = data.get("name", default_name)
    if not isinstance(name, str):
        fail("name", f"must be a string, got {name!r}")
    values = dict(DEFAULTS)
    boundaries = data.get("boundaries", {})
    if isinstance(boundaries, dict) and boundaries.get("contact", None) == []:
        values.update(NO_CONTACT_SIDE)  # the law of no side: [contact] may leave it out
    for section, keys in SCHEMA.items():
        table = data.get(section, {})
        if not isinstance(table, dict):
            fail(section, "must be a table [" + section + "]")
        for key in sorted(set(table) - set(keys)):
            fail(f"{section}.{key}", f"unknown key (allowed in [{section}]: {', '.join(keys)})")
        for key in REQUIRED.get(section, ()):
            if key not in table and key not in values:
                fail(f"{section}.{key}", "missing")
        for key, value in table.items():
            if keys[key] == "geometry":
                continue
            if keys[key] == "pairs":
                try:
                    values["pairs"] = _pairs(f"{section}.{key}", value)
                except _KeyError as exc:
                    fail(exc.key, str(exc))
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
    message = re.sub(r"\bpairs\[(\d+)\]", r"contact.pair[\1]", str(error))  # ContactProblem's pairs[k]
    field = message.split(" ", 1)[0].split("[", 1)[0].removesuffix(":")
    if field in KEYS and field != "pair":
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
    """A :class:`~ngdgfric.Loop` from a region or hole table (a loop or a circle, module docstring); ``allowed``: its
    keys (a region's ``name`` is read by the caller)."""
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
    errors name them as before), or a :class:`~ngdgfric.Domain`."""
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


def _pairs(where, value):
    """The :class:`~ngdgfric.ContactPair` tuple of the ``[[contact.pair]]`` tables (errors name the table)."""
    if not (isinstance(value, list) and all(isinstance(table, dict) for table in value)):
        raise _KeyError(where, f"must be a list of tables ([[{where}]]: side, other, c_n, ...), got {value!r}")
    pairs = []
    for k, table in enumerate(value):
        at = f"{where}[{k}]"
        for key in sorted(set(table) - set(PAIR_KEYS)):
            raise _KeyError(f"{at}.{key}", f"unknown key (allowed: {', '.join(PAIR_KEYS)})")
        for key in PAIR_REQUIRED:
            if key not in table:
                raise _KeyError(f"{at}.{key}", f"missing (a pair needs {', '.join(PAIR_REQUIRED)})")
        fields = {}
        for key, item in table.items():
            if key in ("side", "other"):
                if not (isinstance(item, str) and item):
                    raise _KeyError(f"{at}.{key}", f"must be a side name, got {item!r}")
                fields[key] = item
            else:
                fields[key] = _in(f"{at}.{key}", _number, item)
        try:
            pairs.append(ContactPair(**fields))
        except ValueError as exc:  # "ContactPair.c_n must be >= 0, ...": named by the key of the table
            field = re.match(r"ContactPair\.(\w+) (.*)", str(exc), re.DOTALL)
            raise _KeyError(f"{at}.{field[1]}" if field else at, field[2] if field else str(exc)) from None
    return tuple(pairs)
