r"""The traces of :math:`V_h` at the points of the contact pairs: the rows of :math:`B` for
:math:`[u] = u^1 - u^2 \circ \pi` (:mod:`ngdgfric.contact.pairing`).

For one side, ``SideTraces`` holds the Cartesian traces :math:`u_x, u_y` at the :math:`q` Gauss nodes
:math:`s_i` of every edge, built as the foundation's traces are (:mod:`ngdgfric.contact.traces`: from the Gauss-rule
mass matrices with a facet space of degree :math:`q - 1` on the side).  The trace of :math:`u_h` on an edge is a
polynomial of degree :math:`p_T \le q - 1` in the edge's parameter :math:`s` (on curved edges too: the element map
restricted to an edge is affine in :math:`s` on the reference element), so its value at any :math:`s` is the
Lagrange interpolant of the node values, exactly.  A pair point :math:`x_k` (edge :math:`e`, parameter :math:`s_k`)
with its closest point on the other side (edge :math:`e'`, parameter :math:`s'_k`) gets the rows

.. math::

    (B u)_k = n_k \cdot \Big(\sum_i L_i(s_k)\, u^1_{e,i} - \sum_i L_i(s'_k)\, u^2_{e',i}\Big), \qquad
    (B u)_{M + k} = t_k \cdot (\ldots),

the normal and tangent of the pair's side: the pair's forces act on both bodies, opposite
(:math:`B^T f` is action and reaction).
"""

import ngsolve as ngs
import numpy as np

from ..problem import pattern
from ..threads import threads
from .boundary import contact_rule, edge_jacobians

__all__ = ["SideTraces", "pair_rows", "lagrange"]


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
    elements): a sparse matrix as ``indptr``, ``cols``, ``values`` (CSR), row (component * edges + edge) * q + i;
    ``nodes``: the q parameters s_i."""

    def __init__(self, V, V_plain, mesh, side, q):
        region = mesh.Boundaries(pattern([side]))
        rule = contact_rule(q - 1)
        self.nodes = np.array([point.point[0] for point in rule[ngs.SEGM]])
        weights = np.array([point.weight for point in rule[ngs.SEGM]])
        full = ngs.FacetFESpace(mesh, order=q - 1)
        Q = ngs.Compress(full, active_dofs=full.GetDofs(region))
        edges = [el for el in mesh.Elements(ngs.BND) if el.mat == side]
        self.edges, self.q = len(edges), q
        points = mesh.MapToAllElements(rule, region)
        omega = np.tile(weights, self.edges) * edge_jacobians(points)
        dofs = np.array([list(Q.GetDofNrs(el)) for el in edges], dtype=np.int64).reshape(-1, q)
        probe = ngs.GridFunction(Q)
        vandermonde = np.empty((self.edges, q, q))
        for k in range(q):
            probe.vec[:] = 0.0
            probe.vec.FV().NumPy()[dofs[:, k]] = 1.0
            vandermonde[:, :, k] = np.asarray(probe(points)).reshape(-1, q)
        inverse_t = np.linalg.inv(vandermonde).transpose(0, 2, 1)
        edge_of = np.empty(Q.ndof, dtype=np.int64)
        index_of = np.empty(Q.ndof, dtype=np.int64)
        edge_of[dofs.ravel()] = np.repeat(np.arange(self.edges), q)
        index_of[dofs.ravel()] = np.tile(np.arange(q), self.edges)
        dS = ngs.ds(skeleton=True, definedon=region, intrules=rule)
        rows, cols, values = [], [], []
        for component, direction in enumerate((ngs.CF((1.0, 0.0)), ngs.CF((0.0, 1.0)))):
            mu, v = Q.TrialFunction(), V_plain.TestFunction()
            form = ngs.BilinearForm(trialspace=Q, testspace=V_plain)
            form += mu * (v * direction) * dS
            with threads(V.ndof):
                form.Assemble()
            data, col, rowptr = form.mat.CSR()
            rowptr = np.array(rowptr, dtype=np.int64)
            v_dof = np.repeat(np.arange(form.mat.height, dtype=np.int64), np.diff(rowptr))
            q_dof, entry = np.array(col, dtype=np.int64), np.array(data)
            e, k = edge_of[q_dof], index_of[q_dof]
            for i in range(q):
                rows.append((component * self.edges + e) * q + i)
                cols.append(v_dof)
                values.append(inverse_t[e, i, k] * entry / omega[e * q + i])
        rows, cols, values = np.concatenate(rows), np.concatenate(cols), np.concatenate(values)
        keys, where = np.unique(rows * V.ndof + cols, return_inverse=True)
        summed = np.bincount(where, weights=values)
        keep = np.abs(summed) > 1e-13 * np.max(np.abs(summed), initial=0.0)
        rows, self.cols, self.values = keys[keep] // V.ndof, keys[keep] % V.ndof, summed[keep]
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


def pair_rows(points, side, other, offset, M):
    """COO triplets of the rows of B of one pair's ``points`` (``PairPoints``) with the ``SideTraces`` of its two
    sides; normal rows from ``offset``, tangential rows from ``M + offset`` (M: all points of the mesh)."""
    parts = []
    rows = offset + np.arange(points.M)
    for row_shift, direction in ((0, points.normal), (M, points.tangent)):
        for traces, edge, s, sign in ((side, points.edge, points.s, 1.0),
                                      (other, points.other_edge, points.other_s, -1.0)):
            basis = lagrange(traces.nodes, s)
            for component in (0, 1):
                parts.append(traces.combine(rows + row_shift, edge, np.full(points.M, component),
                                            sign * direction[:, component][:, None] * basis))
    return tuple(np.concatenate(arrays) for arrays in zip(*parts, strict=True))
