r"""The traces of :math:`V_h` at the points of the contact pairs: the rows of :math:`B` for
:math:`[u] = u^1 - u^2 \circ \pi` (:mod:`ngdgfric.contact.pairing`).

For one side, ``SideTraces`` holds the Cartesian traces :math:`u_x, u_y` at the :math:`q` Gauss nodes
:math:`s_i` of every edge, built as the foundation's traces are (:mod:`ngdgfric.contact.traces`: from the Gauss-rule
mass matrices with a facet space of degree :math:`q - 1` on the side).  The trace of :math:`u_h` on an edge is a
polynomial of degree :math:`p_T \le q - 1` in the edge's parameter :math:`s` (on curved edges too: the element map
restricted to an edge is affine in :math:`s` on the reference element), so its value at any :math:`s` is the
Lagrange interpolant of the node values, exactly.  A piece's point :math:`x_i` (edge :math:`e`, parameter
:math:`s_i`) with its closest point on the other side (edge :math:`e'`, parameter :math:`s'_i`) has the jump

.. math::

    n_i \cdot [u](x_i) = n_i \cdot \Big(\sum_j L_j(s_i)\, u^1_{e,j} - \sum_j L_j(s'_i)\, u^2_{e',j}\Big), \qquad
    t_i \cdot [u](x_i),

the normal and tangent of the pair's side, and the rows of :math:`B` at the law's points are their projection
:math:`(B u)_k = \sum_i P_{ki}\, n_i \cdot [u](x_i)`, :math:`(B u)_{M + k} = \sum_i P_{ki}\, t_i \cdot [u](x_i)`
(:mod:`ngdgfric.contact.pairing`): the pair's forces act on both bodies, opposite (:math:`B^T f` is action and
reaction).
"""

import ngsolve as ngs
import numpy as np

from ..problem import pattern
from .boundary import ContactGauss, contact_rule, facet_space
from .traces import trace_rows

__all__ = ["SideTraces", "pair_rows", "lagrange"]

CARTESIAN = (ngs.CF((1.0, 0.0)), ngs.CF((0.0, 1.0)))


def lagrange(nodes, s):
    """The Lagrange basis of ``nodes`` at the points ``s``: shape (len(s), len(nodes))."""
    s = np.asarray(s, dtype=float)[:, None]
    values = np.ones((s.shape[0], len(nodes)))
    for j, node in enumerate(nodes):
        for m, other in enumerate(nodes):
            if m != j:
                values[:, j] *= (s[:, 0] - other) / (node - other)
    return values


class SideTraces:
    """u_x and u_y of V_h at the q Gauss nodes of every edge of side ``side`` (in the order of the side's boundary
    elements; ``trace_rows`` of :mod:`ngdgfric.contact.traces` with a facet space of degree q - 1 on the side): a
    sparse matrix as ``indptr``, ``cols``, ``values`` (CSR), row (component * edges + edge) * q + i; ``nodes``: the
    q parameters s_i; ``ndof``: the dimension of V_h."""

    def __init__(self, V_plain, mesh, side, q):
        rule = contact_rule(q - 1)
        self.nodes = np.array([point.point[0] for point in rule[ngs.SEGM]])
        gauss = ContactGauss(mesh, (side,), q - 1, facet_space(mesh, pattern([side]), q - 1))
        self.edges, self.q, self.ndof = len(gauss.dofs), q, V_plain.ndof
        rows, self.cols, self.values = trace_rows(gauss, V_plain, self.ndof, CARTESIAN)
        self.indptr = np.searchsorted(rows, np.arange(2 * self.edges * q + 1))

    def combine(self, out_rows, edge, component, coefficients):
        """COO triplets of sum_i coefficients[:, i] * (row (component, edge, i) of this matrix), one output row
        ``out_rows[k]`` per entry k of ``edge``, ``component`` (arrays) and ``coefficients`` (k, q)."""
        first = (component * self.edges + edge)[:, None] * self.q + np.arange(self.q)[None]  # (k, q) source rows
        starts, stops = self.indptr[first.ravel()], self.indptr[first.ravel() + 1]
        counts = stops - starts
        picked = np.repeat(starts - np.concatenate([[0], np.cumsum(counts)[:-1]]), counts) + np.arange(counts.sum())
        return (np.repeat(np.repeat(out_rows, self.q), counts), self.cols[picked],
                np.repeat(coefficients.ravel(), counts) * self.values[picked])


def pair_rows(points, side, other):
    """COO triplets of the rows of B of one pair's ``points`` (``PairPoints``) with the ``SideTraces`` of its two
    sides, duplicates summed: normal rows 0 .. M - 1, tangential rows M .. 2 M - 1 (M = ``points.M``): the jump's
    normal and tangential parts at the pieces' points, projected onto the law's points (``points.projection``)."""
    piece, (k, i, weight) = points.piece, points.projection
    m = len(piece.edge)
    rows, cols, values = _piece_rows(piece, side, other)
    order = np.argsort(rows, kind="stable")
    rows, cols, values = rows[order], cols[order], values[order]
    indptr = np.searchsorted(rows, np.arange(2 * m + 1))
    parts = []
    for block in (0, 1):  # normal, tangential
        source = block * m + i
        starts, stops = indptr[source], indptr[source + 1]
        counts = stops - starts
        picked = np.repeat(starts - np.concatenate([[0], np.cumsum(counts)[:-1]]), counts) + np.arange(counts.sum())
        parts.append((np.repeat(block * points.M + k, counts), cols[picked],
                      np.repeat(weight, counts) * values[picked]))
    rows, cols, values = (np.concatenate(arrays) for arrays in zip(*parts, strict=True))
    return _summed(rows, cols, values, side.ndof)


def _piece_rows(piece, side, other):
    """COO triplets of n . [u] and t . [u] at the pieces' points (``PiecePoints``): rows 0 .. m - 1 and
    m .. 2 m - 1."""
    m = len(piece.edge)
    parts = []
    rows = np.arange(m)
    for row_shift, direction in ((0, piece.normal), (m, piece.tangent)):
        for traces, edge, s, sign in ((side, piece.edge, piece.s, 1.0), (other, piece.other_edge, piece.other_s, -1.0)):
            basis = lagrange(traces.nodes, s)
            for component in (0, 1):
                parts.append(traces.combine(rows + row_shift, edge, np.full(m, component),
                                            sign * direction[:, component][:, None] * basis))
    rows, cols, values = (np.concatenate(arrays) for arrays in zip(*parts, strict=True))
    return _summed(rows, cols, values, side.ndof)


def _summed(rows, cols, values, ndof):
    """COO triplets with duplicates summed and zeros dropped."""
    keys, where = np.unique(rows * ndof + cols, return_inverse=True)
    summed = np.bincount(where, weights=values)
    keep = summed != 0
    return keys[keep] // ndof, keys[keep] % ndof, summed[keep]
