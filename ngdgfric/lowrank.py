"""Low-rank corrections of a factorised contact Jacobian (Sherman-Morrison-Woodbury).

A Jacobian J differs from the factorised J_0 only in the dense blocks of the contact elements,
and from one Newton step to the next only in the blocks of the elements where a Gauss point
changed its set (stick/slip, penetrating or not): each such point changes J by a rank-one term.
Writing the change of block g in the diagonal scaling S = diag(|A_ii|^-1/2) as a truncated
singular value decomposition S (J - J_0)_g S ~ U_g Sigma_g V_g^T (singular values above ``tol``),

    J ~ J_0 + U V^T,    J^-1 b ~ y - Z (I + V^T Z)^-1 V^T y,    y = J_0^-1 b,  Z = J_0^-1 U,

costs one back-substitution per retained singular value (the columns of Z, kept while the block
does not change again) instead of a new factorisation, plus one back-substitution per solve.
What the truncation drops (changes below ``tol``, e.g. a soft c_n) is removed by iterative
refinement with the exact J.
"""

import numpy as np

from .linalg import threads

__all__ = ["LowRankUpdate"]


class LowRankUpdate:
    """Solves with J_0 + (low-rank changes in the contact blocks), J_0^-1 given.

    inverse: J_0^-1 (an NGSolve operator); dofs: (G, m) dof numbers of the contact blocks
    (padded with -1); root_diagonal: (n,) |A_ii|^1/2, the inverse of the scaling S; blocks_0:
    (G, m, m) scaled blocks of J_0; vector: an NGSolve vector of the right size.
    """

    def __init__(self, inverse, dofs, root_diagonal, blocks_0, vector, tol):
        self.inverse, self.blocks_0, self.tol = inverse, blocks_0, tol
        self.root_diagonal = root_diagonal
        self._valid = dofs >= 0
        self._index = np.where(self._valid, dofs, 0)
        self._vec, self._out = vector.CreateVector(), vector.CreateVector()
        self._cache = {}  # group -> (scaled change, U_g, V_g, Z_g)
        self._Z = self._V = self._rows = self._capacitance = None

    def columns_needed(self, blocks):
        """Back-substitutions :meth:`prepare` would need for the scaled blocks of the new J."""
        return sum(self._rank(g, delta) for g, delta in self._changed(blocks) if not self._cached(g, delta))

    def prepare(self, blocks):
        """Make :meth:`apply` solve with the J whose scaled contact blocks are ``blocks``."""
        active = []
        for g, delta in self._changed(blocks):
            if not self._cached(g, delta):
                self._cache[g] = (delta, *self._columns(g, delta))
            active.append(g)
        self._cache = {g: self._cache[g] for g in active}  # memory stays bounded by the active rank
        if not active:
            self._Z = None
            return
        self._Z = np.hstack([self._cache[g][3] for g in active])
        self._V = np.concatenate([self._cache[g][2].T for g in active])  # (r, m): rows of V^T
        self._rows = np.concatenate([np.repeat(self._index[g][None], self._cache[g][2].shape[1], axis=0)
                                     for g in active])
        VZ = np.einsum("rm,rms->rs", self._V, self._Z[self._rows])
        self._capacitance = np.linalg.inv(np.eye(len(VZ)) + VZ)

    def apply(self, b, x):
        """x = (J_0 + U V^T)^-1 b."""
        with threads(len(b)):
            x.data = self.inverse * b
        if self._Z is None:
            return
        y = x.FV().NumPy()
        t = np.sum(self._V * y[self._rows], axis=1)
        y -= self._Z @ (self._capacitance @ t)

    @property
    def rank(self):
        return 0 if self._Z is None else self._Z.shape[1]

    def _changed(self, blocks):
        delta = blocks - self.blocks_0
        size = np.max(np.abs(delta), axis=(1, 2), initial=0.0)
        return [(g, delta[g]) for g in np.flatnonzero(size > self.tol)]

    def _cached(self, g, delta):
        return g in self._cache and np.array_equal(self._cache[g][0], delta)

    def _rank(self, g, delta):
        return int(np.sum(np.linalg.svd(delta, compute_uv=False) > self.tol))

    def _columns(self, g, delta):
        u, sigma, vt = np.linalg.svd(delta)
        keep = sigma > self.tol
        s = np.where(self._valid[g], self.root_diagonal[self._index[g]], 0.0)
        U = s[:, None] * u[:, keep] * sigma[keep]  # J - J_0 ~ (S^-1 u sigma)(S^-1 v)^T, S^-1 = s
        V = s[:, None] * vt[keep].T
        Z = np.empty((len(self.root_diagonal), U.shape[1]))
        column, out = self._vec, self._out
        for k in range(U.shape[1]):
            column[:] = 0.0
            column.FV().NumPy()[self._index[g]] += np.where(self._valid[g], U[:, k], 0.0)
            with threads(len(column)):
                out.data = self.inverse * column
            Z[:, k] = out.FV().NumPy()
        return U, V, Z
