r"""Checks of a problem on a mesh before anything is assembled: the data pointwise, and the size.

:class:`~ngdgfric.ContactProblem` checks numbers when it is made; data given as
CoefficientFunctions can only be checked where they are used.  ``check_data`` samples them
at the points where the forms evaluate them (each triangle's Gauss points of degrees :math:`2p - 2, \dots,
2p + 2`, its edges' Gauss points and its vertices; the Gauss points, among them the contact rule's,
and end points of the edges of :math:`\Gamma_F` and :math:`\Gamma_C`; :math:`p` the largest order) and names the
datum and a point where it fails with a :class:`~ngdgfric.DataError` (a datum invalid only at isolated points
between these can pass): unchecked, ``g_a = "sqrt(x - 2)"`` or ``E = "2000*(0.5 - x)"`` would end in a
no-contact answer or a complex energy norm.

``check_solution`` names an argument that is not a solution where one is needed; ``positive_number``,
``positive_integer``, ``callback``, ``choice`` and ``optional`` check one argument each (any real number is a number,
any integral one an integer: numpy's too), for the solvers' options, :func:`~ngdgfric.solve` and
:func:`~ngdgfric.adapt`.

``check_size`` refuses a discretisation whose estimated memory is above a budget (``max_bytes``, default
``MEMORY_BUDGET``, 8 GB) before it is assembled.
"""

import reprlib
from numbers import Integral, Real

import ngsolve as ngs
import numpy as np

from .bounds import DATA
from .dg.dofs import element_dofs
from .problem import pattern

__all__ = ["check_data", "check_size", "estimated_bytes", "check_solution", "shown", "DataError", "MEMORY_BUDGET",
           "positive_number", "positive_integer", "callback", "choice", "optional"]

# bytes; the default of check_size's max_bytes (and of solve's and adapt's), which estimates the peak memory of
# a solve as the sum over elements of n_T (1000 + 270 n_T) bytes, n_T = (p_T + 1)(p_T + 2) DOFs (fitted to the
# peak resident memory of Example 6.1 solves: P1 with 2e5 and 8e5 DOFs, P3 with 1.6e5 and 6.6e5, P6 with 1.1e5; 3-7 %)
MEMORY_BUDGET = 8e9


class DataError(ValueError):
    """A datum of the problem is invalid somewhere on the mesh.

    Raised before assembly (by :func:`ngdgfric.solve` and :class:`~ngdgfric.Discretization`) where a datum given
    as a CoefficientFunction leaves its range at a point where the forms evaluate it.  A subclass of
    ValueError; its message starts with the datum's name and names the point.
    """


def _rule(order, shape):
    r"""Sampling points on a reference element of ``shape`` (TRIG or SEGM): the Gauss points of
    degrees :math:`2p - 2, \dots, 2p + 2` (the forms' rules; on edges :math:`2p + 1` is the contact rule), the edges'
    Gauss points and the vertices."""
    degrees = range(max(2 * order - 2, 0), 2 * order + 3)
    gauss = [tuple(p)[0] for d in degrees for p in ngs.IntegrationRule(ngs.SEGM, d).points]
    if shape == ngs.SEGM:
        points = [(t,) for t in gauss] + [(0.0,), (1.0,)]
    else:
        points = [tuple(p)[:2] for d in degrees for p in ngs.IntegrationRule(ngs.TRIG, d).points]
        for (a, b), (c, d) in (((0, 0), (1, 0)), ((1, 0), (0, 1)), ((0, 1), (0, 0))):
            points += [(a + t * (c - a), b + t * (d - b)) for t in gauss]
        points += [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
    points = list(dict.fromkeys(points))
    return {shape: ngs.IntegrationRule(points, [0.0] * len(points))}


# the data checked on the volume and on each boundary part, with their bounds (ngdgfric.bounds.DATA)
VOLUME = {name: datum for name, datum in DATA.items() if datum.part == "region"}
BOUNDARY = {part: {name: datum for name, datum in DATA.items() if datum.part == part and datum.kind != "number"}
            for part in ("traction", "dirichlet", "contact")}


def check_data(problem, mesh, order):
    r"""ValueError naming the datum and a point unless every CoefficientFunction datum is finite
    (and :math:`E > 0`, :math:`-1 < \nu < 1/2`, :math:`c_n \ge 0`, :math:`c_\tau \ge 0`) at the points where the
    forms of order ``order`` use it."""
    if _varying(problem, VOLUME):
        _check_on(problem, VOLUME, mesh.MapToAllElements(_rule(order, ngs.TRIG), ngs.VOL), "Omega")
    for part, data in BOUNDARY.items():
        if not _varying(problem, data):
            continue
        for name in problem.sides(part):
            if name in mesh.GetBoundaries():
                points = mesh.MapToAllElements(_rule(order, ngs.SEGM), mesh.Boundaries(pattern([name])))
                _check_on(problem, data, points, f"the boundary {name!r}")


def _as_cf(value):
    """A datum as a CoefficientFunction, or None if it is made of numbers only (checked on creation)."""
    if isinstance(value, ngs.CoefficientFunction):
        return value
    if isinstance(value, (tuple, list)) and any(isinstance(c, ngs.CoefficientFunction) for c in value):
        return ngs.CF(tuple(value))
    return None


def _varying(problem, data):
    return any(_as_cf(getattr(problem, name)) is not None for name in data)


def _check_on(problem, data, points, where):
    for name, datum in data.items():
        cf = _as_cf(getattr(problem, name))
        if cf is None:
            continue
        values = np.asarray(cf(points)).reshape(len(points), -1)
        rows = np.flatnonzero(np.any(datum.bad(values), axis=1))
        if rows.size:
            k = int(rows[0])
            x, y = float(ngs.x(points[k])), float(ngs.y(points[k]))
            shown = float(values[k, 0]) if values.shape[1] == 1 else tuple(map(float, values[k]))
            raise DataError(f"{name} must be {datum.requirement()} on {where}, got {shown} at ({x:.6g}, {y:.6g})")


def _size(orders, elements):
    """(DOFs, bytes by the memory model above MEMORY_BUDGET) of elements of ``orders``, or of
    ``elements`` elements of the one order ``orders``."""
    n = element_dofs(np.asarray(orders, dtype=float))
    count = 1.0 if elements is None else float(elements)
    return float(np.sum(n)) * count, float(np.sum(n * (1000 + 270 * n))) * count


def estimated_bytes(orders, elements=None):
    """Peak memory of a solve with element orders ``orders`` (or ``elements`` elements of the one
    order ``orders``), by the model above MEMORY_BUDGET."""
    return _size(orders, elements)[1]


def check_size(orders, max_ndof=None, elements=None, max_bytes=MEMORY_BUDGET):
    """ValueError before assembly if the DOFs of elements of ``orders`` exceed ``max_ndof``, or, for
    ``max_ndof=None``, if the estimated memory exceeds ``max_bytes`` (bytes; default ``MEMORY_BUDGET``, 8 GB;
    the memory model: ``estimated_bytes``).  With ``elements``, ``orders`` is one order p for that many
    elements (an estimate before meshing)."""
    optional(positive_integer)(max_ndof, "max_ndof")
    positive_number(max_bytes, "max_bytes")
    ndof, memory = _size(orders, elements)
    if max_ndof is None:
        if memory > max_bytes:
            allowed = "allowed by default" if max_bytes == MEMORY_BUDGET else f"allowed by max_bytes = {max_bytes:g}"
            raise ValueError(f"{ndof:.4g} DOFs would need about {memory / 1e9:.3g} GB, more than the "
                             f"{max_bytes / 1e9:g} GB {allowed}; pass max_ndof={ndof:.0f} "
                             f"(CLI: --max-ndof) to allow it")
    elif ndof > max_ndof:
        raise ValueError(f"{ndof:.4g} DOFs (about {memory / 1e9:.3g} GB) is more than max_ndof = {max_ndof}")


def check_solution(value, name, reference=False):
    """ValueError naming argument ``name`` unless ``value`` is a :class:`~ngdgfric.Solution` (duck-typed: its
    ``problem``, ``mesh``, ``u`` and ``discretization``), or with ``reference`` also a :class:`~ngdgfric.Reference`
    (``problem``, ``mesh`` and ``u``); an :class:`~ngdgfric.Adaptation` is pointed to its ``solution``."""
    needs = ("problem", "mesh", "u") if reference else ("problem", "mesh", "u", "discretization")
    if all(hasattr(value, key) for key in needs):
        return
    what = "a Solution of ngdgfric.solve" + (" or a Reference" if reference else "")
    hint = "; an Adaptation holds its last one as .solution" if hasattr(value, "solution") else ""
    raise ValueError(f"{name} must be {what}, got {shown(value)}{hint}")


def shown(value):
    """A bad argument as a message shows it: numbers, strings, None and containers by their (shortened) repr, any
    other object by its type."""
    if value is None or isinstance(value, (Real, str, bytes, tuple, list, dict)):
        return reprlib.repr(value)
    name = type(value).__name__
    return f"{'an' if name[0].lower() in 'aeiou' else 'a'} {name}"


def positive_number(value, name):
    """A finite real number > 0."""
    if not isinstance(value, Real) or isinstance(value, bool) or not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")


def nonnegative_number(value, name):
    """A finite real number >= 0."""
    if not isinstance(value, Real) or isinstance(value, bool) or not np.isfinite(value) or value < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")


def positive_integer(value, name):
    """An integer >= 1."""
    if not isinstance(value, Integral) or isinstance(value, bool) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")


def callback(value, name):
    """None or a callable."""
    if value is not None and not callable(value):
        raise ValueError(f"{name} must be callable or None, got {value!r}")


def choice(*choices):
    """A check accepting one of ``choices``."""
    def check(value, name):
        if value not in choices:
            raise ValueError(f"{name} must be one of {list(choices)}, got {value!r}")
    return check


def optional(check):
    """``check``, or None."""
    def check_optional(value, name):
        if value is not None:
            check(value, name)
    return check_optional
