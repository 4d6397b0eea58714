r"""Static condensation of (3.3) onto the contact traces: the Delassus operator :math:`W = B A^{-1} B^T`.

The nonlinearity of (3.1) lives at the :math:`M` Gauss points of :math:`\Gamma_C` (:mod:`ngdgfric.contact.traces`):

.. math::

    A u + B^T f = F, \quad w = B u \quad \Longrightarrow \quad w = w_0 - W f, \quad w_0 = B A^{-1} F,
    \quad W = B A^{-1} B^T,

with :math:`f` the contact forces and :math:`w` the traces :math:`(u_n, u_t)` at the points.  :math:`W` is the
Delassus operator of contact mechanics (a :math:`2M \times 2M` dense matrix, :math:`M = (p + 1) \times` edges on
:math:`\Gamma_C`); once it is known the contact problem is a small dense one (:mod:`ngdgfric.solvers.reduced`),
and :math:`u = A^{-1} (F - B^T f)` comes back with one more substitution.  Two ways to get :math:`W`:

* ``"pardiso"``: the matrix :math:`K = \begin{pmatrix} A & B^T \\ B & 0 \end{pmatrix}` factorised by MKL PARDISO
  with the Schur complement of its trace block, :math:`K_{SS} - B A^{-1} B^T = -W`, in one partial factorisation
  (it costs 1.3-2 factorisations of :math:`A`, measured on the results page *Sparse direct solvers for the
  contact solver*); :math:`w_0` comes
  from its forward substitution and :math:`u` from its backward substitution (``SchurFactorization`` of
  :mod:`ngdgfric.solvers.pardiso`).
* ``"ngsolve"``: :math:`A` factorised by NGSolve (sparsecholesky for symmetric :math:`A`, else umfpack) and
  :math:`W` assembled column by column from :math:`2M` back-substitutions: the same :math:`W`, slower on large
  meshes.  Used when the ``mkl`` wheel is not installed.

The recovered :math:`u` is improved by iterative refinement with :math:`A` while its residual
:math:`A u + B^T f - F` is above :math:`10^{-13} \|F\|` (condition numbers of :math:`A` reach :math:`10^8` for
:math:`\nu \to 1/2`).
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


def _csr(mat):
    values, cols, rowptr = mat.CSR()
    return np.array(rowptr, dtype=np.int64), np.array(cols, dtype=np.int64), np.array(values)


def _stack_rows(n_rows, parts):
    """CSR arrays of the sum of COO ``parts`` (rows, cols, values), each sorted by row and then
    column, where in every row all columns of a later part are larger than those of earlier parts
    (so the concatenation per row is sorted).  Linear time, no sort."""
    counts = [np.bincount(rows, minlength=n_rows) for rows, _, _ in parts]
    indptr = np.zeros(n_rows + 1, dtype=np.int64)
    np.cumsum(np.sum(counts, axis=0), out=indptr[1:])
    total = int(indptr[-1])
    cols_out, values_out = np.empty(total, dtype=np.int64), np.empty(total)
    offset = indptr[:-1].copy()
    for (rows, cols, values), count in zip(parts, counts, strict=True):
        first = np.zeros(n_rows + 1, dtype=np.int64)
        np.cumsum(count, out=first[1:])
        position = offset[rows] + np.arange(len(rows)) - first[rows]
        cols_out[position], values_out[position] = cols, values
        offset += count
    return indptr, cols_out, values_out


def augmented_matrix(A, traces, symmetric):
    """K = [[A, B^T], [B, 0]] in CSR (upper triangle only if ``symmetric``), diagonal stored."""
    n, m = A.height, 2 * traces.M
    rowptr, cols, values = _csr(A)
    rows = np.repeat(np.arange(n, dtype=np.int64), np.diff(rowptr))
    if symmetric:
        upper = cols >= rows
        rows, cols, values = rows[upper], cols[upper], values[upper]
    by_column = np.lexsort((traces.rows, traces.cols))  # B^T by rows of A
    bt = (traces.cols[by_column], n + traces.rows[by_column], traces.values[by_column])
    diagonal = (n + np.arange(m), n + np.arange(m), np.zeros(m))
    if symmetric:
        return _stack_rows(n + m, [(rows, cols, values), bt, diagonal])
    by_row = np.lexsort((traces.cols, traces.rows))
    b = (n + traces.rows[by_row], traces.cols[by_row], traces.values[by_row])
    return _stack_rows(n + m, [(rows, cols, values), bt, b, diagonal])


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

    def reload(self, F):
        """Take the load vector ``F`` (an array) from now on; returns its w0 = B A^-1 F."""
        self._F = np.asarray(F, dtype=float).copy()
        if self.linear_solver == "pardiso":
            self.w0 = -self._factorization.solve_eliminated(self._F, np.zeros(2 * self.traces.M))[1]
        else:
            self.w0 = self.traces.apply(self._solve(self._F))
        return self.w0

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
