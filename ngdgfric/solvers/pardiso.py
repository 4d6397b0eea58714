"""MKL PARDISO through ctypes: a sparse factorisation that returns a Schur complement.

The contact solver (:mod:`ngdgfric.solvers.condensation`) needs the Schur complement of the first ``m``
rows of a sparse matrix K, computed by one partial factorisation (PARDISO's ``iparm[35] = 1``:
the other rows are eliminated, the dense m x m Schur complement is returned), and solves with the
eliminated block through the forward (phase 331) and backward (phase 333) substitutions of that
factorisation.  NGSolve's own direct solvers (sparsecholesky, umfpack) have no Schur complement;
PARDISO comes with the ``mkl`` wheel from PyPI (x86_64), which NGSolve's wheel also finds at run
time.  :func:`available` says whether it is there; without it the contact solver takes a slower path
with NGSolve's solvers (same results).

**What is used** (measured on the matrices of Example 6.2, h = 1/16, one MKL thread, CPU seconds of analysis +
factorisation, best of 3, 2026-12, issue 38):

* a symmetric K whose eliminated block is positive definite (the DG matrix A of SIPG, Bassi, Brezzi, LDG and
  cg with a coercive penalty): Cholesky, PARDISO's type 2, 0.96 s at p = 7 (36,864 DOFs) against 1.22 s with
  the symmetric indefinite type -2 used before (Bunch-Kaufman pivots; numerical phase 0.50 s against 0.74 s),
  the same fill; a nonsymmetric K (NIPG): type 11;
* ``iparm[35] = 1``: the Schur complement without factorising it.  K's Schur block is -B A^-1 B^T, negative
  definite, and with ``iparm[35] = 2`` PARDISO also factorises it, which type 2 refuses (error -4); the partial
  substitutions 331 and 333 work after either (checked against dense linear algebra in tests/test_pardiso.py);
* one MKL thread for small systems (:func:`mkl_threads`).

**Tried and not used** (same measurements): PARDISO's structurally symmetric type 1 for NIPG, 10 % faster
(1.76 s against 1.96 s, the same factors: its analysis skips forming the pattern of K + K^T), factorised a
matrix whose pattern is not symmetric silently wrong (a 5x error in the Schur complement) or crashed, and
checking the pattern costs a sort of K's entries.  Block storage crashed together with a Schur complement,
both BSR (``iparm[36] = 2``, the x and y components of a DOF as 2 x 2 blocks) and VBSR (``iparm[36] < 0``).
Minimum degree ordering (``iparm[1] = 0``) gives the same factor as nested dissection once a Schur complement is
asked for; the two-level factorisation (``iparm[23] = 1`` or 10) was no faster on two cores.  W from a plain
Cholesky of A and 2M forward substitutions, W = Y^T Y with Y = L^-1 B^T: 1.09 s with minimum degree (the
factorisation alone 0.69 s, the dense substitutions 0.25 s), 0.99 s with VBSR (analysis 0.16 s instead of
0.34 s) but W 5e-11 away; marking B^T's rows as a sparse right-hand side (``iparm[30] = 2``) made the
substitutions cheap (0.03 s) and the factorisation dearer (1.04 s).

Reference: Intel oneMKL Developer Reference, "pardiso" and "pardiso iparm Parameter"
(iparm[35], phases 331-333); PETSc's ``mkl_pardiso.c`` uses the same sequence.
"""

import ctypes
import importlib.metadata
import time

import numpy as np

from ..errors import SolverError
from ..threads import PARALLEL_FROM

__all__ = ["available", "SchurFactorization", "PardisoError", "PHASES", "mkl_threads"]

_LIBRARY = None
PHASES = {11: "analysis", 22: "numerical factorisation", 331: "forward substitution", 333: "backward substitution",
          -1: "release of memory"}
ERRORS = {-1: "input inconsistent", -2: "not enough memory", -3: "reordering problem", -4: "zero or negative pivot",
          -5: "unclassified (internal) error", -6: "reordering failed", -7: "diagonal matrix is singular",
          -8: "32-bit integer overflow", -9: "not enough memory for OOC", -10: "error opening OOC files",
          -11: "read/write error with OOC files", -12: "pardiso_64 called from 32-bit library"}


class PardisoError(SolverError):
    """PARDISO returned an error code: a failure of the contact solver (a :class:`~ngdgfric.errors.SolverError`,
    exit code 1 of the command line).  ``phase``: PARDISO's phase number (None: the library is missing);
    ``code``: its error code (oneMKL reference, "pardiso": -4 zero or negative pivot, -2 out of memory, ...)."""

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
                    lib.MKL_Set_Num_Threads_Local.restype = ctypes.c_int
                    lib.MKL_Set_Num_Threads_Local.argtypes = [ctypes.c_int]
                    _LIBRARY = lib
                    break
                except (OSError, AttributeError):
                    continue
    return _LIBRARY or None


def available():
    """True if MKL PARDISO can be loaded (``pip install mkl``)."""
    return _library() is not None


def mkl_threads(size):
    """MKL threads for PARDISO on ``size`` unknowns: 1 below :data:`~ngdgfric.threads.PARALLEL_FROM` (20000), as for
    NGSolve's TaskManager; 0 above, MKL's own setting (all cores unless MKL_NUM_THREADS says otherwise).

    Measured on a shared 2-core machine (load 5-6, whole ``ndf.solve`` of Example 6.2, h = 1/16, one thread and two
    alternating in one process, best of 4, wall seconds of the condensation, 2026-12): SIPG p = 2 (6,144 DOFs)
    0.020 against 0.042, p = 4 (15,360) 0.150 against 0.189, cg p = 4 (8,450) 0.048 against 0.127; at 33,000-37,000
    DOFs mixed (SIPG p = 7 1.80 against 1.69, cg p = 8 0.37 against 0.51).  A parallel region waits for a
    descheduled worker (threads.py); OpenMP's blocktime 0 did not change that.
    """
    return 1 if size < PARALLEL_FROM else 0


def _pointer(array):
    return array.ctypes.data_as(ctypes.c_void_p)


class SchurFactorization:
    """PARDISO factorisation of a square CSR matrix K with the Schur complement of its first rows.

    indptr, indices, data: K in CSR (0-based, column indices sorted in each row); for
    ``symmetric`` only the upper triangle, diagonal included (also where it is zero).
    n_schur: the first ``n_schur`` rows and columns form the Schur block S; the others, I, are
    eliminated.  ``symmetric``: K is real symmetric and K_II positive definite (Cholesky, PARDISO's
    type 2; PardisoError with code -4 if K_II is not), else K is real nonsymmetric (type 11; pivots
    of K_II below 1e-13 times the largest are perturbed, iparm[9] = 13, so K_II must be
    nonsingular, as a coercive B_h is).

    After construction ``schur`` holds K_SS - K_SI K_II^-1 K_IS (dense, n_schur x n_schur),
    :meth:`solve_eliminated` solves with K_II, and ``seconds`` holds the wall-clock seconds of the
    ``analysis`` (PARDISO's phase 11: ordering, symbolic factorisation) and of the numerical
    ``factorisation`` with the Schur complement (phase 22).
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
        self._mtype = np.array([2 if symmetric else 11], dtype=np.int32)
        self._threads = mkl_threads(self.n)
        self._pt = np.zeros(64, dtype=np.int64)
        self._iparm = np.zeros(64, dtype=np.int32)
        lib.pardisoinit(_pointer(self._pt), _pointer(self._mtype), _pointer(self._iparm))
        self._iparm[7] = 0    # no iterative refinement (partial solves cannot refine)
        self._iparm[9] = 13   # pivot perturbation 1e-13 (type 11)
        self._iparm[12] = 0   # no weighted matching (keeps the Schur rows together)
        self._iparm[34] = 1   # 0-based indices
        self._iparm[35] = 1   # Schur complement, not factorised (module docstring)
        self._perm = np.zeros(self.n, dtype=np.int32)
        self._perm[:self.n_schur] = 1
        self.schur = np.zeros((self.n_schur, self.n_schur))
        self._released = False
        self.seconds = {}
        for phase, name in ((11, "analysis"), (22, "factorisation")):
            start = time.perf_counter()
            self._call(phase, x=self.schur)
            self.seconds[name] = time.perf_counter() - start

    def _call(self, phase, b=None, x=None, nrhs=1):
        error = np.zeros(1, dtype=np.int32)
        one = np.ones(1, dtype=np.int32)
        null = ctypes.c_void_p(0)
        previous = self._lib.MKL_Set_Num_Threads_Local(self._threads)  # this thread only, restored below
        try:
            self._lib.pardiso(_pointer(self._pt), _pointer(one), _pointer(one), _pointer(self._mtype),
                              _pointer(np.array([phase], dtype=np.int32)), _pointer(np.array([self.n], dtype=np.int32)),
                              _pointer(self._data), _pointer(self._indptr), _pointer(self._indices),
                              _pointer(self._perm), _pointer(np.array([nrhs], dtype=np.int32)), _pointer(self._iparm),
                              _pointer(np.zeros(1, dtype=np.int32)), null if b is None else _pointer(b),
                              null if x is None else _pointer(x), _pointer(error))
        finally:
            self._lib.MKL_Set_Num_Threads_Local(previous)
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
        m = self.n_schur
        b = np.zeros(self.n)
        b[m:] = b_eliminated
        x = np.zeros(self.n)
        self._call(331, b=b, x=x)
        r_schur = x[:m].copy()
        x[:m] = x_schur
        out = np.zeros(self.n)
        self._call(333, b=x, x=out)
        return out[m:], r_schur

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
