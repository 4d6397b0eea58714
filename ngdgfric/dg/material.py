r"""The material law (1.1)-(1.3) as the DG forms see it: element by element, and across each edge.

:math:`\sigma = 2 \mu \epsilon + \lambda \operatorname{tr}(\epsilon) I` with the Lamé parameters of Section 6,
:math:`\mu = E / (2 (1 + \nu))` and :math:`\lambda = E \nu / ((1 + \nu)(1 - 2 \nu))`.  A facet term needs the
stress of each neighbour from its own side, but a CoefficientFunction such as ``IfPos(y - 0.5, E1, E0)``
evaluated on the interface :math:`y = 1/2` gives both neighbours the same branch, and the forms then mix the
materials (relative errors of 5 % to several 100 % on a piecewise linear solution that every method must
reproduce).  So data
that vary (:math:`E` or :math:`\nu` given as CoefficientFunctions) enter through :math:`\mu` and :math:`\lambda`
projected element by element into discontinuous fields (``element_fields``): the element's :math:`L^2` projection
of degree 0 where the data are constant on every element (a mesh that follows the jumps: exact), else of the
discretisation's degree :math:`p`.  Where they vary inside elements more than degree-:math:`p` polynomials can
follow (a jump that cuts elements) the element means are used and a :class:`~ngdgfric.MaterialWarning` names the
datum.

Across an interior edge :math:`e` with neighbours :math:`T^+` and :math:`T^-` the stresses are averaged with the
weights of Dryja (CMAM 3, 2003) and Ern, Stephansen & Zunino (IMA J. Numer. Anal. 29, 2009),

.. math::

    \{\sigma\}_w = w^+ \sigma^+ + w^- \sigma^-, \qquad
    w^\pm = \frac{k^\mp}{k^+ + k^-}, \qquad k = 2 \mu + \lambda,

and penalties scale with harmonic means :math:`2 a^+ a^- / (a^+ + a^-)` of the material on the two sides
(``Material.harmonic``), so that coercivity and accuracy do not depend on the contrast.  For constant data
:math:`w^\pm = 1/2` and the means are the data themselves: the paper's forms, number for number.
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..errors import warn
from ..problem import coefficient, is_number

__all__ = ["Material", "Lame", "EdgeCoefficient", "MaterialWarning", "element_fields", "largest", "RESOLVED"]

RESOLVED = 0.1
"""mu and lam count as represented by their degree-p projections on an element when these differ from them
by at most this fraction of the largest stress scale 2 mu + lam there (a jump by a factor r inside an
element leaves about (r - 1) / (2 r)); beyond it the element means are used and :class:`MaterialWarning`
is issued."""


class MaterialWarning(UserWarning):
    r"""A material datum varies inside elements more than the discretisation's polynomials can follow.

    Issued by :class:`~ngdgfric.Discretization` (so by :func:`ngdgfric.solve` too) where :math:`E` or :math:`\nu`,
    given as CoefficientFunctions, jump inside elements (a jump that the mesh does not follow): the element
    means of :math:`\mu` and :math:`\lambda` are used there (:mod:`ngdgfric.dg.material`) and convergence is slow
    (about :math:`h^{1/2}`).  The message names the data and a point; a mesh with edges along the jump avoids it.
    """


@dataclass(frozen=True)
class Lame:
    """Lame parameters ``mu`` and ``lam`` (numbers or CoefficientFunctions) seen from one side of an edge."""

    mu: object
    lam: object

    @property
    def stiffness(self):
        """k = 2 mu + lam: the scale of the stress (the weight of the averages, the coercivity thresholds)."""
        return 2 * self.mu + self.lam


@dataclass(frozen=True)
class EdgeCoefficient:
    """A coefficient of the edge terms: ``interior`` on interior edges (it may use the neighbour's values,
    ``Other()``), ``boundary`` on boundary edges (its element's values); numbers or CoefficientFunctions.
    ``text`` says what it is, for reports (``str()``)."""

    interior: object
    boundary: object
    text: str

    def __str__(self):
        return self.text

    def scaled(self, factor, text):
        """``factor`` (a number) times this coefficient, described by ``text``."""
        return EdgeCoefficient(factor * self.interior, factor * self.boundary, text)


MATERIAL_BONUS = 8
"""Extra quadrature degree of the projections and of the points that check them: data that jump inside an
element are integrated by many points, not by the few that a polynomial of the element's degree needs."""


def _evaluation_points(mesh, order):
    """Gauss points of degree 2 p + :data:`MATERIAL_BONUS` in every element, mapped (an element's points are
    consecutive)."""
    rule = ngs.IntegrationRule(ngs.TRIG, 2 * order + MATERIAL_BONUS)
    return mesh.MapToAllElements({ngs.TRIG: rule}, ngs.VOL), len(rule.weights)


def largest(value, mesh):
    """The largest value of a scalar datum: a number itself, a CoefficientFunction at the Gauss points of degree
    2 + :data:`MATERIAL_BONUS`, the vertices and the edge midpoints of every element of ``mesh`` (a datum
    largest at a vertex, where a linear one is, is seen there; Poisson's ratio for
    :func:`ngdgfric.adaptivity.choose_method` and the locking check of :class:`~ngdgfric.Discretization`, a stress
    scale for the penalty check)."""
    if is_number(value):
        return float(value)
    gauss = [tuple(point)[:2] for point in ngs.IntegrationRule(ngs.TRIG, 2 + MATERIAL_BONUS).points]
    corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.5, 0.0), (0.5, 0.5), (0.0, 0.5)]
    rule = ngs.IntegrationRule(gauss + corners, [0.0] * (len(gauss) + len(corners)))
    return float(np.max(np.asarray(value(mesh.MapToAllElements({ngs.TRIG: rule}, ngs.VOL)))))


def _projection(value, mesh, degree):
    """The element-wise L2 projection of ``value`` onto polynomials of ``degree`` (a GridFunction of L2)."""
    field = ngs.GridFunction(ngs.L2(mesh, order=degree))
    field.Set(value, bonus_intorder=MATERIAL_BONUS)
    return field


def _piecewise_constant(values, mesh):
    """The order-0 L2 GridFunction with the given value on every element."""
    field = ngs.GridFunction(ngs.L2(mesh, order=0))
    field.vec.FV().NumPy()[:] = values
    return field


def element_fields(problem, mesh, order):
    """mu and lam of ``problem`` as discontinuous fields on ``mesh`` (module docstring); returns
    (mu, lam, unresolved): GridFunctions of L2 of degree 0 if the data are constant on every element, of
    degree ``order`` if those projections follow mu and lam within :data:`RESOLVED` of 2 mu + lam on every
    element and keep C positive definite (mu > 0, mu + lam > 0), else of degree 0 (element means), with a
    :class:`MaterialWarning` naming the data that vary and ``unresolved`` the number of elements off."""
    data = (coefficient(problem.mu), coefficient(problem.lam))
    points, per_element = _evaluation_points(mesh, order)
    values = lambda cf: np.asarray(cf(points)).reshape(mesh.ne, per_element)  # noqa: E731
    exact = [values(cf) for cf in data]
    scale = np.maximum(np.max(np.abs(2 * exact[0] + exact[1]), axis=1), np.finfo(float).tiny)
    spread = np.max([np.ptp(value, axis=1) for value in exact], axis=0) / scale
    if np.all(spread <= 1e-12):  # constant on every element: its value (a projection on a curved element is
        return (*(_piecewise_constant(value[:, 0], mesh) for value in exact), 0)  # not exact to round-off)
    for degree in (0, order):
        fields = [_projection(cf, mesh, degree) for cf in data]
        mu, lam = (values(field) for field in fields)
        deviation = np.max(np.maximum(np.abs(mu - exact[0]), np.abs(lam - exact[1])), axis=1) / scale
        valid = np.all((mu > 0) & (mu + lam > 0), axis=1)
        if degree == order and np.all(deviation <= RESOLVED) and np.all(valid):
            return (*fields, 0)
    bad = np.flatnonzero((deviation > RESOLVED) | ~valid)
    worst = int(bad[np.argmax(deviation[bad])])
    x, y = (float(np.mean(values(c)[worst])) for c in (ngs.x, ngs.y))
    names = " and ".join(name for name in ("E", "nu") if not is_number(getattr(problem, name)))
    warn(f"{names} varies inside {bad.size} of {mesh.ne} elements more than polynomials of degree {order} "
                  f"follow (the stress scale off by up to {100 * float(deviation[worst]):.0f} % near ({x:.4g}, "
                  f"{y:.4g})): a jump that cuts elements?  The element means are used there; expect slow "
                  f"convergence (about h^(1/2)) unless the mesh follows the jump (edges along it)",
                  MaterialWarning)
    return _projection(data[0], mesh, 0), _projection(data[1], mesh, 0), bad.size


class Material:
    """The Lame parameters of ``problem`` element by element on ``mesh`` (module docstring).

    ``own``: the :class:`Lame` parameters of the element integrated over (numbers, or L2 GridFunctions);
    ``neighbour``: those of the element across an interior edge (``Other()``); ``constant``: E and nu are
    numbers (then ``own`` and ``neighbour`` hold the same numbers and nothing is projected);
    ``unresolved``: the number of elements on which varying data were replaced by their means; ``jumps``:
    the material differs across some interior edge (a jump along the mesh, or element means of one that
    cuts elements), so that stresses and the pressure jump there.
    """

    def __init__(self, problem, mesh, order):
        self.constant = is_number(problem.E) and is_number(problem.nu)
        self.unresolved, self.jumps = 0, False
        if self.constant:
            self.own = self.neighbour = Lame(problem.mu, problem.lam)
            return
        mu, lam, self.unresolved = element_fields(problem, mesh, order)
        self.own = Lame(mu, lam)
        self.neighbour = Lame(mu.Other(), lam.Other())
        if mu.space.globalorder == 0:  # (an expression with Other() is 0 on boundary edges: interior ones count)
            jump = self.own.stiffness - self.neighbour.stiffness
            scale = ngs.Integrate(self.own.stiffness**2 * ngs.dx(element_boundary=True), mesh)
            self.jumps = bool(ngs.Integrate(jump * jump * ngs.dx(element_boundary=True), mesh) > 1e-20 * scale)

    @property
    def mu(self):
        """mu of the element integrated over."""
        return self.own.mu

    @property
    def lam(self):
        """lam of the element integrated over."""
        return self.own.lam

    def average(self, own, neighbour):
        """{a}_w = w+ a+ + w- a- on interior edges, w+- = k-+ / (k+ + k-) (1/2 each for constant data)."""
        if self.constant:
            return 0.5 * (own + neighbour)
        k, k_other = self.own.stiffness, self.neighbour.stiffness
        return (k_other * own + k * neighbour) / (k + k_other)

    def harmonic(self, quantity, text):
        """The :class:`EdgeCoefficient` of ``quantity`` (a function of a :class:`Lame`): on interior edges
        the harmonic mean 2 a+ a- / (a+ + a-) of its values on the two sides, on boundary edges its value."""
        own = quantity(self.own)
        if self.constant:
            return EdgeCoefficient(own, own, text)
        other = quantity(self.neighbour)
        return EdgeCoefficient(2 * own * other / (own + other), own, text)

    def largest(self, quantity, mesh):
        """The largest value of ``quantity`` (a function of a :class:`Lame`) over the elements' Gauss points
        (:func:`largest`)."""
        return largest(quantity(self.own), mesh)
