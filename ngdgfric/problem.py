r"""Problem data of the frictional contact problem (1.4)-(1.10) with normal compliance.

A :class:`~ngdgfric.ContactProblem` is a frozen dataclass of numbers and NGSolve
CoefficientFunctions of ``x, y``; it also carries its geometry (a :class:`~ngdgfric.Polygon`, or a
:class:`~ngdgfric.Domain` with regions, holes and circular arcs) whose sides are named, and which
names belong to :math:`\Gamma_D` (prescribed displacement :math:`u_D`), :math:`\Gamma_F` (traction :math:`g`),
:math:`\Gamma_C` (contact) and the symmetry sides (:math:`u \cdot n = 0`, no tangential traction).  Data may be
given per named part: a dict ``{region: value}`` for ``E``, ``nu``, ``f``, a dict ``{side: value}`` for ``g``,
``u_D`` and the contact data ``c_n``, ``g_a``, ``c_tau``; on a mesh they become CoefficientFunctions
(:meth:`ngdgfric.ContactProblem.on`), so the forms see one datum each.  Validation runs in ``__post_init__``,
so ``dataclasses.replace`` checks the new values too.
"""

import dataclasses
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from .bounds import DATA, Datum, check_datum, coefficient, is_number
from .domain import Geometry, Loop
from .geometry import check_polygon

__all__ = ["ContactProblem", "ContactPair", "Polygon", "PerSide", "exponents", "pattern", "PARTS", "strain",
           "strain_of", "stress", "von_mises", "coefficient", "is_number"]


def _point(k, vertex):
    """vertices[k] as a pair of floats (ValueError naming it otherwise)."""
    try:
        x, y = vertex
        return float(x), float(y)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"vertices[{k}] must be a pair of numbers (x, y), got {vertex!r}") from None


@dataclass(frozen=True)
class Polygon(Geometry):
    r"""A polygonal domain, vertices counter-clockwise (one region, named "omega").

    The domain :math:`\Omega` of the paper's examples.  Validated on construction (``check_polygon`` of
    :mod:`ngdgfric.geometry`): finite, at least 3 vertices, no (near-)duplicates, a simple polygon,
    counter-clockwise.

    Parameters
    ----------
    vertices : sequence of (float, float)
        The corners, counter-clockwise; stored as a tuple of pairs of floats.
    labels : sequence of str
        ``labels[i]`` names the side from ``vertices[i]`` to ``vertices[i+1]`` (cyclic); each label is one of
        the problem's boundary names.

    Raises
    ------
    ValueError
        If a vertex is not a pair of numbers, the polygon is not simple or not counter-clockwise, or the
        number of labels is not the number of sides.

    See Also
    --------
    ngdgfric.Domain : Regions with curved sides, holes and interfaces.

    Examples
    --------
    >>> square = ndf.Polygon.rectangle(0, 0, 1, 1, "contact", "dirichlet", "traction", "traction")
    >>> square.labels
    ('contact', 'dirichlet', 'traction', 'traction')
    """

    vertices: tuple
    labels: tuple
    kind = "polygon"

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
        object.__setattr__(self, "_loop", Loop(vertices, labels))

    @property
    def region_loops(self):
        """The polygon as the one region ``"omega"`` of a geometry, ``(("omega", Loop(vertices, labels)),)``."""
        return (("omega", self._loop),)

    @property
    def area(self):
        return self.signed_area

    @classmethod
    def rectangle(cls, x0, y0, x1, y1, bottom, right, top, left):
        r"""The rectangle :math:`(x_0, x_1) \times (y_0, y_1)` with its four sides labelled.

        Parameters
        ----------
        x0, y0 : float
            The lower left corner.
        x1, y1 : float
            The upper right corner (``x1 > x0``, ``y1 > y0``).
        bottom, right, top, left : str
            The labels of the four sides.

        Returns
        -------
        Polygon
            The rectangle, vertices counter-clockwise from ``(x0, y0)``.
        """
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
        """True for an axis-parallel rectangle given as by :meth:`ngdgfric.Polygon.rectangle`."""
        if len(self.vertices) != 4:
            return False
        (a, b), (c, d), (e, f), (g, h) = self.vertices
        return b == d and c == e and f == h and g == a and c > a and f > b

    @property
    def bounds(self):
        """``(x0, y0, x1, y1)`` of the bounding box."""
        xs = [x for x, _ in self.vertices]
        ys = [y for _, y in self.vertices]
        return min(xs), min(ys), max(xs), max(ys)


# boundary parts: where a dict may leave a side out, its value there (zero traction, zero displacement);
# "pair": the sides of the contact pairs (two bodies in contact, ContactPair)
PARTS = ("dirichlet", "traction", "contact", "symmetry", "pair")
_OPTIONAL = {"traction": (0.0, 0.0), "dirichlet": (0.0, 0.0)}


def _names(part, value):
    """A boundary part's names as a tuple: one name or a sequence of names."""
    names = (value,) if isinstance(value, str) else value
    try:
        names = tuple(names)
    except TypeError:
        raise ValueError(f"{part} must be a side name or a list of side names, got {value!r}") from None
    for name in names:
        if not isinstance(name, str) or not name:
            raise ValueError(f"{part}: side names must be non-empty strings, got {name!r}")
    return names


def pattern(names):
    """The NGSolve region pattern (a regular expression) that selects exactly the sides ``names``."""
    special = set(".^$|?*+()[]{}\\")
    return "|".join("".join("\\" + c if c in special else c for c in name) for name in names)


@dataclass(frozen=True)
class PerSide:
    """A number per contact side on a mesh (the exponents :math:`m_n`, :math:`m_t` given as dicts, made by
    :meth:`ngdgfric.ContactProblem.on`): ``entries`` holds (side, value, indicator) with the order-0 facet function
    that is 1 on the side's edges."""

    entries: tuple

    def values(self):
        return [value for _, value, _ in self.entries]

    def combine(self, law):
        r"""The sum over the sides of indicator :math:`\times` ``law(value)``: a law written for one exponent, side by
        side."""
        return sum(indicator * law(value) for _, value, indicator in self.entries)

    def at(self, names):
        """The values at points on the sides ``names`` (a sequence of side names), as an array."""
        table = {side: value for side, value, _ in self.entries}
        return np.array([table[name] for name in names], dtype=float)


def exponents(value):
    """The values of an exponent :math:`m_n` or :math:`m_t`: a number, a dict {side: number} or a ``PerSide``, as a
    list."""
    if isinstance(value, PerSide):
        return value.values()
    return list(value.values()) if isinstance(value, dict) else [value]


@dataclass(frozen=True)
class ContactPair:
    r"""Two bodies in contact: side ``side`` of one body meets side ``other`` of another.

    The relative displacement :math:`[u] = u^1 - u^2 \circ \pi` at the points of ``side`` (:math:`\pi`: the
    closest point of ``other``) takes the place of :math:`u` in the laws (1.8)-(1.9), with the outward normal
    :math:`n` and the tangent :math:`t = (-n_y, n_x)` of ``side`` and the gap :math:`g = |x - \pi(x)|` measured
    along :math:`n` from the geometry, plus the offset ``g_a``: :math:`[u] \cdot n - (g + g_a)` is the
    penetration (:mod:`ngdgfric.contact.pairing`).  The forces act on both bodies, opposite (action and reaction).

    Parameters
    ----------
    side : str
        The side whose points carry the law (the "slave" side of the contact literature).
    other : str
        The side of the other body that it meets.
    c_n : float
        Normal compliance coefficient of the pair, :math:`c_n \ge 0` (1.8).
    m_n : float, optional
        Exponent of the normal compliance, :math:`m_n \ge 1`.  Default 1.
    c_tau : float, optional
        Friction coefficient, :math:`c_\tau \ge 0` (1.9).  Default 0: no friction.
    m_t : float, optional
        Exponent of the friction bound, :math:`m_t \ge 0`.  Default 0: the reduced law (1.10).
    g_a : float, optional
        An offset added to the geometric gap (negative: an initial overlap, a press fit).  Default 0.
    reach : float or None, optional
        The largest distance at which a point of ``side`` finds ``other``: farther points never touch it.  Default
        None: a tenth of the domain's diameter.

    Examples
    --------
    >>> pair = ndf.ContactPair("punch_bottom", "plate_top", c_n=1e4, c_tau=0.3)
    >>> pair.m_n, pair.g_a
    (1.0, 0.0)
    """

    side: str
    other: str
    c_n: float
    m_n: float = 1.0
    c_tau: float = 0.0
    m_t: float = 0.0
    g_a: float = 0.0
    reach: float = None

    def __post_init__(self):
        for name in ("side", "other"):
            if not isinstance(getattr(self, name), str) or not getattr(self, name):
                raise ValueError(f"ContactPair.{name} must be a side name, got {getattr(self, name)!r}")
        if self.side == self.other:
            raise ValueError(f"a contact pair needs two sides, got {self.side!r} twice")
        for name in ("c_n", "m_n", "g_a", "c_tau", "m_t"):
            check_datum(f"ContactPair.{name}", _PAIR_DATA[name], getattr(self, name))
            object.__setattr__(self, name, float(getattr(self, name)))
        if self.reach is not None:
            check_datum("ContactPair.reach", Datum("number", "pair", 0, True), self.reach)
            object.__setattr__(self, "reach", float(self.reach))

    def swapped(self):
        """The same pair with the roles of the two sides exchanged."""
        return dataclasses.replace(self, side=self.other, other=self.side)


_PAIR_DATA = {name: dataclasses.replace(DATA[name], kind="number") for name in ("c_n", "m_n", "g_a", "c_tau", "m_t")}


@dataclass(frozen=True)
class ContactProblem:
    r"""Data of problem (1.4) with the laws (1.8)-(1.9): :math:`m_t = 0` (the reduced law (1.10)) or :math:`m_t > 0`.

    Every datum may be a number or an NGSolve CoefficientFunction of ``x, y``; ``f``, ``g`` and ``u_D`` are
    pairs or 2-vector CoefficientFunctions.  ``E``, ``nu`` and ``f`` may also be dicts ``{region name: value}``
    (regions of a :class:`~ngdgfric.Domain`; a :class:`~ngdgfric.Polygon` has one, ``"omega"``), ``g`` a dict
    ``{traction side: value}`` (sides left out are free, :math:`g = 0`), ``u_D`` a dict
    ``{Dirichlet side: value}`` (left out: :math:`u_D = 0`), ``c_n``, ``g_a`` and ``c_tau`` dicts
    ``{contact side: value}``; on a mesh they become CoefficientFunctions (:meth:`~ngdgfric.ContactProblem.on`),
    and every region's interfaces are edges of the mesh, so the forms take each region's own material
    (:mod:`ngdgfric.dg.material`).

    Parameters
    ----------
    E : float, CoefficientFunction or dict
        Young's modulus, :math:`E > 0`; with ``nu`` it gives the Lamé parameters :attr:`~ngdgfric.ContactProblem.mu` and
        :attr:`~ngdgfric.ContactProblem.lam`
        (Section 6).  Where it varies, the forms take it element by element (:mod:`ngdgfric.dg.material`).
    nu : float, CoefficientFunction or dict
        Poisson's ratio, :math:`-1 < \nu < 1/2`.
    f : pair, CoefficientFunction or dict
        Body force in :math:`\Omega`, (1.5).
    g : pair, CoefficientFunction or dict
        Traction on :math:`\Gamma_F`, (1.7).
    c_n : float, CoefficientFunction or dict
        Normal compliance coefficient, :math:`c_n \ge 0`: on :math:`\Gamma_C`,
        :math:`\sigma_n = -c_n (u_n - g_a)_+^{m_n}`, (1.8).
    m_n : float or dict
        Exponent of the normal compliance, :math:`m_n \ge 1`.
    g_a : float, CoefficientFunction or dict
        Initial gap on :math:`\Gamma_C`.
    c_tau : float, CoefficientFunction or dict
        Friction coefficient on :math:`\Gamma_C`, :math:`c_\tau \ge 0`: the friction bound of (1.9) is
        :math:`c_\tau (u_n - g_a)_+^{m_t}`.
    geometry : Polygon or Domain
        The domain, whose sides carry the names of ``dirichlet``, ``traction``, ``contact`` and ``symmetry``.
    dirichlet : str or sequence of str, optional
        The side names of :math:`\Gamma_D`, where :math:`u = u_D`, (1.6).  Default ``"dirichlet"``.
    traction : str or sequence of str, optional
        The side names of :math:`\Gamma_F`, where :math:`\sigma n = g`, (1.7).  Default ``"traction"``.
    contact : str or sequence of str, optional
        The side names of :math:`\Gamma_C`, (1.8)-(1.9); several sides are allowed.  Default ``"contact"``.
    m_t : float or dict, optional
        Exponent of the friction bound, :math:`m_t \ge 0`; :math:`m_t = 0` is the reduced law (1.10) of the
        paper, :math:`m_t > 0` makes (1.4) a quasi-variational inequality (bound 0 where there is no contact).
        Default ``0.0``.
    name : str, optional
        A name for reports and plots (not compared by ``==``).  Default ``"contact problem"``.
    symmetry : str or sequence of str, optional
        The side names of the symmetry (roller) sides, :math:`u \cdot n = 0` and :math:`(\sigma n) \cdot t = 0`.
        Default ``()``: none.  Every side of the geometry has one of the four conditions.
    u_D : pair, CoefficientFunction or dict, optional
        The prescribed displacement on :math:`\Gamma_D`.  Default ``(0.0, 0.0)`` (the paper's).
    pairs : sequence of ContactPair, optional
        Contact between two bodies of the geometry (regions joined by interfaces are a body,
        ``Domain.bodies``): each :class:`~ngdgfric.ContactPair` names a side of one body and a side of
        another.  With pairs, ``dirichlet`` and ``contact`` may be empty: a body held by contact and symmetry
        sides only is solved wherever the contact holds it.  Default ``()``: one body against the foundation.

    Raises
    ------
    ValueError
        If a datum is out of its range, a dict names an unknown region or side (or misses one), a side name is
        in two boundary parts, or a side of the geometry has no condition.

    See Also
    --------
    ngdgfric.load_problem : The same data written as a TOML file.
    ngdgfric.example : The paper's examples and the shipped scenes.

    Examples
    --------
    A unit square pressed down onto the foundation along its bottom side:

    >>> square = ndf.Polygon.rectangle(0, 0, 1, 1, "contact", "dirichlet", "traction", "traction")
    >>> problem = ndf.ContactProblem(E=2000.0, nu=0.3, f=(0.0, 0.0), g=(0.0, -100.0), c_n=1.0, m_n=1.0,
    ...                              g_a=0.0, c_tau=100.0, geometry=square)
    >>> print(f"mu = {problem.mu:.1f}, lam = {problem.lam:.1f}")
    mu = 769.2, lam = 1153.8
    >>> sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
    """

    E: object
    nu: float
    f: object
    g: object
    c_n: object
    m_n: float
    g_a: object
    c_tau: object
    geometry: Geometry
    dirichlet: object = "dirichlet"
    traction: object = "traction"
    contact: object = "contact"
    m_t: float = 0.0
    name: str = field(default="contact problem", compare=False)
    symmetry: object = ()
    u_D: object = (0.0, 0.0)
    pairs: tuple = ()

    def __post_init__(self):
        if not isinstance(self.geometry, Geometry):
            raise ValueError(f"geometry must be a Polygon or a Domain, got {self.geometry!r}")
        self._check_pairs()
        for part in PARTS[:-1]:
            object.__setattr__(self, part, _names(part, getattr(self, part)) if part == "symmetry"
                               else self._group(part))
        seen = {}
        for part in PARTS:
            for name in self.sides(part):
                if name in seen:
                    raise ValueError(f"side name {name!r} is in both {seen[name]} and {part}: boundary names "
                                     f"must be distinct")
                seen[name] = part
        for label in self.geometry.side_names:
            if label not in seen:
                raise ValueError(f"geometry side label {label!r} is not one of the boundary names "
                                 f"{tuple(seen)}: give it a condition (dirichlet, traction, contact or symmetry)")
        for part in ("dirichlet", "contact"):
            present = [name for name in self.sides(part) if name in self.geometry.side_names]
            if not present and self.sides(part):
                raise ValueError(f"geometry has no side labelled {' or '.join(map(repr, self.sides(part)))} "
                                 f"({part} boundary)")
        for name, datum in DATA.items():  # the bounds of the data: ngdgfric.bounds
            value = getattr(self, name)
            if isinstance(value, dict):
                self._check_parts(name, datum.part, value)
                for key, item in value.items():
                    check_datum(f"{name}[{key!r}]", datum, item)
            elif not isinstance(value, PerSide):  # made by on() from checked numbers
                check_datum(name, datum, value)

    def _group(self, part):
        """The names of a boundary part as given: one name stays a str (the paper's problems), a list a tuple."""
        value = getattr(self, part)
        names = _names(part, value)
        if not names and part != "traction" and not self.pairs:
            raise ValueError(f"{part} needs at least one side name" + (
                " (a body held by contact pairs only needs pairs: ContactPair)" if part == "dirichlet" else ""))
        return value if isinstance(value, str) else names

    def _check_pairs(self):
        """``pairs`` as a tuple of ContactPair; ValueError for an unknown side, a side in two pairs, or a pair whose
        two sides belong to one body."""
        try:
            pairs = tuple(self.pairs)
        except TypeError:
            raise ValueError(f"pairs must be a sequence of ContactPair, got {self.pairs!r}") from None
        object.__setattr__(self, "pairs", pairs)
        seen = {}
        for k, pair in enumerate(pairs):
            if not isinstance(pair, ContactPair):
                raise ValueError(f"pairs[{k}] must be a ContactPair, got {pair!r}")
            for name in (pair.side, pair.other):
                if name not in self.geometry.side_names:
                    raise ValueError(f"pairs[{k}]: the geometry has no side {name!r}; its sides: "
                                     f"{list(self.geometry.side_names)}")
                if name in seen:
                    raise ValueError(f"pairs[{k}]: side {name!r} is in pairs[{seen[name]}] too: a side may be in one "
                                     f"contact pair only")
                seen[name] = k
            bodies = [self.geometry.body_of_side(name) for name in (pair.side, pair.other)]
            if bodies[0] == bodies[1]:
                raise ValueError(f"pairs[{k}]: sides {pair.side!r} and {pair.other!r} belong to one body (regions "
                                 f"{', '.join(map(repr, self.geometry.body_regions(bodies[0])))}): a pair joins two "
                                 f"bodies")
        paired = {tuple(sorted((pair.side, pair.other))) for pair in pairs}
        for a, b in sorted(self.geometry.touching - paired):
            raise ValueError(f"sides {a!r} and {b!r} of two bodies touch but are not a contact pair: make them a "
                             f"ContactPair, or glue the two regions (one shared side with the same end points, "
                             f"labelled alike)")

    def _check_parts(self, name, part, values):
        """ValueError unless the dict ``values`` of datum ``name`` is keyed by the names of ``part``."""
        known = self.geometry.region_names if part == "region" else self.sides(part)
        for key in values:
            if key not in known:
                raise ValueError(f"{name}: {key!r} is not a{'' if part == 'region' else ' ' + part} "
                                 f"{'region' if part == 'region' else 'side'}; known: {list(known)}")
        if part not in _OPTIONAL:
            missing = [key for key in known if key not in values]
            if missing:
                raise ValueError(f"{name} has no value for {'region' if part == 'region' else part + ' side'}"
                                 f"{'s' * (len(missing) > 1)} {', '.join(map(repr, missing))}")

    def sides(self, part):
        """The side names of a boundary part as a tuple.

        Parameters
        ----------
        part : str
            ``"dirichlet"``, ``"traction"``, ``"contact"``, ``"symmetry"`` or ``"pair"`` (both sides of every
            contact pair).

        Returns
        -------
        tuple of str
            The side names of that part (one name given as a str becomes a 1-tuple).
        """
        if part == "pair":
            return tuple(name for pair in self.pairs for name in (pair.side, pair.other))
        return _names(part, getattr(self, part))

    def where(self, part):
        """The NGSolve region pattern of a boundary part.

        Parameters
        ----------
        part : str
            ``"dirichlet"``, ``"traction"``, ``"contact"`` or ``"symmetry"``.

        Returns
        -------
        str
            A regular expression that selects exactly the part's sides:
            ``mesh.Boundaries(problem.where("contact"))``.
        """
        return pattern(self.sides(part))

    @property
    def per_part(self):
        """Whether some datum is given per region or per side (a dict).

        Then :meth:`~ngdgfric.ContactProblem.on` resolves it on a mesh.
        """
        return any(isinstance(getattr(self, name), dict) for name in DATA)

    def on(self, mesh):
        r"""This problem with every dict datum made a CoefficientFunction on ``mesh``.

        Per region a ``MaterialCF``, per side the sum of value :math:`\times` indicator of the side's edges (an
        order-0 facet function: NGSolve's ``BoundaryCF`` cannot be evaluated in the skeleton integrals of DG
        forms); the exponents :math:`m_n`, :math:`m_t` per side become a ``PerSide`` (one number if all sides
        have the same).

        Parameters
        ----------
        mesh : ngsolve.Mesh
            A mesh of the problem's domain.

        Returns
        -------
        ContactProblem
            The problem with data per part resolved; the problem itself if it has none
            (:attr:`~ngdgfric.ContactProblem.per_part`).
        """
        if not self.per_part:
            return self
        from .meshes import facet_indicator  # meshes imports this module

        changes = {}
        for name, datum in DATA.items():
            values, kind, part = getattr(self, name), datum.kind, datum.part
            if not isinstance(values, dict):
                continue
            if kind == "number":
                same = len(set(values.values())) == 1
                changes[name] = next(iter(values.values())) if same else PerSide(tuple(
                    (side, value, facet_indicator(mesh, pattern([side]))) for side, value in values.items()))
                continue
            if part == "region":
                if kind == "vector":
                    changes[name] = ngs.CF(tuple(mesh.MaterialCF({key: coefficient(value)[i]
                                                                  for key, value in values.items()})
                                                 for i in range(2)))
                else:
                    changes[name] = mesh.MaterialCF({key: coefficient(value) for key, value in values.items()})
                continue
            zero = 0 * coefficient(_OPTIONAL.get(part, 0.0))
            changes[name] = sum((coefficient(value) * facet_indicator(mesh, pattern([key]))
                                 for key, value in values.items()), zero)
        return dataclasses.replace(self, **changes)

    @property
    def mu(self):
        r"""Lamé parameter :math:`\mu = E / (2 (1 + \nu))` (Section 6)."""
        return self.E / (2 * (1 + self.nu))

    @property
    def lam(self):
        r"""Lamé parameter :math:`\lambda = E \nu / ((1 + \nu)(1 - 2 \nu))` (Section 6)."""
        return self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))

    def roles(self):
        """The boundary part of every side of the geometry.

        Returns
        -------
        dict
            ``{side label: part}``, the part one of ``"dirichlet"``, ``"traction"``, ``"contact"``, ``"symmetry"``
            (names of a part that no side of the geometry carries are left out).
        """
        labels = self.geometry.side_names
        return {name: part for part in PARTS for name in self.sides(part) if name in labels}

    def value_on(self, name, part):
        """The value of a datum on one region or side.

        Parameters
        ----------
        name : str
            A datum, e.g. ``"E"`` or ``"g"``.
        part : str
            A region name (``E``, ``nu``, ``f``) or a side name of the datum's boundary part.

        Returns
        -------
        object
            The datum's entry for ``part`` if it is a dict (zero for a traction or Dirichlet side it leaves out),
            else the datum itself.
        """
        value = getattr(self, name)
        if not isinstance(value, dict):
            return value
        return value[part] if part in value else _OPTIONAL[DATA[name].part]

    def boundary_names(self):
        """Every side name the problem gives a condition.

        Returns
        -------
        tuple of str
            The names in the order dirichlet, traction, contact, symmetry.
        """
        return tuple(name for part in PARTS for name in self.sides(part))


def strain(w):
    r""":math:`\epsilon(w) = (\nabla w + \nabla w^T)/2`, (1.1), of a GridFunction or a trial/test function."""
    return ngs.Sym(ngs.Grad(w))


def strain_of(u):
    r""":math:`\epsilon(u)` of a CoefficientFunction :math:`u` of ``x, y`` (an exact solution), by symbolic
    differentiation."""
    g = ngs.CF((u[0].Diff(ngs.x), u[0].Diff(ngs.y), u[1].Diff(ngs.x), u[1].Diff(ngs.y)), dims=(2, 2))
    return 0.5 * (g + g.trans)


def stress(law, e):
    r""":math:`\sigma = C e = \lambda \operatorname{tr}(e) I + 2 \mu e` for a strain :math:`e`, (1.3); ``law``:
    anything with Lamé parameters ``mu`` and ``lam`` (a :class:`~ngdgfric.ContactProblem`, or ``Material`` of
    :mod:`ngdgfric.dg.material` element by element)."""
    return 2 * law.mu * e + law.lam * ngs.Trace(e) * ngs.Id(2)


def von_mises(law, u):
    r"""Von Mises stress of :math:`\sigma(u)` (1.3) in plane strain, :math:`\sigma_{zz} = \lambda \operatorname{tr}
    \epsilon(u)` (``law`` as in ``stress``)."""
    e = strain(u)
    s = stress(law, e)
    sxx, syy, sxy, szz = s[0, 0], s[1, 1], s[0, 1], law.lam * ngs.Trace(e)
    return ngs.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy**2)
