r"""The contact pairs' terms of the residual estimator (:mod:`ngdgfric.estimator`): :math:`\eta_4` and
:math:`\eta_6` on both sides of every pair.

At a pair point :math:`x_k` (:mod:`ngdgfric.contact.pairing`; weight :math:`\omega_k`, normal :math:`n_k` and
tangent :math:`t_k` of the pair's side) the solver's forces :math:`f_{n,k}, f_{t,k}`
(``sol.info["pair_forces"]``) act on the pair's side as the traction
:math:`-T_k = -(f_{n,k} n_k + f_{t,k} t_k) / \omega_k` and on the other side, at :math:`\pi(x_k)`, as :math:`+T_k`
(action and reaction).  The residuals of the two bodies' boundary conditions there are

.. math::

    r^1_k = \sigma_h(u_h^1)(x_k)\, n^1 + T_k, \qquad r^2_k = \sigma_h(u_h^2)(\pi(x_k))\, n^2 - T_k,

split along :math:`n_k` (the normal part, :math:`\eta_6`: the compliance law (1.8)) and :math:`t_k` (the tangential
part, :math:`\eta_4`: the friction law (1.9)), as for the foundation (:math:`\sigma_{h,n} + c_n (\cdot)_+^{m_n}`
and :math:`\sigma_{h,\tau} + c_\tau (\cdot)_+^{m_t} \lambda_\tau`, which are :math:`r \cdot n` and
:math:`r \cdot t` with the foundation's forces in :math:`T`).  Each point adds
:math:`(h_e / p_T)\, \omega_k (r \cdot n)^2` and :math:`(h_e / p_T)\, \omega_k (r \cdot t)^2` to the element of
its edge on that side (:math:`h_e` the edge's length, :math:`p_T` the element's degree).  The pair's points are
Gauss points of the common refinement (``q`` = p + 1 per piece): on straight sides the squared residual of a
piecewise polynomial traction is integrated exactly; on the other side the weights are those of the pair's side
(the closest-point map preserves length on parallel sides; on curved ones to first order in the gap).

Where a side does not face the other (farther than the pair's ``reach``: the pairing leaves those points out)
it is a free boundary: the residual is :math:`\sigma_h(u_h) n` itself, integrated with a Gauss rule of
:math:`p + 2` points per edge at the points whose closest point on the other side is beyond ``reach``.

:math:`\sigma_h(u_h)` along an edge is evaluated at ``p + 2`` nodes of the edge's boundary element (from the
element the edge belongs to: each side of a pair belongs to one body) and interpolated in the edge parameter:
exact on straight edges, where it is a polynomial of degree at most ``p``.
"""

import ngsolve as ngs
import numpy as np

from ..problem import pattern
from .curves import SideCurves
from .pair_traces import lagrange

__all__ = ["pair_terms", "side_values", "side_elements"]


def side_values(mesh, side, cf, nodes):
    """The values of the volume CoefficientFunction ``cf`` at the parameters ``nodes`` of every edge of side
    ``side`` (from the element each edge belongs to), shape (edges, len(nodes), cf.dim), edges in the order of
    the side's boundary elements (that of :class:`~ngdgfric.contact.curves.SideCurves`)."""
    rule = ngs.IntegrationRule(points=[(float(s),) for s in nodes], weights=[1.0] * len(nodes))
    points = mesh.MapToAllElements({ngs.SEGM: rule}, mesh.Boundaries(pattern([side])))
    return np.asarray(ngs.BoundaryFromVolumeCF(cf)(points)).reshape(-1, len(nodes), cf.dim)


def side_elements(mesh, side):
    """The number of the element of every edge of side ``side`` (in the order of ``side_values``)."""
    return np.array([mesh[el.edges[0]].elements[0].nr for el in mesh.Elements(ngs.BND) if el.mat == side],
                    dtype=np.int64)


class _Side:
    """One side of a pair for the estimator: its curves, elements, edge lengths, h_e / p_T per edge and the stress
    at the nodes of every edge."""

    def __init__(self, sol, side, sigma, nodes, weights):
        mesh = sol.mesh
        self.curves = SideCurves(mesh, side)
        self.elements = side_elements(mesh, side)
        edges = len(self.elements)
        self.nodes, self.weights = nodes, weights
        speed, _, _ = self.curves.frame(np.repeat(np.arange(edges), len(nodes)), np.tile(nodes, edges))
        self.speed = speed.reshape(edges, len(nodes))
        length = self.speed @ weights
        self.h_over_p = length / np.asarray(sol.discretization.orders, dtype=float)[self.elements]
        self.stress = side_values(mesh, side, sigma, nodes)

    def traction(self, edge, s):
        """sigma_h(u_h) n at parameters ``s`` of edges ``edge`` (arrays), with the side's outward normal n; returns
        (sigma n, n, t), each (k, 2)."""
        values = np.einsum("kj,kjc->kc", lagrange(self.nodes, s), self.stress[edge]).reshape(-1, 2, 2)
        _, n, t = self.curves.frame(edge, s)
        return np.einsum("kab,kb->ka", values, n), n, t


def pair_terms(sol, sigma):
    r"""The pairs' shares of :math:`\eta_4^2` and :math:`\eta_6^2` per element (module docstring), two arrays of
    length ``mesh.ne``; ``sigma``: the stress CoefficientFunction the estimator's variant uses
    (:func:`ngdgfric.estimator.residual_parts`)."""
    mesh, contact = sol.mesh, sol.contact
    eta4, eta6 = np.zeros(mesh.ne), np.zeros(mesh.ne)
    count = contact.degree + 2
    nodes, weights = np.polynomial.legendre.leggauss(count)
    nodes, weights = 0.5 * (nodes + 1), 0.5 * weights
    forces = np.asarray(sol.info["pair_forces"])
    start = 0
    for pair, points, _ in contact.pairs:
        force = forces[:, start:start + points.M]
        start += points.M
        T = (force[0][:, None] * points.normal + force[1][:, None] * points.tangent) / points.weight[:, None]
        sides = [_Side(sol, name, sigma, nodes, weights) for name in (pair.side, pair.other)]
        for here, there, edge, s, sign in ((sides[0], sides[1], points.edge, points.s, 1.0),
                                           (sides[1], sides[0], points.other_edge, points.other_s, -1.0)):
            sigma_n, _, _ = here.traction(edge, s)
            _add(eta4, eta6, here, edge, points.weight, sigma_n + sign * T, points.normal, points.tangent)
            _free_boundary(eta4, eta6, here, there, contact.reach(pair))
    return eta4, eta6


def _free_boundary(eta4, eta6, here, there, reach):
    """Add the residual sigma_h(u_h) n of the points of side ``here`` (Gauss rule of its ``_Side``) that do not
    face side ``there`` within ``reach`` (their closest point farther than that): a free boundary."""
    edges, count = here.speed.shape
    edge, s = np.repeat(np.arange(edges), count), np.tile(here.nodes, edges)
    _, _, distance = there.curves.closest(here.curves.at(edge, s))
    free = distance > reach
    if not np.any(free):
        return
    edge, s = edge[free], s[free]
    sigma_n, n, t = here.traction(edge, s)
    weight = (here.speed * here.weights[None]).ravel()[free]
    _add(eta4, eta6, here, edge, weight, sigma_n, n, t)


def _add(eta4, eta6, side, edge, weight, residual, normal, tangent):
    """eta_6^2 += (h_e / p_T) weight (r . n)^2 and eta_4^2 += (h_e / p_T) weight (r . t)^2 on the elements of the
    points' edges."""
    scale = side.h_over_p[edge] * weight
    elements = side.elements[edge]
    np.add.at(eta6, elements, scale * np.sum(residual * normal, axis=1) ** 2)
    np.add.at(eta4, elements, scale * np.sum(residual * tangent, axis=1) ** 2)
