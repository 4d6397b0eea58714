"""Sparse-matrix plumbing: add contact blocks to a fixed linear matrix without re-assembly.

The nonlinearity of (3.1) lives on Gamma_C only, so every Jacobian is J = A + K with the linear
DG matrix A assembled once and K nonzero only in the blocks coupling the degrees of freedom of
the elements on Gamma_C.  :class:`BlockSum` builds the pattern of J once and refreshes its values
with two numpy scatters.
"""

import ngsolve as ngs
import numpy as np

__all__ = ["BlockSum", "csr_keys", "direct_inverse", "diagonal", "sparse_sum"]


def csr_keys(mat, ncols=None):
    """Sorted int64 keys row * ncols + col of the stored entries of an NGSolve sparse matrix."""
    _, cols, rowptr = mat.CSR()
    rowptr = np.asarray(rowptr, dtype=np.int64)
    rows = np.repeat(np.arange(len(rowptr) - 1, dtype=np.int64), np.diff(rowptr))
    return rows * (ncols or mat.width) + np.asarray(cols, dtype=np.int64)


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
    group x group (the contact elements' blocks).
    """

    def __init__(self, A, groups):
        n = self.n = A.height
        keys_a = csr_keys(A, n)
        keys_b = _block_keys(groups, n)
        _, found = _positions(keys_a, keys_b)
        new = keys_b[~found]
        if len(new) == 0:
            keys_j, self.J = keys_a, A.CreateMatrix()
        else:
            keys_j = np.insert(keys_a, np.searchsorted(keys_a, new), new)
            self.J = ngs.la.SparseMatrixd.CreateFromCOO(keys_j // n, keys_j % n, np.zeros(len(keys_j)), n, n)
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


def sparse_sum(terms):
    """sum_k w_k M_k for (w_k, M_k) pairs of equally sized NGSolve sparse matrices.

    If one pattern contains all others (the usual case here: liftings inside the DG pattern, or
    the DG pattern inside the two-ring pattern of r_0), the others are scattered into a copy of
    it; otherwise the union pattern is built from COO triplets.
    """
    terms = sorted(terms, key=lambda term: -term[1].nze)
    weight, base = terms[0]
    width = base.width
    base_keys = csr_keys(base, width)
    positions = []
    for _, mat in terms[1:]:
        pos, found = _positions(base_keys, csr_keys(mat, width))
        if not found.all():
            return _coo_sum(terms)
        positions.append(pos)
    out = base.CreateMatrix()
    values = out.AsVector().FV().NumPy()
    values[:] = weight * np.asarray(base.AsVector().FV().NumPy())
    for (w, mat), pos in zip(terms[1:], positions, strict=True):
        values[pos] += w * np.asarray(mat.AsVector().FV().NumPy())
    return out


def _coo_sum(terms):
    rows, cols, values = [], [], []
    for weight, mat in terms:
        r, c, v = mat.COO()
        rows.append(np.asarray(r, dtype=np.int64))
        cols.append(np.asarray(c, dtype=np.int64))
        values.append(weight * np.asarray(v))
    height, width = terms[0][1].height, terms[0][1].width
    return ngs.la.SparseMatrixd.CreateFromCOO(np.concatenate(rows), np.concatenate(cols),
                                              np.concatenate(values), height, width)
