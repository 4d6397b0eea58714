r"""The sides of a contact pair as curves, and the closest-point search on them (:mod:`ngdgfric.contact.pairing`).

Each boundary edge of a side is a curve :math:`x_e(s)`, :math:`s \in [0, 1]` the reference parameter of its boundary
element (a polynomial of the mesh's curving degree on curved sides, fitted exactly from its values at
``CURVE_SAMPLES`` points); the outward normal comes from the side of the edge its element lies on.

**The search.**  :math:`\pi(x)` starts from the nearest of ``4 * CURVE_SAMPLES`` samples per edge: the edges whose
samples' bounding boxes meet the 3 x 3 cells around :math:`x` of a bucket grid (cells about one edge long) give the
nearest sample wherever it is closer than a cell; elsewhere (points far from the side) every edge whose box is no
farther than the nearest edge end is searched.  The cuts of an edge come from the vertices whose closest point on
it lies inside it: a vertex :math:`v` and an edge :math:`x(s)` qualify only if the edge's box is within ``reach`` of
:math:`v` and :math:`(x(s) - v) \cdot x'(s)` changes sign on it (or the edge bends too much to tell from its ends).
The search finds the same sample as a search through all samples (``tests/test_pairs.py``), in time about linear
in the number of edges near the pair's points; where the nearest sample is a shared end of two edges the point may
lie across from the neighbour, which is tried too.
"""

import ngsolve as ngs
import numpy as np

from ..problem import pattern

__all__ = ["SideCurves", "box_distance", "CURVE_SAMPLES", "NEWTON_STEPS", "CHUNK"]

CURVE_SAMPLES = 12
"""Points per edge at which its curve is sampled: a polynomial of degree up to 11 in s is fitted exactly (Netgen
curves elements up to the discretisation's degree; ``MAX_DEGREE`` allows more, then the fit is a least-squares
approximation of the curve to about 1e-12 on arcs)."""
NEWTON_STEPS = 8
"""Newton steps of the closest point on an edge."""
CHUNK = 1 << 20
"""Entries of the (points x edges) arrays of the far-point and cut searches, per chunk."""


def _chebyshev(count):
    """``count`` points in [0, 1] (Chebyshev-Gauss-Lobatto): a well-conditioned polynomial fit."""
    return 0.5 - 0.5 * np.cos(np.pi * np.arange(count) / (count - 1))


class SideCurves:
    """The edges of one side as curves: ``coefficients`` (edges, 2, degree + 1) of x(s), y(s) (numpy's polyval
    order), ``normal_sign`` per edge (+1 if the outward normal is (y', -x')), ``ends`` (edges, 2, 2) the points at
    s = 0, 1, ``neighbour`` (edges, 2, 2) the edge sharing each of those points (its mesh vertex) and its end there
    (-1, -1: none), ``side_end`` (edges, 2) whether that point is an end of the whole side (no neighbour there),
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
        self.neighbour = _neighbours(mesh, side, self.ends)
        self.side_end = self.neighbour[:, :, 0] < 0
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
        return np.nonzero(box_distance(xy, self.lower, self.upper) <= bound[:, None] * (1 + 1e-9))

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


def box_distance(xy, lower, upper):
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
