r"""The data of problem (1.4)-(1.10) and their bounds, in one table (``DATA``).

:math:`E > 0` and :math:`-1 < \nu < 1/2` (Young's modulus and Poisson ratio, Section 6), :math:`c_n \ge 0` and
:math:`m_n \ge 1` (normal compliance (1.8)), :math:`c_\tau \ge 0` and :math:`m_t \ge 0` (friction bound (1.9));
the loads :math:`f` (1.5), :math:`g` (1.7), the prescribed displacement :math:`u_D` (1.6) and the gap :math:`g_a`
only finite.  :class:`~ngdgfric.ContactProblem` checks the numbers among them when it is made (``check_datum``),
``check_data`` of :mod:`ngdgfric.checks` the CoefficientFunctions pointwise on a mesh (``Datum.bad``), both from
this table.
"""

import math
from dataclasses import dataclass
from numbers import Real

import ngsolve as ngs
import numpy as np

__all__ = ["Datum", "DATA", "coefficient", "is_number", "check_datum"]


@dataclass(frozen=True)
class Datum:
    """One datum of the problem: ``kind`` "scalar" (a number or a scalar CoefficientFunction), "number" (a number
    only) or "vector" (a pair, or a 2-vector CoefficientFunction); ``part``: what a dict of its values is keyed by
    ("region", or the sides of a boundary part); its values must be finite and lie in [low, high) ((low, high)
    with ``low_open``; None: no bound)."""

    kind: str
    part: str
    low: float = None
    low_open: bool = False
    high: float = None

    def bad(self, values):
        """Where an array of values breaks the bounds (or is not finite): a boolean array."""
        bad = ~np.isfinite(values)
        if self.low is not None:
            bad |= (values <= self.low) if self.low_open else (values < self.low)
        if self.high is not None:
            bad |= values >= self.high
        return bad

    def requirement(self):
        """The bounds in words: "finite", "finite and > 0", "finite and > -1 and < 0.5", ..."""
        need = "finite" if self.low is None else f"finite and {'>' if self.low_open else '>='} {self.low:g}"
        return need + ("" if self.high is None else f" and < {self.high:g}")


# in the order they are checked
DATA = {"E": Datum("scalar", "region", 0, True), "nu": Datum("scalar", "region", -1, True, 0.5),
        "f": Datum("vector", "region"), "g": Datum("vector", "traction"), "u_D": Datum("vector", "dirichlet"),
        "c_n": Datum("scalar", "contact", 0), "m_n": Datum("number", "contact", 1), "g_a": Datum("scalar", "contact"),
        "c_tau": Datum("scalar", "contact", 0), "m_t": Datum("number", "contact", 0)}


def coefficient(value):
    """A datum of the problem as a CoefficientFunction: a number, a pair (f_x, f_y) of data or a
    CoefficientFunction (returned as is)."""
    if isinstance(value, ngs.CoefficientFunction):
        return value
    return ngs.CF(tuple(value)) if isinstance(value, (tuple, list)) else ngs.CF(value)


def is_number(value):
    """Whether a datum is a (real, non-boolean) number rather than a CoefficientFunction or anything else."""
    return isinstance(value, Real) and not isinstance(value, bool)


def check_datum(name, datum, value):
    """ValueError naming ``name`` unless ``value`` is of the :class:`Datum`'s kind and, if a number, within its
    bounds (CoefficientFunctions are checked later, pointwise: ``ngdgfric.checks.check_data``)."""
    if datum.kind == "vector":
        _check_vector(name, value)
        return
    if datum.kind == "scalar":
        _check_scalar(name, value)
    elif not is_number(value):
        raise ValueError(f"{name} must be a number, got {value!r}")
    if not is_number(value):
        return
    _finite(name, value)
    if datum.low is not None and (value < datum.low or (datum.low_open and value == datum.low)):
        raise ValueError(f"{name} must be {'>' if datum.low_open else '>='} {datum.low}, got {value!r}")
    if datum.high is not None and value >= datum.high:
        raise ValueError(f"{name} must be < {datum.high}, got {value!r}")


def _finite(name, value):
    """``value`` as a float, ValueError unless it is a finite real number."""
    try:
        number = float(value)
    except OverflowError:
        number = float("inf")
    if not math.isfinite(number):
        shown = repr(value) if len(repr(value)) <= 40 else f"{repr(value)[:20]}... ({len(repr(value))} digits)"
        raise ValueError(f"{name} must be a finite number, got {shown}")
    return number


def _check_scalar(name, value):
    """A datum is a finite real number or a real scalar CoefficientFunction."""
    if is_number(value):
        _finite(name, value)
        return
    if isinstance(value, ngs.CoefficientFunction):
        if value.dim == 1 and not value.is_complex:
            return
        value = f"a {'complex ' * value.is_complex}CoefficientFunction of dimension {value.dim}"
    else:
        value = repr(value)
    raise ValueError(f"{name} must be a real number or a real scalar CoefficientFunction, got {value}")


def _check_vector(name, value):
    """A vector datum is a pair of scalar data or a CoefficientFunction of dimension 2."""
    if isinstance(value, ngs.CoefficientFunction):
        if value.dim != 2 or value.is_complex:
            raise ValueError(f"{name} must have 2 real components, got a {'complex ' * value.is_complex}"
                             f"CoefficientFunction of dimension {value.dim}")
        return
    if isinstance(value, (tuple, list)) and len(value) == 2:
        for i, component in enumerate(value):
            _check_scalar(f"{name}[{i}]", component)
        return
    raise ValueError(f"{name} must be a pair (f_x, f_y) or a 2-vector CoefficientFunction, got {value!r}")
