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
``q`` Gauss points (the pieces' points, ``PiecePoints``): integrals over them are exact for piecewise
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

The sides' curves and the closest-point search: :mod:`ngdgfric.contact.curves`.
"""

from dataclasses import dataclass

import numpy as np

from .curves import CHUNK, NEWTON_STEPS, SideCurves, box_distance
from .pair_traces import lagrange

__all__ = ["PairPoints", "PiecePoints", "pair_points", "OVERHANG"]

SPLIT = 1e-6
"""A piece is split where pi changes the edge it lands on only that far (in the edge's parameter) from its ends."""
OVERHANG = 1e-9
"""A point whose closest point is an end of the other side is left out where its offset has a tangential part above
OVERHANG times the length of the edge there (module docstring)."""


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
        within = box_distance(vertices[chunk], curves.lower, curves.upper) <= reach + sag[None] + 1e-12 * radius
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
    values = (piece.weight[i_whole][:, None] * lagrange(nodes, piece.s[i_whole])).ravel() / omega[k]
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
