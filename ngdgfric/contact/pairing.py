r"""The geometry of a contact pair (:class:`~ngdgfric.ContactPair`): the sides' edges as curves, the closest-point
map :math:`\pi` from one side onto the other, and the pair's points on the common refinement of the two sides'
edges.

Each boundary edge of a side is a curve :math:`x_e(s)`, :math:`s \in [0, 1]` the reference parameter of its boundary
element (a polynomial of the mesh's curving degree on curved sides, fitted exactly from its values at
``CURVE_SAMPLES`` points).  For a point :math:`x` of the pair's side, :math:`\pi(x)` is the closest point of the
other side (the nearest of many samples, then Newton's method on the edge's curve), and the gap

.. math::

    g(x) = (\pi(x) - x) \cdot n(x) + g_a

with :math:`n` the outward normal of the pair's side: the penetration is :math:`[u] \cdot n - g`.

**Segment to segment.**  A displacement of the other body is a polynomial on each of its edges, so
:math:`v^2 \circ \pi` is piecewise polynomial on the pair's side with kinks where :math:`\pi` crosses a vertex of the
other side.  Each edge of the pair's side is cut at the closest points of those vertices, and every piece gets
``q`` = max degree + 1 Gauss points: the contact integrals are exact for piecewise polynomials on the common
refinement, so a uniform pressure crosses a flat interface between non-matching meshes exactly (the contact patch
test, ``tests/test_pairs.py``).  Points farther than ``reach`` from the other side (and their pieces) never touch it
and are left out.
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..problem import pattern

__all__ = ["SideCurves", "PairPoints", "pair_points", "CURVE_SAMPLES"]

CURVE_SAMPLES = 12
"""Points per edge at which its curve is sampled: a polynomial of degree up to 11 in s is fitted exactly (Netgen
curves elements up to the discretisation's degree; ``MAX_DEGREE`` allows more, then the fit is a least-squares
approximation of the curve to about 1e-12 on arcs)."""
NEWTON_STEPS = 8


def _chebyshev(count):
    """``count`` points in [0, 1] (Chebyshev-Gauss-Lobatto): a well-conditioned polynomial fit."""
    return 0.5 - 0.5 * np.cos(np.pi * np.arange(count) / (count - 1))


class SideCurves:
    """The edges of one side as curves: ``coefficients`` (edges, 2, degree + 1) of x(s), y(s) (numpy's polyval
    order), ``normal_sign`` per edge (+1 if the outward normal is (y', -x'))."""

    def __init__(self, mesh, side):
        nodes = _chebyshev(CURVE_SAMPLES)
        rule = ngs.IntegrationRule(points=[(s,) for s in nodes], weights=[1.0] * len(nodes))
        points = mesh.MapToAllElements({ngs.SEGM: rule}, mesh.Boundaries(pattern([side])))
        xy = np.column_stack([np.asarray(ngs.x(points)).ravel(), np.asarray(ngs.y(points)).ravel()])
        xy = xy.reshape(-1, len(nodes), 2)
        count = len(xy)
        basis = np.polynomial.chebyshev.chebvander(2 * nodes - 1, CURVE_SAMPLES - 1)
        self.coefficients = np.linalg.solve(basis, xy).transpose(0, 2, 1)  # (edges, 2, samples), Chebyshev in 2s - 1
        normal = np.asarray(ngs.specialcf.normal(2)(points)).reshape(count, len(nodes), 2)[:, len(nodes) // 2]
        tangent = self._derivative(np.arange(count), nodes[len(nodes) // 2] * np.ones(count))
        self.normal_sign = np.sign(tangent[:, 1] * normal[:, 0] - tangent[:, 0] * normal[:, 1])
        self.ends = np.stack([self.at(np.arange(count), np.zeros(count)), self.at(np.arange(count), np.ones(count))],
                             axis=1)

    def at(self, edge, s):
        """Points x_e(s) for arrays ``edge`` and ``s``, shape (n, 2)."""
        return self._evaluate(self.coefficients[edge], s)

    @staticmethod
    def _evaluate(c, s):
        basis = np.polynomial.chebyshev.chebvander(2 * np.asarray(s, dtype=float) - 1, c.shape[2] - 1)
        return np.einsum("ndk,nk->nd", c, basis)

    def _derivative(self, edge, s, order=1):
        c = np.polynomial.chebyshev.chebder(self.coefficients[edge], m=order, scl=2.0, axis=2)
        return self._evaluate(c, s)

    def frame(self, edge, s):
        """(|dx/ds|, outward unit normal, tangent t = (-n_y, n_x)) at parameters s of edges ``edge``."""
        d = self._derivative(edge, s)
        speed = np.linalg.norm(d, axis=1)
        n = self.normal_sign[edge][:, None] * np.column_stack([d[:, 1], -d[:, 0]]) / speed[:, None]
        return speed, n, np.column_stack([-n[:, 1], n[:, 0]])

    def closest(self, xy, edges=None):
        """For points xy (n, 2): (edge, s, distance) of the closest point of this side (of ``edges`` only, if
        given): the nearest of 4 * CURVE_SAMPLES samples per edge, then Newton's method on that edge, s in [0, 1]."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        candidates = np.arange(len(self.coefficients)) if edges is None else np.asarray(edges)
        grid = np.linspace(0.0, 1.0, 4 * CURVE_SAMPLES)
        samples = self.at(np.repeat(candidates, len(grid)), np.tile(grid, len(candidates)))
        nearest = np.argmin(np.linalg.norm(xy[:, None, :] - samples[None], axis=2), axis=1)
        edge, s = candidates[nearest // len(grid)], grid[nearest % len(grid)]
        for _ in range(NEWTON_STEPS):
            r = self.at(edge, s) - xy
            d1, d2 = self._derivative(edge, s), self._derivative(edge, s, 2)
            slope = np.sum(d1 * d1, axis=1) + np.sum(r * d2, axis=1)
            s = np.clip(s - np.sum(r * d1, axis=1) / np.where(slope > 0, slope, np.sum(d1 * d1, axis=1)), 0.0, 1.0)
        return edge, s, np.linalg.norm(self.at(edge, s) - xy, axis=1)


@dataclass
class PairPoints:
    """The points of one contact pair on its side (module docstring), arrays of length M: ``xy`` (M, 2), ``weight``
    (Gauss weight times the piece's length), ``normal``, ``tangent`` (M, 2) of the pair's side, ``gap`` (geometric
    gap plus the pair's g_a), ``edge``, ``s`` (edge of the pair's side, parameter), ``other_edge``, ``other_s`` (of
    the closest point on the other side), ``other_xy`` (M, 2), ``cell`` (M, 2: the parameters s at the ends of each
    point's Gauss cell, the part of its piece it owns: from a + (b - a) c_{i-1} to a + (b - a) c_i on the piece
    [a, b], c_i = w_1 + ... + w_i the Gauss weights on [0, 1] summed, as on the foundation,
    :mod:`ngdgfric.contact.forces`); ``pieces``: the number of pieces of the common refinement."""

    xy: np.ndarray
    weight: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    gap: np.ndarray
    edge: np.ndarray
    s: np.ndarray
    other_edge: np.ndarray
    other_s: np.ndarray
    other_xy: np.ndarray
    cell: np.ndarray
    pieces: int

    @property
    def M(self):
        return len(self.weight)


def _breakpoints(curves, other, reach):
    """For every edge of ``curves``: the sorted parameters in (0, 1) of the closest points of the vertices of
    ``other`` that lie within ``reach`` of the edge."""
    vertices = np.unique(np.round(other.ends.reshape(-1, 2), 14), axis=0)
    cuts = []
    for e in range(len(curves.coefficients)):
        _, s, distance = curves.closest(vertices, edges=[e])
        cuts.append(np.unique(s[(distance <= reach) & (s > 1e-12) & (s < 1 - 1e-12)]))
    return cuts


def pair_points(mesh, pair, q, reach):
    """The :class:`PairPoints` of ``pair`` (a :class:`~ngdgfric.ContactPair`) on ``mesh`` with ``q`` Gauss points per
    piece; ValueError if no point of the pair's side comes within ``reach`` of the other side."""
    curves, other = SideCurves(mesh, pair.side), SideCurves(mesh, pair.other)
    nodes, weights = np.polynomial.legendre.leggauss(q)
    nodes, weights = 0.5 * (nodes + 1), 0.5 * weights
    fractions = np.r_[0.0, np.cumsum(weights)]
    edges, params, lengths, cells = [], [], [], []
    pieces = 0
    for e, cut in enumerate(_breakpoints(curves, other, reach)):
        ends = np.concatenate([[0.0], cut, [1.0]])
        keep = np.diff(ends) > 1e-12
        a, b = ends[:-1][keep], ends[1:][keep]
        pieces += len(a)
        edges.append(np.full(len(a) * q, e))
        params.append((a[:, None] + (b - a)[:, None] * nodes[None]).ravel())
        lengths.append(np.repeat(b - a, q) * np.tile(weights, len(a)))
        cells.append(np.stack([a[:, None] + (b - a)[:, None] * fractions[None, :-1],
                               a[:, None] + (b - a)[:, None] * fractions[None, 1:]], axis=2).reshape(-1, 2))
    edge, s, w = np.concatenate(edges), np.concatenate(params), np.concatenate(lengths)
    xy = curves.at(edge, s)
    speed, normal, tangent = curves.frame(edge, s)
    other_edge, other_s, distance = other.closest(xy)
    near = distance <= reach
    if not np.any(near):
        raise ValueError(f"sides {pair.side!r} and {pair.other!r} of a contact pair do not face each other: no point "
                         f"of {pair.side!r} comes within reach = {reach:.3g} of {pair.other!r} (closest "
                         f"{distance.min():.3g}); move the bodies closer or give the pair a larger reach")
    other_xy = other.at(other_edge, other_s)
    gap = np.sum((other_xy - xy) * normal, axis=1) + pair.g_a
    return PairPoints(xy=xy[near], weight=(w * speed)[near], normal=normal[near], tangent=tangent[near],
                      gap=gap[near], edge=edge[near], s=s[near], other_edge=other_edge[near],
                      other_s=other_s[near], other_xy=other_xy[near], cell=np.concatenate(cells)[near], pieces=pieces)
