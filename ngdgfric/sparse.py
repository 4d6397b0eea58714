r"""Sparse-matrix plumbing: add contact blocks to a fixed linear matrix without re-assembly.

The nonlinearity of (3.1) lives on :math:`\Gamma_C` only, so every Jacobian is :math:`J = A + K` with the linear
DG matrix :math:`A` assembled once and :math:`K` nonzero only in the blocks coupling the degrees of freedom of the
elements on :math:`\Gamma_C`.  ``BlockSum`` builds the pattern of :math:`J` once and refreshes its values with two
numpy scatters.
"""

import ngsolve as ngs
import numpy as np

__all__ = ["BlockSum", "csr_keys", "nonzero_keys", "direct_inverse", "diagonal"]


def csr_keys(mat, ncols=None):
    """Sorted int64 keys row * ncols + col of the stored entries of an NGSolve sparse matrix."""
    _, cols, rowptr = mat.CSR()
    rowptr = np.asarray(rowptr, dtype=np.int64)
    rows = np.repeat(np.arange(len(rowptr) - 1, dtype=np.int64), np.diff(rowptr))
    return rows * (ncols or mat.width) + np.asarray(cols, dtype=np.int64)


def nonzero_keys(mat, ncols=None):
    """Sorted int64 keys row * ncols + col of the nonzero entries of an NGSolve sparse matrix."""
    return csr_keys(mat, ncols)[np.asarray(mat.AsVector().FV().NumPy()) != 0]


def _block_keys(groups, n):
    keys = [np.add.outer(np.asarray(g, dtype=np.int64) * n, np.asarray(g, dtype=np.int64)).ravel()
            for g in groups if len(g)]
    return np.unique(np.concatenate(keys)) if keys else np.zeros(0, dtype=np.int64)


def _positions(sorted_keys, keys):
    """Positions of ``keys`` in ``sorted_keys`` and a mask of those present."""
    pos = np.searchsorted(sorted_keys, keys)
    pos_clipped = np.minimum(pos, len(sorted_keys) - 1)
    found = sorted_keys[pos_clipped] == keys if len(sorted_keys) else np.zeros(len(keys), bool)
    return pos_clipped, found


class BlockSum:
    """J = A + K with K restricted to dense blocks ``groups`` x ``groups``.

    A: NGSolve sparse matrix; groups: lists of dof numbers; K may be nonzero only inside each
    group x group (the contact elements' blocks).  ``pattern`` instead of groups: a sparse matrix whose nonzero
    entries are those K may have.
    """

    def __init__(self, A, groups=(), pattern=None):
        n = self.n = A.height
        keys_a = csr_keys(A, n)
        keys_b = _block_keys(groups, n) if pattern is None else nonzero_keys(pattern, n)
        _, found = _positions(keys_a, keys_b)
        new = keys_b[~found]
        if len(new) == 0:
            keys_j, self.J = keys_a, A.CreateMatrix()
        else:
            keys_j = np.insert(keys_a, np.searchsorted(keys_a, new), new)
            self.J = ngs.la.SparseMatrixd.CreateFromCOO(keys_j // n, keys_j % n, np.zeros(len(keys_j)), n, n)
        self._keys_j = keys_j
        self._pos_b = np.searchsorted(keys_j, keys_b)
        self._keys_b = keys_b
        self._k_positions = None
        values = self.J.AsVector().FV().NumPy()
        values[:] = 0.0
        values[np.searchsorted(keys_j, keys_a)] = A.AsVector().FV().NumPy()
        self._a_blocks = values[self._pos_b].copy()  # J = A outside the blocks, for good

    def update(self, K):
        """Set J = A + K (K restricted to the blocks) and return J."""
        if self._k_positions is None:
            self._k_positions = _positions(csr_keys(K, self.n), self._keys_b)
        pos, found = self._k_positions
        values = self.J.AsVector().FV().NumPy()
        values[self._pos_b] = self._a_blocks
        values[self._pos_b[found]] += K.AsVector().FV().NumPy()[pos[found]]
        return self.J

    def add(self, rows, cols, values):
        """J += the COO triplets (rows, cols, values), which lie in the blocks (after :meth:`update`); returns J."""
        np.add.at(self.J.AsVector().FV().NumPy(), np.searchsorted(self._keys_j, rows * self.n + cols), values)
        return self.J


def direct_inverse(mat, symmetric):
    """Sparse direct inverse: Cholesky for symmetric positive definite matrices, else UMFPACK."""
    return mat.Inverse(inverse="sparsecholesky" if symmetric else "umfpack")


def diagonal(mat):
    """The diagonal of an NGSolve sparse matrix as a numpy array."""
    values, cols, rowptr = mat.CSR()
    rowptr = np.asarray(rowptr, dtype=np.int64)
    rows = np.repeat(np.arange(len(rowptr) - 1, dtype=np.int64), np.diff(rowptr))
    on_diagonal = rows == np.asarray(cols, dtype=np.int64)
    out = np.zeros(mat.height)
    out[rows[on_diagonal]] = np.asarray(values)[on_diagonal]
    return out
