"""Problem data of the frictional contact problem (1.4)-(1.10) with normal compliance.

A :class:`ContactProblem` is a frozen dataclass of numbers and NGSolve
CoefficientFunctions of ``x, y``; it also carries its geometry (a polygon whose
sides are labelled as Gamma_D, Gamma_F or Gamma_C) so that meshes can be built
from it.  Validation runs in ``__post_init__``, so ``dataclasses.replace``
checks the new values too.
"""

import math
from dataclasses import dataclass, field
from numbers import Real

import ngsolve as ngs

from .geometry import check_polygon

__all__ = ["ContactProblem", "Polygon", "strain", "strain_of", "stress", "von_mises", "coefficient", "is_number"]


def coefficient(value):
    """A datum of the problem as a CoefficientFunction: a number, a pair (f_x, f_y) of data or a
    CoefficientFunction (returned as is)."""
    if isinstance(value, ngs.CoefficientFunction):
        return value
    return ngs.CF(tuple(value)) if isinstance(value, (tuple, list)) else ngs.CF(value)


def is_number(value):
    """Whether a datum is a (real, non-boolean) number rather than a CoefficientFunction or anything else."""
    return isinstance(value, Real) and not isinstance(value, bool)


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
    """A datum is a finite real number or a scalar CoefficientFunction (checked pointwise by
    :func:`ngdgfric.checks.check_data` on a mesh)."""
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


def _check_number(name, value, low=None, high=None, low_open=False, high_open=True):
    """A finite number in [low, high) (or with the given open/closed ends); CFs are checked later, pointwise."""
    if not is_number(value):
        return
    _finite(name, value)
    if low is not None and (value < low or (low_open and value == low)):
        bound = f"> {low}" if low_open else f">= {low}"
        raise ValueError(f"{name} must be {bound}, got {value!r}")
    if high is not None and (value > high or (high_open and value == high)):
        bound = f"< {high}" if high_open else f"<= {high}"
        raise ValueError(f"{name} must be {bound}, got {value!r}")


def _point(k, vertex):
    """vertices[k] as a pair of floats (ValueError naming it otherwise)."""
    try:
        x, y = vertex
        return float(x), float(y)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"vertices[{k}] must be a pair of numbers (x, y), got {vertex!r}") from None


@dataclass(frozen=True)
class Polygon:
    """A polygonal domain Omega, vertices counter-clockwise.

    Validated on construction (:func:`ngdgfric.geometry.check_polygon`): finite, at least 3
    vertices, no (near-)duplicates, a simple polygon, counter-clockwise.

    ``labels[i]`` names the side from ``vertices[i]`` to ``vertices[i+1]`` (cyclic);
    each label is one of the problem's boundary names.
    """

    vertices: tuple
    labels: tuple

    def __post_init__(self):
        vertices = tuple(_point(k, vertex) for k, vertex in enumerate(self.vertices))
        labels = tuple(str(label) for label in self.labels)
        object.__setattr__(self, "vertices", vertices)
        object.__setattr__(self, "labels", labels)
        check_polygon(vertices)
        if len(labels) != len(vertices):
            raise ValueError(f"a polygon needs one label per side: {len(vertices)} sides, {len(labels)} labels")
        if self.signed_area <= 0:
            raise ValueError("polygon vertices must be counter-clockwise and enclose a positive area")

    @classmethod
    def rectangle(cls, x0, y0, x1, y1, bottom, right, top, left):
        """The rectangle (x0, x1) x (y0, y1) with its four sides labelled."""
        if not (x1 > x0 and y1 > y0):
            raise ValueError(f"rectangle needs x0 < x1 and y0 < y1, got ({x0}, {y0}, {x1}, {y1})")
        return cls(((x0, y0), (x1, y0), (x1, y1), (x0, y1)), (bottom, right, top, left))

    @property
    def signed_area(self):
        (x0, y0), v = self.vertices[0], self.vertices  # relative to a vertex: exact far from the origin too
        return 0.5 * sum((v[i - 1][0] - x0) * (v[i][1] - y0) - (v[i][0] - x0) * (v[i - 1][1] - y0)
                         for i in range(len(v)))

    @property
    def is_rectangle(self):
        """True for an axis-parallel rectangle given as by :meth:`rectangle`."""
        if len(self.vertices) != 4:
            return False
        (a, b), (c, d), (e, f), (g, h) = self.vertices
        return b == d and c == e and f == h and g == a and c > a and f > b

    @property
    def bounds(self):
        """(x0, y0, x1, y1) of the bounding box."""
        xs = [x for x, _ in self.vertices]
        ys = [y for _, y in self.vertices]
        return min(xs), min(ys), max(xs), max(ys)


# the data of ContactProblem in the order they are checked: (kind, low, low_open, high); kind "scalar"
# (a number or a scalar CoefficientFunction), "number" (a number only) or "vector"; a number must lie
# in [low, high) ((low, high) if low_open; None: no bound), a CoefficientFunction is checked pointwise later
_DATA = {"E": ("scalar", 0, True, None), "nu": ("scalar", -1, True, 0.5), "f": ("vector", None, False, None),
         "g": ("vector", None, False, None), "c_n": ("scalar", 0, False, None), "m_n": ("number", 1, False, None),
         "g_a": ("scalar", None, False, None), "c_tau": ("scalar", 0, False, None), "m_t": ("number", 0, False, None)}


@dataclass(frozen=True)
class ContactProblem:
    """Data of problem (1.4): the reduced law (1.10) for m_t = 0 (Section 1).

    Every datum may be a number or an NGSolve CoefficientFunction of ``x, y``;
    ``f`` and ``g`` are pairs or 2-vector CoefficientFunctions.

    E, nu:     Young's modulus and Poisson ratio (Lame parameters ``mu``, ``lam`` by Section 6); where they
               vary, the forms take them element by element (:mod:`ngdgfric.material`).
    f:         body force in Omega (1.5).
    g:         traction on Gamma_F (1.7).
    c_n, m_n:  normal compliance sigma_n = -c_n (u_n - g_a)_+^{m_n} on Gamma_C (1.8), m_n >= 1.
    g_a:       initial gap on Gamma_C.
    c_tau:     friction coefficient on Gamma_C: the friction bound of (1.9) is c_tau (u_n - g_a)_+^{m_t}.
    m_t:       exponent of the friction bound, m_t >= 0; m_t = 0 is the reduced law (1.10) of the paper,
               m_t > 0 makes (1.4) a quasi-variational inequality (bound 0 where there is no contact).
    geometry:  the polygon with its sides labelled by the boundary names below.
    """

    E: object
    nu: float
    f: object
    g: object
    c_n: object
    m_n: float
    g_a: object
    c_tau: object
    geometry: Polygon
    dirichlet: str = "dirichlet"
    traction: str = "traction"
    contact: str = "contact"
    m_t: float = 0.0
    name: str = field(default="contact problem", compare=False)

    def __post_init__(self):
        for name, (kind, low, low_open, high) in _DATA.items():
            value = getattr(self, name)
            if kind == "vector":
                _check_vector(name, value)
                continue
            if kind == "scalar":
                _check_scalar(name, value)
            elif not is_number(value):
                raise ValueError(f"{name} must be a number, got {value!r}")
            _check_number(name, value, low=low, low_open=low_open, high=high)
        if not isinstance(self.geometry, Polygon):
            raise ValueError(f"geometry must be a Polygon, got {self.geometry!r}")
        names = (self.dirichlet, self.traction, self.contact)
        if len(set(names)) != 3:
            raise ValueError(f"boundary names must be distinct, got {names}")
        for label in self.geometry.labels:
            if label not in names:
                raise ValueError(f"geometry side label {label!r} is not one of the boundary names {names}")
        for part, label in (("dirichlet", self.dirichlet), ("contact", self.contact)):
            if label not in self.geometry.labels:
                raise ValueError(f"geometry has no side labelled {label!r} ({part} boundary)")

    @property
    def mu(self):
        """Lame parameter mu = E / (2 (1 + nu)) (Section 6)."""
        return self.E / (2 * (1 + self.nu))

    @property
    def lam(self):
        """Lame parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) (Section 6)."""
        return self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))

    def boundary_names(self):
        """(dirichlet, traction, contact)."""
        return self.dirichlet, self.traction, self.contact


def strain(w):
    """eps(w) = (grad w + grad w^T)/2, (1.1), of a GridFunction or a trial/test function."""
    return ngs.Sym(ngs.Grad(w))


def strain_of(u):
    """eps(u) of a CoefficientFunction u of x, y (an exact solution), by symbolic differentiation."""
    g = ngs.CF((u[0].Diff(ngs.x), u[0].Diff(ngs.y), u[1].Diff(ngs.x), u[1].Diff(ngs.y)), dims=(2, 2))
    return 0.5 * (g + g.trans)


def stress(law, e):
    """sigma = C e = lam tr(e) I + 2 mu e for a strain e, (1.3); ``law``: anything with Lame parameters
    ``mu`` and ``lam`` (a :class:`ContactProblem`, or :class:`ngdgfric.material.Material` element by element)."""
    return 2 * law.mu * e + law.lam * ngs.Trace(e) * ngs.Id(2)


def von_mises(law, u):
    """Von Mises stress of sigma(u) (1.3) in plane strain, sigma_zz = lam tr eps(u) (``law`` as in :func:`stress`)."""
    e = strain(u)
    s = stress(law, e)
    sxx, syy, sxy, szz = s[0, 0], s[1, 1], s[0, 1], law.lam * ngs.Trace(e)
    return ngs.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy**2)
