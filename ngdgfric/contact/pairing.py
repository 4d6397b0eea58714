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
other side.  Each edge of the pair's side is cut at the closest points of those vertices, the cuts moved to where
:math:`\pi` actually crosses a vertex (``_aligned``: on curved sides with a gap the two differ), and every piece gets
``q`` Gauss points (the pieces' points, :class:`PiecePoints`): integrals over them are exact for piecewise
polynomials on the common refinement.

**The law's points (mortar).**  The laws act at the ``q`` Gauss points :math:`x_k` (weights :math:`\omega_k`) of
each edge of the pair's side, as on the foundation's edges, on the jump projected onto the polynomials of degree
``q - 1`` on the edge, evaluated with the pieces' rule:

.. math::

    [u]_k = \frac{1}{\omega_k} \int_e \phi_k\, [u]\, ds = \sum_i P_{ki}\, [u](x_i), \qquad
    P_{ki} = w_i\, \phi_k(s_i) / \omega_k,

:math:`\phi_k` the Lagrange basis of the edge's Gauss nodes, :math:`x_i, w_i` the pieces' points and weights (the
gap is projected the same way).  A uniform pressure then crosses a flat interface between non-matching meshes
exactly (:math:`\sum_k \phi_k = 1`: the contact patch test, ``tests/test_pairs.py``), and the rows of :math:`B` are
as independent as the foundation's (the law at the pieces' points repeated rows where two pieces lie on one edge:
a singular Delassus operator, the proximal point method and 28-44 Newton iterations on two strips where the
projection takes 2-5).  An edge that faces the other side only in part (an end of the other side, the reach) keeps
its pieces' points as the law's points.

Points farther than ``reach`` from the other side (and their pieces) never touch it and are left out, and so are the
points beyond an end of the other side (an overhang): where :math:`\pi(x)` is an end of the whole other side (a vertex
of one of its edges only) and :math:`x - \pi(x)` is not along its normal (a
tangential part above ``OVERHANG`` times the edge's length), no part of the other side lies across from :math:`x`;
and the points whose closest point lies on a flank of the other side that does not face them (its outward normal
there not against theirs, :math:`n \cdot n' \ge 0`: far along two convex sides, where the gap along :math:`n` would be
negative and a contact spurious).
A closed side has no ends.

**The search.**  :math:`\pi(x)` starts from the nearest of ``4 * CURVE_SAMPLES`` samples per edge: the edges whose
samples' bounding boxes meet the 3 x 3 cells around :math:`x` of a bucket grid (cells about one edge long) give the
nearest sample wherever it is closer than a cell; elsewhere (points far from the side) every edge whose box is no
farther than the nearest edge end is searched.  The cuts of an edge come from the vertices whose closest point on
it lies inside it: a vertex :math:`v` and an edge :math:`x(s)` qualify only if the edge's box is within ``reach`` of
:math:`v` and :math:`(x(s) - v) \cdot x'(s)` changes sign on it (or the edge bends too much to tell from its ends).
The search finds the same sample as a search through all samples (``tests/test_pairs.py``), in time about linear in
the number of edges near the pair's points.
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..problem import pattern

__all__ = ["SideCurves", "PairPoints", "PiecePoints", "pair_points", "CURVE_SAMPLES", "OVERHANG"]

CURVE_SAMPLES = 12
"""Points per edge at which its curve is sampled: a polynomial of degree up to 11 in s is fitted exactly (Netgen
curves elements up to the discretisation's degree; ``MAX_DEGREE`` allows more, then the fit is a least-squares
approximation of the curve to about 1e-12 on arcs)."""
NEWTON_STEPS = 8
SPLIT = 1e-6
"""A piece is split where pi changes the edge it lands on only that far (in the edge's parameter) from its ends."""
OVERHANG = 1e-9
"""A point whose closest point is an end of the other side is left out where its offset has a tangential part above
OVERHANG times the length of the edge there (module docstring)."""
CHUNK = 1 << 20  # entries of the (points x edges) arrays of the far-point and cut searches, per chunk


def _chebyshev(count):
    """``count`` points in [0, 1] (Chebyshev-Gauss-Lobatto): a well-conditioned polynomial fit."""
    return 0.5 - 0.5 * np.cos(np.pi * np.arange(count) / (count - 1))


class SideCurves:
    """The edges of one side as curves: ``coefficients`` (edges, 2, degree + 1) of x(s), y(s) (numpy's polyval
    order), ``normal_sign`` per edge (+1 if the outward normal is (y', -x')), ``ends`` (edges, 2, 2) the points at
    s = 0, 1, ``side_end`` (edges, 2) whether that point is an end of the whole side (no other edge shares it),
    ``neighbour`` (edges, 2, 2) the edge sharing each of those points and its end there (-1, -1: none),
    ``samples`` (edges, 4 * CURVE_SAMPLES, 2) the points at the parameters ``grid`` and their bounding boxes
    ``lower``, ``upper`` (edges, 2)."""

    def __init__(self, mesh, side):
        nodes = _chebyshev(CURVE_SAMPLES)
        rule = ngs.IntegrationRule(points=[(s,) for s in nodes], weights=[1.0] * len(nodes))
        points = mesh.MapToAllElements({ngs.SEGM: rule}, mesh.Boundaries(pattern([side])))
        xy = np.column_stack([np.asarray(ngs.x(points)).ravel(), np.asarray(ngs.y(points)).ravel()])
        xy = xy.reshape(-1, len(nodes), 2)
        count = len(xy)
        self._derivatives = {}
        basis = np.polynomial.chebyshev.chebvander(2 * nodes - 1, CURVE_SAMPLES - 1)
        self.coefficients = np.linalg.solve(basis, xy).transpose(0, 2, 1)  # (edges, 2, samples), Chebyshev in 2s - 1
        middle = xy[:, len(nodes) // 2]
        inward = _centroids(mesh, side) - middle  # towards the inside of each edge's element
        tangent = self._derivative(np.arange(count), nodes[len(nodes) // 2] * np.ones(count))
        self.normal_sign = -np.sign(tangent[:, 1] * inward[:, 0] - tangent[:, 0] * inward[:, 1])
        self.ends = np.stack([self.at(np.arange(count), np.zeros(count)), self.at(np.arange(count), np.ones(count))],
                             axis=1)
        self.grid = np.linspace(0.0, 1.0, 4 * CURVE_SAMPLES)
        self.samples = self.at(np.repeat(np.arange(count), len(self.grid)),
                               np.tile(self.grid, count)).reshape(count, len(self.grid), 2)
        self.lower, self.upper = self.samples.min(axis=1), self.samples.max(axis=1)
        self.side_end = _unshared(self.ends)
        self.neighbour = _neighbours(mesh, side, self.ends)
        self._buckets = _Buckets(self.lower, self.upper)

    def at(self, edge, s):
        """Points x_e(s) for arrays ``edge`` and ``s``, shape (n, 2)."""
        return self._evaluate(self.coefficients[edge], s)

    @staticmethod
    def _evaluate(c, s):
        basis = np.polynomial.chebyshev.chebvander(2 * np.asarray(s, dtype=float) - 1, c.shape[2] - 1)
        return np.einsum("ndk,nk->nd", c, basis)

    def _derivative(self, edge, s, order=1):
        for m in range(1, order + 1):  # Chebyshev coefficients of x^(m)(s), computed once
            if m not in self._derivatives:
                self._derivatives[m] = np.polynomial.chebyshev.chebder(self.coefficients, m=m, scl=2.0, axis=2)
        return self._evaluate(self._derivatives[order][edge], s)

    def frame(self, edge, s):
        """(|dx/ds|, outward unit normal, tangent t = (-n_y, n_x)) at parameters s of edges ``edge``."""
        d = self._derivative(edge, s)
        speed = np.linalg.norm(d, axis=1)
        n = self.normal_sign[edge][:, None] * np.column_stack([d[:, 1], -d[:, 0]]) / speed[:, None]
        return speed, n, np.column_stack([-n[:, 1], n[:, 0]])

    def nearest_sample(self, xy):
        """For points xy (n, 2): (edge, s) of the nearest of the ``samples`` (the first in the order edge by edge
        where several are as near), through the bucket grid (module docstring)."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        point, edge = self._buckets.near(xy)
        best_edge, best_k, best = _nearest_among(self.samples, xy, point, edge)
        far = np.flatnonzero(~(best < self._buckets.cell * (1 - 1e-9)))  # another cell may hold a nearer sample
        for chunk in np.array_split(far, max(1, len(far) * len(self.lower) // CHUNK)):
            if len(chunk):
                point, edge = self._boxes_within(xy[chunk])
                best_edge[chunk], best_k[chunk], _ = _nearest_among(self.samples, xy[chunk], point, edge)
        return best_edge, self.grid[best_k]

    def _boxes_within(self, xy):
        """(point, edge) pairs, sorted, of the edges whose bounding box is no farther from the point than the nearest
        edge end (s = 0, a sample): they hold every nearest sample."""
        bound = np.min(np.linalg.norm(xy[:, None, :] - self.samples[None, :, 0], axis=2), axis=1)
        return np.nonzero(_box_distance(xy, self.lower, self.upper) <= bound[:, None] * (1 + 1e-9))

    def project(self, edge, s, xy, steps=NEWTON_STEPS):
        """Newton's method (``steps`` steps) for the closest point of edge ``edge`` to xy from the parameters s, s
        kept in [0, 1]; returns (s, distance)."""
        self._derivative(edge[:0], s[:0], 2)  # the derivatives' coefficients
        c0, c1, c2 = self.coefficients[edge], self._derivatives[1][edge], self._derivatives[2][edge]
        for _ in range(steps):
            basis = np.polynomial.chebyshev.chebvander(2 * s - 1, c0.shape[2] - 1)  # one basis for x, x', x''
            r = np.einsum("ndk,nk->nd", c0, basis) - xy
            d1 = np.einsum("ndk,nk->nd", c1, basis[:, :c1.shape[2]])
            d2 = np.einsum("ndk,nk->nd", c2, basis[:, :c2.shape[2]])
            slope = np.sum(d1 * d1, axis=1) + np.sum(r * d2, axis=1)
            s = np.clip(s - np.sum(r * d1, axis=1) / np.where(slope > 0, slope, np.sum(d1 * d1, axis=1)), 0.0, 1.0)
        return s, np.linalg.norm(self.at(edge, s) - xy, axis=1)

    def closest(self, xy):
        """For points xy (n, 2): (edge, s, distance) of the closest point of this side: the nearest sample
        (``nearest_sample``), then Newton's method on that edge (``project``), s in [0, 1]."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        edge, start = self.nearest_sample(xy)
        s, distance = self.project(edge, start, xy)
        for end in (0, 1):  # a point whose nearest sample is a shared end may lie across from the neighbour edge
            at = np.flatnonzero(((start == end) | (s == end)) & (self.neighbour[edge, end, 0] >= 0))
            if len(at):
                other, other_end = self.neighbour[edge[at], end].T
                other_s, other_distance = self.project(other, other_end.astype(float), xy[at])
                better = other_distance < distance[at]
                edge[at[better]], s[at[better]], distance[at[better]] = (other[better], other_s[better],
                                                                         other_distance[better])
        return edge, s, distance

    def bend_bound(self):
        """Per edge, an upper bound of |x''(s)| on [0, 1] (the sum of the second derivative's Chebyshev
        coefficients' sizes) and a lower bound of |x'(s)| (its least value at the samples less that bound times
        the samples' half spacing)."""
        second = np.polynomial.chebyshev.chebder(self.coefficients, m=2, scl=2.0, axis=2)
        bend = np.linalg.norm(np.sum(np.abs(second), axis=2), axis=1)
        count = len(self.coefficients)
        speed = np.linalg.norm(self._derivative(np.repeat(np.arange(count), len(self.grid)),
                                                np.tile(self.grid, count)), axis=1).reshape(count, -1)
        return bend, speed.min(axis=1) - bend * 0.5 / (len(self.grid) - 1)


class _Buckets:
    """A grid of square cells about one edge long; ``keys``, ``edges``: each edge listed in every cell its bounding
    box meets, sorted by cell."""

    def __init__(self, lower, upper):
        extent = np.max(upper - lower, axis=1)
        scale = max(float(np.max(upper - lower.min(axis=0), initial=0.0)), 1e-300)
        self.cell = max(float(np.median(extent)) if len(extent) else scale, 1e-9 * scale)
        self.origin = lower.min(axis=0)
        while True:  # coarser cells where a few long edges would fill too many
            first, last = self._cell(lower), self._cell(upper)
            counts = np.prod(last - first + 1, axis=1)
            if counts.sum() <= 16 * len(extent) + 64:
                break
            self.cell *= 2
        self.shape = self._cell(upper.max(axis=0)[None])[0] + 1
        edge = np.repeat(np.arange(len(extent)), counts)
        index = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        width = (last - first + 1)[edge, 1]
        i, j = first[edge, 0] + index // width, first[edge, 1] + index % width
        keys = i * self.shape[1] + j
        order = np.argsort(keys, kind="stable")
        self.keys, self.edges = keys[order], edge[order]

    def _cell(self, xy):
        return np.floor((xy - self.origin) / self.cell).astype(np.int64)

    def near(self, xy):
        """(point, edge) pairs, sorted and without repeats, of the edges listed in the 3 x 3 cells around each
        point's cell."""
        cell = self._cell(xy)
        offsets = np.array([(a, b) for a in (-1, 0, 1) for b in (-1, 0, 1)])
        around = (cell[:, None, :] + offsets[None]).reshape(-1, 2)
        point = np.repeat(np.arange(len(xy)), len(offsets))
        inside = np.all((around >= 0) & (around < self.shape), axis=1)
        point, around = point[inside], around[inside]
        key = around[:, 0] * self.shape[1] + around[:, 1]
        start, stop = np.searchsorted(self.keys, key, "left"), np.searchsorted(self.keys, key, "right")
        counts = stop - start
        picked = np.repeat(start - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
        pairs = np.unique(np.repeat(point, counts) * len(self.keys) + self.edges[picked])
        return pairs // len(self.keys), pairs % len(self.keys)


def _neighbours(mesh, side, ends):
    """(edges, 2, 2): for the end s = 0, 1 of every edge of ``side``, the other edge of the side that shares that
    mesh vertex and which of its ends it is (-1, -1 if none), from the mesh's vertex numbers."""
    numbers = np.array([[v.nr for v in el.vertices] for el in mesh.Elements(ngs.BND) if el.mat == side],
                       dtype=np.int64).reshape(-1, 2)
    points = np.array([mesh[ngs.NodeId(ngs.VERTEX, int(v))].point for v in numbers.ravel()]).reshape(-1, 2, 2)
    flipped = np.linalg.norm(points[:, 0] - ends[:, 0], axis=1) > np.linalg.norm(points[:, 1] - ends[:, 0], axis=1)
    numbers = np.where(flipped[:, None], numbers[:, ::-1], numbers)  # numbers[e, k]: the vertex at s = k
    found = np.full((len(numbers), 2, 2), -1, dtype=np.int64)
    at = {}
    for e, k in np.ndindex(numbers.shape):
        at.setdefault(int(numbers[e, k]), []).append((e, k))
    for shared in at.values():
        if len(shared) == 2:
            (e1, k1), (e2, k2) = shared
            found[e1, k1], found[e2, k2] = (e2, k2), (e1, k1)
    return found


def _centroids(mesh, side):
    """(edges, 2): the centroid of the element of every edge of ``side`` (its vertices' mean)."""
    elements = [mesh[el.edges[0]].elements[0] for el in mesh.Elements(ngs.BND) if el.mat == side]
    return np.array([np.mean([mesh[v].point for v in mesh[element].vertices], axis=0) for element in elements],
                    dtype=float).reshape(-1, 2)


def _unshared(ends):
    """(edges, 2): whether each end point of each edge is shared by no other end (to 1e-9 of the median edge
    length): the ends of a side's chains; a closed side has none."""
    points = ends.reshape(-1, 2)
    size = 1e-9 * max(float(np.median(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1))), 1e-300)
    shared = np.zeros(len(points), dtype=bool)
    for shift in (0.0, 0.5):  # two roundings half a bin apart: points closer than half a bin share a bin in one
        bins = np.floor(points / size + shift)
        _, inverse, counts = np.unique(bins, axis=0, return_inverse=True, return_counts=True)
        shared |= counts[inverse.ravel()] > 1
    return ~shared.reshape(-1, 2)


def _box_distance(xy, lower, upper):
    """(points, boxes): the distance of each point from each box."""
    below, above = lower[None] - xy[:, None], xy[:, None] - upper[None]
    return np.linalg.norm(np.maximum(np.maximum(below, above), 0.0), axis=2)


def _nearest_among(samples, xy, point, edge):
    """Over the (point, edge) pairs (sorted by point, then edge): per point the (edge, sample index, distance) of
    its nearest sample, the first edge by edge where several are as near; edge 0, index 0 and distance inf for a
    point without pairs."""
    count = samples.shape[1]
    best_edge, best_k, best = np.zeros(len(xy), dtype=int), np.zeros(len(xy), dtype=int), np.full(len(xy), np.inf)
    if len(point) == 0:
        return best_edge, best_k, best
    distance = np.linalg.norm(xy[point][:, None, :] - samples[edge], axis=2)  # (pairs, samples)
    starts = np.flatnonzero(np.diff(point, prepend=-1))
    owners = point[starts]
    best[owners] = np.minimum.reduceat(distance.min(axis=1), starts)
    hits = np.flatnonzero(distance.ravel() == best[np.repeat(point, count)])
    _, first = np.unique(point[hits // count], return_index=True)
    hit = hits[first]
    best_edge[owners], best_k[owners] = edge[hit // count], hit % count
    return best_edge, best_k, best


@dataclass
class PiecePoints:
    """The Gauss points of the pieces of the common refinement that face the other side (module docstring), arrays
    of length m: ``edge``, ``s`` (edge of the pair's side, parameter), ``weight`` (Gauss weight times |dx/ds|
    times the piece's length in s), ``normal``, ``tangent`` (m, 2) of the pair's side, ``gap`` (geometric gap plus
    the pair's g_a), ``other_edge``, ``other_s`` (the closest point on the other side)."""

    edge: np.ndarray
    s: np.ndarray
    weight: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    gap: np.ndarray
    other_edge: np.ndarray
    other_s: np.ndarray


@dataclass
class PairPoints:
    """The law's points of one contact pair (module docstring): the Gauss points of the edges of the pair's side
    that face the other side, arrays of length M: ``xy`` (M, 2), ``weight`` (Gauss weight times |dx/ds|),
    ``normal``, ``tangent`` (M, 2) of the pair's side, ``gap`` (the projected gap, ``projection`` applied to the
    pieces' gaps), ``edge``, ``s`` (edge of the pair's side, parameter), ``other_edge``, ``other_s`` (of the closest
    point on the other side), ``other_xy`` (M, 2), ``cell`` (M, 2: the parameters s at the ends of each point's
    Gauss cell, from c_{k-1} to c_k, c_k = w_1 + ... + w_k the Gauss weights on [0, 1] summed, as on the foundation,
    :mod:`ngdgfric.contact.forces`); ``pieces``: the number of pieces of the common refinement; ``piece``: their
    :class:`PiecePoints`; ``projection``: (k, i, P_ki) the weights of the projection onto the law's points,
    P_ki = w_i phi_k(s_i) / omega_k."""

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
    piece: PiecePoints
    projection: tuple

    @property
    def M(self):
        return len(self.weight)


def _breakpoints(curves, other, reach):
    """The cuts of the edges of ``curves``: (edge, s) arrays, sorted by edge, then s, of the parameters in (0, 1)
    of the closest points on each edge (the nearest of its samples, then Newton's method) of the vertices of
    ``other`` that lie within ``reach`` of it.  Only the (vertex, edge) pairs that can have such a point are
    projected (module docstring)."""
    vertices = np.unique(np.round(other.ends.reshape(-1, 2), 14), axis=0)
    bend, speed = curves.bend_bound()
    first, last = curves.samples[:, 0], curves.samples[:, -1]
    start_tangent = curves._derivative(np.arange(len(first)), np.zeros(len(first)))
    end_tangent = curves._derivative(np.arange(len(first)), np.ones(len(first)))
    centre, radius = 0.5 * (curves.lower + curves.upper), 0.5 * np.linalg.norm(curves.upper - curves.lower, axis=1)
    sag = bend / (8 * (len(curves.grid) - 1) ** 2)  # the curve strays at most this far from its samples' box
    pairs = []
    for chunk in np.array_split(np.arange(len(vertices)), max(1, len(vertices) * len(first) // CHUNK)):
        v = vertices[chunk][:, None, :]
        within = _box_distance(vertices[chunk], curves.lower, curves.upper) <= reach + sag[None] + 1e-12 * radius
        # (x - v) . x' rises along an edge that bends little against its distance from v: its sign at the ends
        # then says whether the closest point is inside the edge
        rising = (np.linalg.norm(v - centre[None], axis=2) + radius[None]) * bend[None] < speed[None] ** 2
        inside = (np.sum((first[None] - v) * start_tangent[None], axis=2) < 0) & \
                 (np.sum((last[None] - v) * end_tangent[None], axis=2) > 0)
        vertex, edge = np.nonzero(within & (inside | ~rising))
        pairs.append((chunk[vertex], edge))
    vertex, edge = (np.concatenate(parts) for parts in zip(*pairs, strict=True))
    order = np.lexsort((vertex, edge))
    vertex, edge = vertex[order], edge[order]
    distance = np.linalg.norm(vertices[vertex][:, None, :] - curves.samples[edge], axis=2)
    s, distance = curves.project(edge, curves.grid[np.argmin(distance, axis=1)], vertices[vertex])
    keep = (distance <= reach) & (s > 1e-12) & (s < 1 - 1e-12)
    cuts = np.unique(np.column_stack([edge[keep], s[keep]]), axis=0)
    return cuts[:, 0].astype(int), cuts[:, 1]


def pair_points(mesh, pair, q, reach):
    """The :class:`PairPoints` of ``pair`` (a :class:`~ngdgfric.ContactPair`) on ``mesh`` with ``q`` Gauss points per
    piece; ValueError if no point of the pair's side comes within ``reach`` of the other side."""
    curves, other = SideCurves(mesh, pair.side), SideCurves(mesh, pair.other)
    nodes, weights = np.polynomial.legendre.leggauss(q)
    nodes, weights = 0.5 * (nodes + 1), 0.5 * weights
    count = len(curves.coefficients)
    cut_edge, cut_s = _breakpoints(curves, other, reach)
    edge = np.concatenate([np.arange(count), cut_edge, np.arange(count)])
    ends = np.concatenate([np.zeros(count), cut_s, np.ones(count)])
    order = np.lexsort((ends, edge))
    edge, ends = edge[order], ends[order]
    same = edge[1:] == edge[:-1]
    a, b, piece_edge = ends[:-1][same], ends[1:][same], edge[:-1][same]
    a, b, piece_edge = _aligned(other, curves, a, b, piece_edge)
    pieces = len(a)
    edge = np.repeat(piece_edge, q)
    s = (a[:, None] + (b - a)[:, None] * nodes[None]).ravel()
    w = np.repeat(b - a, q) * np.tile(weights, len(a))
    fractions = np.r_[0.0, np.cumsum(weights)]
    cells = np.stack([a[:, None] + (b - a)[:, None] * fractions[None, :-1],
                      a[:, None] + (b - a)[:, None] * fractions[None, 1:]], axis=2).reshape(-1, 2)
    xy = curves.at(edge, s)
    speed, normal, tangent = curves.frame(edge, s)
    other_edge, other_s, distance = other.closest(xy)
    near = distance <= reach
    if not np.any(near):
        raise ValueError(f"sides {pair.side!r} and {pair.other!r} of a contact pair do not face each other: no point "
                         f"of {pair.side!r} comes within reach = {reach:.3g} of {pair.other!r} (closest "
                         f"{distance.min():.3g}); move the bodies closer or give the pair a larger reach")
    other_xy = other.at(other_edge, other_s)
    near &= ~_overhang(other, other_edge, other_s, xy - other_xy)
    _, other_normal, _ = other.frame(other_edge, other_s)
    near &= np.sum(normal * other_normal, axis=1) < 0  # the sides face each other (else pi lands on a far flank)
    gap = np.sum((other_xy - xy) * normal, axis=1) + pair.g_a
    piece = PiecePoints(edge=edge[near], s=s[near], weight=(w * speed)[near], normal=normal[near],
                        tangent=tangent[near], gap=gap[near], other_edge=other_edge[near], other_s=other_s[near])
    covered = np.bincount(edge[near], weights=w[near], minlength=count) > 1 - 1e-9  # every piece of it faces
    return _law_points(curves, other, piece, nodes, weights, pieces, covered, cells[near])


def _law_points(curves, other, piece, nodes, weights, pieces, covered, cells):
    """The :class:`PairPoints` of the pieces' points ``piece``: on every edge that faces the other side along its
    whole length (``covered``) the edge's q Gauss points (``nodes``, ``weights`` on [0, 1]), onto which the pieces'
    points are projected; on the edges that face it in part (an end of the other side, the reach) the pieces'
    points themselves (their Gauss ``cells``)."""
    q = len(nodes)
    whole = covered[piece.edge]
    edges = np.unique(piece.edge[whole])
    own = np.flatnonzero(~whole)
    law_edge = np.concatenate([np.repeat(edges, q), piece.edge[own]])
    law_s = np.concatenate([np.tile(nodes, len(edges)), piece.s[own]])
    order = np.lexsort((law_s, law_edge))
    law_edge, law_s = law_edge[order], law_s[order]
    position = np.argsort(order)  # where each unsorted law point went
    xy = curves.at(law_edge, law_s)
    speed, normal, tangent = curves.frame(law_edge, law_s)
    omega = np.concatenate([np.tile(weights, len(edges)) * speed[position[:len(edges) * q]], piece.weight[own]])
    omega = omega[order]
    other_edge, other_s, _ = other.closest(xy)
    i_whole = np.flatnonzero(whole)
    first = np.searchsorted(edges, piece.edge[i_whole]) * q  # the edge's law points first .. first + q - 1
    k = position[(first[:, None] + np.arange(q)[None]).ravel()]
    i = np.repeat(i_whole, q)
    values = (piece.weight[i_whole][:, None] * _lagrange(nodes, piece.s[i_whole])).ravel() / omega[k]
    k = np.concatenate([k, position[len(edges) * q + np.arange(len(own))]])
    i = np.concatenate([i, own])
    values = np.concatenate([values, np.ones(len(own))])
    gap = np.bincount(k, weights=values * piece.gap[i], minlength=len(law_edge))
    fractions = np.r_[0.0, np.cumsum(weights)]
    law_cells = np.concatenate([np.tile(np.column_stack([fractions[:-1], fractions[1:]]), (len(edges), 1)),
                                cells[own]])[order]
    return PairPoints(xy=xy, weight=omega, normal=normal, tangent=tangent, gap=gap, edge=law_edge, s=law_s,
                      other_edge=other_edge, other_s=other_s, other_xy=other.at(other_edge, other_s), cell=law_cells,
                      pieces=pieces, piece=piece, projection=(k, i, values))


def _lagrange(nodes, s):
    """The Lagrange basis of ``nodes`` at the points ``s``: shape (len(s), len(nodes))."""
    s = np.asarray(s, dtype=float)[:, None]
    values = np.ones((s.shape[0], len(nodes)))
    for j, node in enumerate(nodes):
        for m, other in enumerate(nodes):
            if m != j:
                values[:, j] *= (s[:, 0] - other) / (node - other)
    return values


def _target(other, curves, edge, s):
    """The edge of ``other`` on which pi sends the points (edge, s) of ``curves``, or -1 - that edge where pi is an
    end of the whole other side (beyond which the points overhang)."""
    other_edge, other_s, _ = other.closest(curves.at(edge, s))
    at_end = ((other_s == 0.0) & other.side_end[other_edge, 0]) | ((other_s == 1.0) & other.side_end[other_edge, 1])
    return np.where(at_end, -1 - other_edge, other_edge)


def _edge_of(target):
    """The edge of a ``_target`` value."""
    return np.where(target < 0, -1 - target, target)


def _aligned(other, curves, a, b, edge, passes=3, halvings=24):
    """Pieces [a, b] of the edges ``edge`` of ``curves`` on each of which pi (onto ``other``) lands on one edge:
    split where that edge changes inside a piece (the crossing found by halving, unless it lies within SPLIT of an
    end: then the end is the crossing), then neighbouring pieces of one edge that land on the same edge joined.  On
    parallel sides the cuts at the closest points of the other side's vertices are these crossings; on curved sides
    with a gap pi crosses a vertex where the other side's normal there meets this side, elsewhere: a piece would
    hold a kink of v^2 o pi, and two pieces landing on one edge repeat each other's rows of B (W singular)."""
    inside = 1e-9
    for _ in range(passes):
        start = _target(other, curves, edge, a + inside * (b - a))
        stop = _target(other, curves, edge, b - inside * (b - a))
        split = np.flatnonzero(start != stop)
        if not len(split):
            break
        low, high = a[split] + inside * (b[split] - a[split]), b[split] - inside * (b[split] - a[split])
        first, second = _edge_of(start[split]), _edge_of(stop[split])
        two = first != second  # pi goes from one edge to another: nearer to the first than to the second
        on_first, on_second = np.full(int(two.sum()), 0.5), np.full(int(two.sum()), 0.5)
        for halving in range(halvings):
            middle = 0.5 * (low + high)
            same = np.empty(len(split), dtype=bool)
            xy = curves.at(edge[split][two], middle[two])
            steps = NEWTON_STEPS if halving == 0 else 2  # from the last halving's closest points: near already
            on_first, near_first = other.project(first[two], on_first, xy, steps)
            on_second, near_second = other.project(second[two], on_second, xy, steps)
            same[two] = near_first <= near_second
            same[~two] = _target(other, curves, edge[split][~two], middle[~two]) == start[split][~two]  # an end
            low, high = np.where(same, middle, low), np.where(same, high, middle)
        cut = 0.5 * (low + high)
        inner = (cut - a[split] > SPLIT) & (b[split] - cut > SPLIT)
        split, cut = split[inner], cut[inner]
        if not len(split):
            break
        a, b, edge = np.concatenate([a, cut]), np.concatenate([b, b[split]]), np.concatenate([edge, edge[split]])
        b[split] = cut
        order = np.lexsort((a, edge))
        a, b, edge = a[order], b[order], edge[order]
    landing = _target(other, curves, edge, 0.5 * (a + b))
    first = np.ones(len(a), dtype=bool)
    first[1:] = (edge[1:] != edge[:-1]) | (landing[1:] != landing[:-1])
    kept = np.flatnonzero(first)
    return a[kept], b[np.append(kept[1:], len(a)) - 1], edge[kept]


def _overhang(other, edge, s, offset):
    """Whether each point lies beyond an end of the side ``other`` (its closest point, parameter s of ``edge``, an
    end of the whole side, and its ``offset`` x - pi(x) with a tangential part above OVERHANG times the edge's
    length there)."""
    at_end = ((s == 0.0) & other.side_end[edge, 0]) | ((s == 1.0) & other.side_end[edge, 1])
    speed, _, tangent = other.frame(edge, s)
    return at_end & (np.abs(np.sum(offset * tangent, axis=1)) > OVERHANG * speed)
