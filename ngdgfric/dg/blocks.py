r"""Element blocks of :math:`V_h` and of its sparse matrices: dense local matrices added into an assembled pattern.

:math:`V_h = Q \times Q` (``dg_space`` of :mod:`ngdgfric.dg.discretization`) numbers its DOFs component by
component and, within a component, element by element: the :math:`n_T = (p_T + 1)(p_T + 2) / 2` scalar functions
of element :math:`T` are the DOFs :math:`\mathrm{first}_T, \dots, \mathrm{first}_T + n_T - 1` of component 0,
and those plus :math:`\dim Q` of component 1.  A sparse matrix on :math:`V_h` whose rows of an element :math:`R`
couple to all DOFs of a set :math:`\mathrm{ring}(R)` of elements (:math:`R` and its neighbours across edges for a
DG matrix; also the neighbours' neighbours for the global lifting) stores, in every row of :math:`R`, the columns
of :math:`\mathrm{ring}(R)` in increasing order: component 0 element by element, then component 1.  So the entry
(row :math:`(c, R, k)`, column :math:`(c', S, k')`) sits at
:math:`\mathrm{rowptr}[\mathrm{row}] + \mathrm{offset}(R, S) + c' N(R) + k'` (:math:`N(R)`: the DOFs of
:math:`\mathrm{ring}(R)` per component), and a dense block over two elements lands at positions computed from a
few numbers per element pair (``Pattern``), without a search among the matrix's columns.  ``Pattern.build``
checks the row lengths.
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .dofs import element_dofs

__all__ = ["ElementBlocks", "Pattern", "neighbours"]


@dataclass(frozen=True)
class ElementBlocks:
    """The DOF layout of V_h: ``sizes`` n_T per component and element, ``first`` the first DOF of each element in
    component 0, ``stride`` dim Q (the offset of component 1)."""

    sizes: np.ndarray
    first: np.ndarray
    stride: int

    @classmethod
    def of(cls, orders, ndof):
        """The blocks of V_h with element degrees ``orders`` (ValueError unless dim V_h = ``ndof``)."""
        sizes = element_dofs(np.asarray(orders, dtype=np.int64)) // 2
        if 2 * int(sizes.sum()) != ndof:
            raise ValueError(f"a space of {ndof} DOFs does not have the element blocks of these orders")
        return cls(sizes, np.cumsum(sizes) - sizes, int(sizes.sum()))

    def dofs(self, elements, size):
        """The DOFs of ``elements`` (each with ``size`` functions per component), (count, 2 size): component 0 by
        local index, then component 1."""
        local = self.first[elements][:, None] + np.arange(size)[None, :]
        return np.concatenate([local, local + self.stride], axis=1)


def neighbours(facets):
    """(other, local): for each element and local edge (``facets``: (ne, 3) edge numbers), the element across the
    edge (-1 on the boundary) and the edge's local number in that element."""
    flat = facets.ravel()
    order = np.argsort(flat, kind="stable")
    other = np.full(flat.size, -1)
    pair = np.flatnonzero(flat[order][1:] == flat[order][:-1])
    other[order[pair]], other[order[pair + 1]] = order[pair + 1], order[pair]
    slot = np.maximum(other, 0)
    return np.where(other >= 0, slot // 3, -1).reshape(facets.shape), (slot % 3).reshape(facets.shape)


def _rings(candidates):
    """(ptr, ring): the distinct non-negative entries of every row of ``candidates`` (ne, k), sorted, as a CSR."""
    ne = len(candidates)
    rows = np.repeat(np.arange(ne), candidates.shape[1])
    valid = candidates.ravel() >= 0
    keys = np.unique(rows[valid] * ne + candidates.ravel()[valid])
    return np.concatenate([[0], np.cumsum(np.bincount(keys // ne, minlength=ne))]), keys % ne


@dataclass
class Pattern:
    """A sparse matrix on V_h (``matrix``) whose rows of element R hold the DOFs of the elements ring(R) (a CSR
    over elements: ``ring_ptr``, ``ring``, sorted per row), with what places its element blocks."""

    matrix: object
    rowptr: np.ndarray
    ring_ptr: np.ndarray
    ring: np.ndarray
    before: np.ndarray  # per entry of ring: the DOFs per component of ring(R) before it (its block's offset)
    total: np.ndarray  # per element R: the DOFs per component of ring(R)
    blocks: ElementBlocks

    @classmethod
    def build(cls, matrix, ring_ptr, ring, blocks):
        """The pattern of ``matrix`` whose rows of R couple to ``ring``; RuntimeError if its row lengths are not
        those of the element blocks (a pattern other than the one assumed)."""
        sizes, counts = blocks.sizes[ring], np.diff(ring_ptr)
        total = np.add.reduceat(sizes, ring_ptr[:-1])
        before = np.cumsum(sizes) - sizes - np.repeat(np.cumsum(total) - total, counts)
        rowptr = np.asarray(matrix.CSR()[2], dtype=np.int64)
        expected = np.tile(np.repeat(2 * total, blocks.sizes), 2)
        if matrix.height != 2 * blocks.stride or not np.array_equal(np.diff(rowptr), expected):
            raise RuntimeError("the matrix's rows do not hold the element blocks of their neighbourhoods")
        return cls(matrix, rowptr, ring_ptr, ring, before, total, blocks)

    @classmethod
    def of(cls, matrix, blocks, other):
        """The DG pattern of ``matrix``: every element with its neighbours ``other`` (ne, 3; -1: none)."""
        return cls.build(matrix, *_rings(np.column_stack([np.arange(len(other)), other])), blocks)

    @classmethod
    def two_ring(cls, blocks, other):
        """A new zero matrix on V_h whose rows of R hold R, its neighbours ``other`` and theirs (the stencil of the
        global lifting r_0), made by NGSolve's sparse product D G D^T (D: DOF -> element, G: the element pairs)."""
        ne = len(other)
        near = np.column_stack([np.arange(ne), other])  # (ne, 4), -1 for none
        second = np.where(near[:, :, None] >= 0, near[np.maximum(near, 0)], -1)
        ptr, ring = _rings(second.reshape(ne, -1))
        ndof = 2 * blocks.stride
        owner = np.tile(np.repeat(np.arange(ne), blocks.sizes), 2)
        D = ngs.la.SparseMatrixd.CreateFromCOO(np.arange(ndof), owner, np.ones(ndof), ndof, ne)
        G = ngs.la.SparseMatrixd.CreateFromCOO(np.repeat(np.arange(ne), np.diff(ptr)), ring, np.ones(len(ring)),
                                               ne, ne)
        matrix = (D @ G) @ D.CreateTranspose()
        matrix.AsVector().FV().NumPy()[:] = 0.0
        return cls.build(matrix, ptr, ring, blocks)

    def positions(self, rows, cols, n_rows, n_cols):
        """Positions in the matrix's values of the dense blocks (count, 2 n_rows, 2 n_cols) of the element pairs
        (``rows``, ``cols``) (each with n_rows, n_cols functions per component; rows and columns component 0 by
        local index, then component 1).  RuntimeError for a pair outside the pattern."""
        ne = len(self.blocks.sizes)
        keys = np.repeat(np.arange(ne), np.diff(self.ring_ptr)) * ne + self.ring
        wanted = rows * ne + cols
        at = np.minimum(np.searchsorted(keys, wanted), len(keys) - 1)
        if np.any(keys[at] != wanted):
            raise RuntimeError("an element block outside the matrix's pattern")
        kind = np.int32 if self.rowptr[-1] < 2**31 else np.int64  # half the memory traffic of int64
        local = np.arange(n_cols, dtype=kind)[None, :]
        offset = self.before[at].astype(kind)[:, None]
        columns = np.concatenate([offset + local, offset + self.total[rows].astype(kind)[:, None] + local], axis=1)
        start = self.rowptr[self.blocks.dofs(rows, n_rows)].astype(kind)  # (count, 2 n_rows)
        return start[:, :, None] + columns[:, None, :]

    def add(self, rows, cols, values):
        """Add the dense blocks ``values`` (count, 2 n_R, 2 n_S) of the element pairs (``rows``, ``cols``) into the
        matrix (pairs may repeat: their blocks add up)."""
        if len(rows):
            positions = self.positions(rows, cols, values.shape[1] // 2, values.shape[2] // 2)
            np.add.at(self.matrix.AsVector().FV().NumPy(), positions, values)

    def gather(self, rows, cols, n_rows, n_cols):
        """The dense blocks of the element pairs (``rows``, ``cols``), (count, 2 n_rows, 2 n_cols)."""
        return self.matrix.AsVector().FV().NumPy()[self.positions(rows, cols, n_rows, n_cols)]
