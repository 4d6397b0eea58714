r"""MKL PARDISO through ctypes: a sparse factorisation that returns a Schur complement.

The contact solver (:mod:`ngdgfric.solvers.condensation`) needs the Schur complement of the last :math:`m`
rows of a sparse matrix :math:`K`, computed by one partial factorisation (PARDISO's ``iparm[35] = 2``:
the other rows are eliminated first, the dense :math:`m \times m` Schur complement is returned), and solves
with the eliminated block through the forward (phase 331) and backward (phase 333) substitutions
of that factorisation.  NGSolve's own direct solvers (sparsecholesky, umfpack) have no Schur
complement; PARDISO comes with the ``mkl`` wheel from PyPI (x86_64), which NGSolve's wheel also
finds at run time.  ``available()`` says whether it is there; without it the contact solver
takes a slower path with NGSolve's solvers (same results).

Reference: Intel oneMKL Developer Reference, "pardiso" and "pardiso iparm Parameter"
(iparm[35], phases 331-333); PETSc's ``mkl_pardiso.c`` uses the same sequence.
"""

import ctypes
import importlib.metadata

import numpy as np

from ..errors import SolverError

__all__ = ["available", "SchurFactorization", "Factorization", "PardisoError", "PHASES"]

_LIBRARY = None
PHASES = {11: "analysis", 12: "analysis and factorisation", 22: "numerical factorisation",
          33: "solve", 331: "forward substitution", 332: "diagonal substitution",
          333: "backward substitution", -1: "release of memory"}
ERRORS = {-1: "input inconsistent", -2: "not enough memory", -3: "reordering problem", -4: "zero pivot",
          -5: "unclassified (internal) error", -6: "reordering failed", -7: "diagonal matrix is singular",
          -8: "32-bit integer overflow", -9: "not enough memory for OOC", -10: "error opening OOC files",
          -11: "read/write error with OOC files", -12: "pardiso_64 called from 32-bit library"}


class PardisoError(SolverError):
    """PARDISO returned an error code: a failure of the contact solver.

    A :class:`ngdgfric.SolverError` (exit code 1 of the command line), raised by :func:`ngdgfric.solve` with
    ``linear_solver="pardiso"`` or ``"auto"`` (:class:`ngdgfric.NewtonOptions`) when MKL PARDISO fails.

    Parameters
    ----------
    message : str
        What failed.
    phase : int or None, optional
        PARDISO's phase number (e.g. ``11`` analysis, ``22`` numerical factorisation).  Default ``None``: the
        library is missing.
    code : int or None, optional
        PARDISO's error code (oneMKL reference, "pardiso": ``-4`` zero pivot, ``-2`` out of memory, ...).
        Default ``None``.

    Attributes
    ----------
    phase : int or None
        PARDISO's phase number.
    code : int or None
        PARDISO's error code.
    """

    def __init__(self, message, phase=None, code=None):
        super().__init__(message, solver="MKL PARDISO")
        self.phase, self.code = phase, code


def _library():
    """libmkl_rt from the ``mkl`` wheel (None if it is not installed or does not load)."""
    global _LIBRARY
    if _LIBRARY is None:
        _LIBRARY = False
        try:
            dist = importlib.metadata.distribution("mkl")
        except importlib.metadata.PackageNotFoundError:
            return None
        for file in dist.files or []:
            if "mkl_rt" in file.name and ".so" in file.name or file.name.startswith("mkl_rt") and file.suffix == ".dll":
                try:
                    lib = ctypes.CDLL(str(dist.locate_file(file)))
                    lib.pardiso.restype = None
                    lib.pardisoinit.restype = None
                    _LIBRARY = lib
                    break
                except (OSError, AttributeError):
                    continue
    return _LIBRARY or None


def available():
    """True if MKL PARDISO can be loaded (``pip install mkl``)."""
    return _library() is not None


def _pointer(array):
    return array.ctypes.data_as(ctypes.c_void_p)


class SchurFactorization:
    """PARDISO factorisation of a square CSR matrix K with the Schur complement of its last rows.

    indptr, indices, data: K in CSR (0-based, column indices sorted in each row); for
    ``symmetric`` only the upper triangle, diagonal included (also where it is zero).
    n_schur: the last ``n_schur`` rows and columns form the Schur block.  ``symmetric``: K is
    real symmetric (PARDISO's symmetric indefinite type -2, Bunch-Kaufman pivots), else real
    nonsymmetric (type 11).  Pivots of the eliminated block below 1e-13 times the largest are
    perturbed (iparm[9] = 13), so that block must be nonsingular, as a coercive B_h is.

    After construction ``schur`` holds K_SS - K_SI K_II^-1 K_IS (dense, n_schur x n_schur) and
    ``solve_eliminated`` solves with K_II.
    """

    def __init__(self, indptr, indices, data, n_schur, symmetric):
        lib = _library()
        if lib is None:
            raise PardisoError("MKL PARDISO is not available: pip install mkl")
        self._lib = lib
        self.n = len(indptr) - 1
        self.n_schur = int(n_schur)
        if not 0 < self.n_schur < self.n:
            raise ValueError(f"n_schur must be in (0, {self.n}), got {n_schur}")
        self._indptr = np.ascontiguousarray(indptr, dtype=np.int32)
        self._indices = np.ascontiguousarray(indices, dtype=np.int32)
        self._data = np.ascontiguousarray(data, dtype=np.float64)
        self._mtype = np.array([-2 if symmetric else 11], dtype=np.int32)
        self._pt = np.zeros(64, dtype=np.int64)
        self._iparm = np.zeros(64, dtype=np.int32)
        lib.pardisoinit(_pointer(self._pt), _pointer(self._mtype), _pointer(self._iparm))
        self._iparm[7] = 0    # no iterative refinement (partial solves cannot refine)
        self._iparm[9] = 13   # pivot perturbation 1e-13
        self._iparm[12] = 0   # no weighted matching (keeps the Schur rows last)
        self._iparm[34] = 1   # 0-based indices
        self._iparm[35] = 2   # Schur complement, factorisation kept for partial solves
        self._perm = np.zeros(self.n, dtype=np.int32)
        self._perm[self.n - self.n_schur:] = 1
        self.schur = np.zeros((self.n_schur, self.n_schur))
        self._released = False
        self._call(12, x=self.schur)  # analysis + numerical factorisation + Schur complement
        if not symmetric:  # returned row by row
            self.schur = np.ascontiguousarray(self.schur)

    def _call(self, phase, b=None, x=None, nrhs=1):
        error = np.zeros(1, dtype=np.int32)
        one = np.ones(1, dtype=np.int32)
        null = ctypes.c_void_p(0)
        self._lib.pardiso(_pointer(self._pt), _pointer(one), _pointer(one), _pointer(self._mtype),
                          _pointer(np.array([phase], dtype=np.int32)), _pointer(np.array([self.n], dtype=np.int32)),
                          _pointer(self._data), _pointer(self._indptr), _pointer(self._indices),
                          _pointer(self._perm), _pointer(np.array([nrhs], dtype=np.int32)), _pointer(self._iparm),
                          _pointer(np.zeros(1, dtype=np.int32)), null if b is None else _pointer(b),
                          null if x is None else _pointer(x), _pointer(error))
        if error[0] != 0:
            code = int(error[0])
            raise PardisoError(f"MKL PARDISO failed in phase {phase} ({PHASES.get(phase, 'unknown phase')}) with "
                               f"error {code} ({ERRORS.get(code, 'see the oneMKL reference')})", phase, code)

    def solve_eliminated(self, b_eliminated, x_schur):
        """x_I = K_II^-1 (b_I - K_IS x_S): the eliminated unknowns for given Schur unknowns.

        Returns (x_I, r_S) with r_S = b_S - K_SI K_II^-1 b_I for b_S = 0, the right-hand side the
        Schur system would have (forward substitution, phase 331), and x_I from the backward
        substitution (phase 333) with the Schur part of the solution set to ``x_schur``.
        """
        m = self.n - self.n_schur
        b = np.zeros(self.n)
        b[:m] = b_eliminated
        x = np.zeros(self.n)
        self._call(331, b=b, x=x)
        r_schur = x[m:].copy()
        if self._mtype[0] == -2:  # symmetric indefinite: D^-1 between the triangular solves
            y = np.zeros(self.n)
            self._call(332, b=x, x=y)
            x = y
        x[m:] = x_schur
        out = np.zeros(self.n)
        self._call(333, b=x, x=out)
        return out[:m], r_schur

    def release(self):
        """Free PARDISO's memory (also done when the object is garbage collected)."""
        if not self._released:
            self._released = True
            self._call(-1)

    def __del__(self):
        try:
            self.release()
        except Exception:  # interpreter shutdown
            pass


class Factorization:
    """PARDISO factorisation of a real symmetric indefinite matrix K in CSR (upper triangle, diagonal stored,
    0-based, sorted columns) whose values change while its pattern stays: one analysis (phase 11), a numerical
    factorisation per set of values (``factor``, phase 22) and solves with any number of right-hand sides
    (``solve``, phase 33).  For the full-space contact solver (:mod:`ngdgfric.solvers.fullspace`), whose
    Newton matrices are saddle-point matrices [[A, B^T], [B, -C]] with C >= 0: Bunch-Kaufman pivots (type -2),
    pivots below 1e-8 perturbed (iparm[9] = 8), no iterative refinement (the Newton iteration refines).  Without
    weighted matching and scaling (iparm[10] = iparm[12] = 0): with them the analysis took 0.52 s instead of 0.24 s
    and the factorisations 0.063 s instead of 0.054 s (long strip, cg P4, 105,042 unknowns, M = 2,500), and the
    solutions agreed with the condensed solver's to the same 1e-12."""

    def __init__(self, indptr, indices, data):
        lib = _library()
        if lib is None:
            raise PardisoError("MKL PARDISO is not available: pip install mkl")
        self._lib = lib
        self.n = len(indptr) - 1
        self._indptr = np.ascontiguousarray(indptr, dtype=np.int32)
        self._indices = np.ascontiguousarray(indices, dtype=np.int32)
        self._data = np.ascontiguousarray(data, dtype=np.float64)
        self._mtype = np.array([-2], dtype=np.int32)
        self._pt = np.zeros(64, dtype=np.int64)
        self._iparm = np.zeros(64, dtype=np.int32)
        lib.pardisoinit(_pointer(self._pt), _pointer(self._mtype), _pointer(self._iparm))
        self._iparm[7] = 0    # no iterative refinement: the Newton iteration refines
        self._iparm[9] = 8    # pivot perturbation 1e-8
        self._iparm[10] = 0   # no scaling
        self._iparm[12] = 0   # no weighted matching
        self._iparm[34] = 1   # 0-based indices
        self._perm = np.zeros(self.n, dtype=np.int32)
        self._released = False
        self.factorizations = 0
        self._call(11)

    _call = SchurFactorization._call
    release = SchurFactorization.release
    __del__ = SchurFactorization.__del__

    @property
    def memory_bytes(self):
        """PARDISO's peak memory so far: the larger of the analysis' peak and the permanent plus factorisation memory
        (iparm[14], iparm[15] + iparm[16], reported in kB)."""
        return 1024 * max(int(self._iparm[14]), int(self._iparm[15]) + int(self._iparm[16]))

    def factor(self, data):
        """Numerical factorisation with the values ``data`` (same pattern)."""
        self._data[:] = data
        self._call(22)
        self.factorizations += 1

    def solve(self, b):
        """K^-1 b for b of shape (n,) or (n, k) (k right-hand sides)."""
        b = np.asarray(b, dtype=np.float64)
        columns = 1 if b.ndim == 1 else b.shape[1]
        rhs = np.asfortranarray(b.reshape(self.n, columns))
        x = np.zeros_like(rhs, order="F")
        self._call(33, b=rhs, x=x, nrhs=columns)
        return x.reshape(b.shape)
