"""Static condensation of (3.3) onto the contact traces: the Delassus operator W = B A^-1 B^T.

The nonlinearity of (3.1) lives at the M Gauss points of Gamma_C (:mod:`ngdgfric.solvers.traces`):

    A u + B^T f = F,   w = B u   =>   w = w0 - W f,   w0 = B A^-1 F,   W = B A^-1 B^T,

with f the contact forces and w the traces (u_n, u_t) at the points.  W is the Delassus operator
of contact mechanics (a 2M x 2M dense matrix, M = (p + 1) x edges on Gamma_C); once it is known
the contact problem is a small dense one (:mod:`ngdgfric.solvers.reduced`), and u = A^-1 (F - B^T f)
comes back with one more substitution.  Two ways to get W:

* ``"pardiso"``: the matrix K = [[0, B], [B^T, A]] factorised by MKL PARDISO with the Schur
  complement of its trace block, -B A^-1 B^T = -W, in one partial factorisation (Cholesky of A for the
  symmetric methods, which needs A positive definite, as NGSolve's sparsecholesky of the other path does;
  LU for NIPG); w0 comes from its forward substitution and u from its backward substitution
  (:class:`ngdgfric.solvers.pardiso.SchurFactorization`; costs in results/linear_solvers.md).
* ``"ngsolve"``: A factorised by NGSolve (sparsecholesky for symmetric A, else umfpack) and W
  assembled column by column from 2M back-substitutions: the same W, 3-11 times slower for SIPG on
  Example 6.2 from 1,536 to 15,360 DOFs, p = 2-7 (best of 3, 2026-12; at p = 7, h = 1/16 sparsecholesky
  alone took 2.5 s and the 256 back-substitutions 30 s, against 1.1 s for PARDISO's factorisation with the
  Schur complement).  Used when the ``mkl`` wheel is not installed.

The recovered u is improved by iterative refinement with A while its residual A u + B^T f - F is
above 1e-13 ||F|| (condition numbers of A reach 1e8 for nu -> 1/2).
"""

import time

import ngsolve as ngs
import numpy as np

from ..errors import SolverError
from ..sparse import direct_inverse
from ..threads import threads
from . import pardiso

__all__ = ["Condensation", "LINEAR_SOLVERS", "default_linear_solver"]

LINEAR_SOLVERS = ("auto", "pardiso", "ngsolve")


def default_linear_solver():
    """"pardiso" if MKL PARDISO is installed, else "ngsolve"."""
    return "pardiso" if pardiso.available() else "ngsolve"


def _trace_rows(traces, m):
    """CSR (int64 indptr, int32 columns, values) of the first rows [0, B] of K: each trace row's zero diagonal,
    then B's entries of that row, their columns shifted by m = 2M."""
    order = np.lexsort((traces.cols, traces.rows))
    indptr = np.zeros(m + 1, dtype=np.int64)
    np.cumsum(np.bincount(traces.rows, minlength=m) + 1, out=indptr[1:])
    cols, values = np.empty(indptr[-1], dtype=np.int32), np.zeros(indptr[-1])
    cols[indptr[:-1]] = np.arange(m)
    after_diagonal = np.ones(indptr[-1], dtype=bool)
    after_diagonal[indptr[:-1]] = False
    cols[after_diagonal], values[after_diagonal] = m + traces.cols[order], traces.values[order]
    return indptr, cols, values


def _upper_triangle(rowptr, cols, values):
    """CSR of the upper triangle (diagonal included) of a CSR matrix with sorted rows."""
    rows = np.repeat(np.arange(len(rowptr) - 1, dtype=cols.dtype), np.diff(rowptr))
    upper = cols >= rows
    indptr = np.zeros_like(rowptr)
    np.cumsum(np.bincount(rows[upper], minlength=len(rowptr) - 1), out=indptr[1:])
    return indptr, np.compress(upper, cols), np.compress(upper, values)


def augmented_matrix(A, traces, symmetric):
    """K = [[0, B], [B^T, A]] in CSR (int64 indptr, int32 columns), the 2M trace rows first (the Schur block of
    :class:`~ngdgfric.solvers.pardiso.SchurFactorization`), its zero diagonal stored; upper triangle only if
    ``symmetric``.

    With the trace rows first, K's upper triangle is the rows [0, B] followed by A's upper triangle with its
    columns shifted by 2M, two concatenations; the nonsymmetric K inserts B^T's few entries at the starts of
    A's rows.  p = 7 on Example 6.2, h = 1/16 (10.3 million entries of A), best of 5, CPU seconds, 2026-12:
    SIPG 0.135 s, NIPG 0.090 s, against 0.224 s and 0.261 s with the trace rows last (a merge per row; its
    first call in a process took up to 1.4 s).
    """
    n, m = A.height, 2 * traces.M
    values, cols, rowptr = A.CSR()
    rowptr, cols, values = np.asarray(rowptr, dtype=np.int64), np.asarray(cols, dtype=np.int32), np.asarray(values)
    if symmetric:
        rowptr, cols, values = _upper_triangle(rowptr, cols, values)
        cols = cols + np.int32(m)
    else:
        order = np.lexsort((traces.rows, traces.cols))  # B^T by rows of A
        starts = rowptr[traces.cols[order]]
        cols = np.insert(cols + np.int32(m), starts, traces.rows[order].astype(np.int32))
        values = np.insert(values, starts, traces.values[order])
        rowptr = rowptr + np.concatenate([[0], np.cumsum(np.bincount(traces.cols, minlength=n))])
    top_indptr, top_cols, top_values = _trace_rows(traces, m)
    return (np.concatenate([top_indptr, top_indptr[-1] + rowptr[1:]]), np.concatenate([top_cols, cols]),
            np.concatenate([top_values, values]))


class Condensation:
    """W, w0 and the recovery of u for the linear part ``A``, load ``F`` and ``traces``.

    linear_solver: "pardiso", "ngsolve" or "auto" (:func:`default_linear_solver`).
    Attributes: ``W`` (2M x 2M), ``w0`` (2M), ``linear_solver`` (the one used), ``seconds``
    (time to build W and w0), ``refinements`` (iterative refinement steps of the recoveries).
    """

    def __init__(self, A, F, traces, symmetric, linear_solver="auto"):
        if linear_solver not in LINEAR_SOLVERS:
            raise ValueError(f"linear_solver must be one of {LINEAR_SOLVERS}, got {linear_solver!r}")
        if linear_solver == "auto":
            linear_solver = default_linear_solver()
        if linear_solver == "pardiso" and not pardiso.available():
            raise ValueError("linear_solver='pardiso' needs MKL PARDISO: pip install mkl (or use 'ngsolve')")
        start = time.perf_counter()
        self.A, self.F, self.traces, self.linear_solver = A, F, traces, linear_solver
        self.refinements = 0
        self._F = F.FV().NumPy().copy()
        if linear_solver == "pardiso":
            indptr, cols, values = augmented_matrix(A, traces, symmetric)
            try:
                self._factorization = pardiso.SchurFactorization(indptr, cols, values, 2 * traces.M, symmetric)
            except pardiso.PardisoError as error:
                if error.code not in (-4, -7):  # not a zero pivot or a singular diagonal: PARDISO's message says it
                    raise
                raise SolverError(f"{error}: the linear part A cannot be factorised (is B_h coercive? check the "
                                  "penalty eta)", solver="newton") from error
            self.W = -self._factorization.schur
            _, minus_w0 = self._factorization.solve_eliminated(self._F, np.zeros(2 * traces.M))
            self.w0 = -minus_w0
        else:
            with threads(A.height):
                self._inverse = direct_inverse(A, symmetric)
            self.W = self._delassus_by_backsubstitution()
            self.w0 = traces.apply(self._solve(self._F))
        if symmetric:
            self.W = 0.5 * (self.W + self.W.T)
        self.seconds = time.perf_counter() - start

    def _solve(self, b):
        """A^-1 b with NGSolve's factorisation (numpy in, numpy out)."""
        rhs, out = self.F.CreateVector(), self.F.CreateVector()
        rhs.FV().NumPy()[:] = b
        with threads(len(b)):
            out.data = self._inverse * rhs
        return out.FV().NumPy().copy()

    def _delassus_by_backsubstitution(self, block=64):
        """W = B A^-1 B^T from 2M back-substitutions (in blocks of ``block`` right-hand sides)."""
        traces, m = self.traces, 2 * self.traces.M
        W = np.empty((m, m))
        rhs, out = ngs.MultiVector(self.F, block), ngs.MultiVector(self.F, block)
        for start in range(0, m, block):
            stop = min(start + block, m)
            for k in range(start, stop):
                unit = np.zeros(m)
                unit[k] = 1.0
                rhs[k - start].FV().NumPy()[:] = traces.apply_transpose(unit)
            with threads(self.A.height):
                out[:] = self._inverse * rhs
            for k in range(start, stop):
                W[:, k] = traces.apply(out[k - start].FV().NumPy())
        return W

    def displacement(self, f):
        """u = A^-1 (F - B^T f) as a numpy array, improved by iterative refinement while its residual
        F - A u - B^T f is above 1e-13 ||F|| (at most two steps)."""
        zero = np.zeros(2 * self.traces.M)
        u = self._solve_with(self._F, f)
        for _ in range(2):
            residual = self._residual(u, f)
            if np.linalg.norm(residual) <= 1e-13 * np.linalg.norm(self._F):
                break
            u = u + self._solve_with(residual, zero)
            self.refinements += 1
        return u

    def correction(self, df):
        """-A^-1 B^T df: the change of u when the forces change by df (no residual is re-evaluated, so
        its round-off is relative to the change)."""
        return self._solve_with(np.zeros_like(self._F), df)

    def _solve_with(self, b, f):
        """A^-1 (b - B^T f)."""
        if self.linear_solver == "pardiso":
            return self._factorization.solve_eliminated(b, f)[0]
        return self._solve(b - self.traces.apply_transpose(f))

    def _residual(self, u, f):
        """F - A u - B^T f."""
        vec, out = self.F.CreateVector(), self.F.CreateVector()
        vec.FV().NumPy()[:] = u
        with threads(len(u)):
            out.data = self.A * vec
        return self._F - self.traces.apply_transpose(f) - out.FV().NumPy()
