"""MKL PARDISO's Schur complement and partial solves against dense linear algebra."""

import ctypes

import numpy as np
import pytest

from ngdgfric.cli import main
from ngdgfric.errors import SolverError
from ngdgfric.solvers import pardiso

pytestmark = pytest.mark.skipif(not pardiso.available(), reason="MKL PARDISO not installed (pip install mkl)")


def csr_of(K, upper):
    """CSR arrays of a dense matrix (upper triangle only if ``upper``), diagonal always stored."""
    stored = np.triu(K) if upper else K.copy()
    mask = stored != 0
    mask[np.diag_indices_from(mask)] = True
    rows, cols = np.nonzero(mask)
    return np.searchsorted(rows, np.arange(len(K) + 1)), cols, stored[rows, cols]


def saddle_point(symmetric, n=80, m=10, seed=3):
    """(K, A, B): K = [[0, B], [B^T, A]] (the Schur rows first) with a random sparse A, symmetric positive definite
    or nonsymmetric with a positive definite symmetric part."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n)) * (rng.random((n, n)) < 0.1)
    A = A @ A.T + n * np.eye(n) if symmetric else A + n * np.eye(n) + 0.3 * A.T
    B = rng.standard_normal((m, n)) * (rng.random((m, n)) < 0.3)
    return np.block([[np.zeros((m, m)), B], [B.T, A]]), A, B


@pytest.mark.parametrize("symmetric", [True, False])
def test_schur_complement_and_partial_solves(symmetric):
    K, A, B = saddle_point(symmetric)
    m, n = B.shape
    factorization = pardiso.SchurFactorization(*csr_of(K, symmetric), m, symmetric)
    W = B @ np.linalg.solve(A, B.T)
    assert np.allclose(factorization.schur, -W, atol=1e-13 * np.abs(W).max())
    rng = np.random.default_rng(4)
    b, y = rng.standard_normal(n), rng.standard_normal(m)
    x, r = factorization.solve_eliminated(b, y)
    assert np.allclose(x, np.linalg.solve(A, b - B.T @ y), atol=1e-13 * np.abs(x).max())
    assert np.allclose(r, -B @ np.linalg.solve(A, b), atol=1e-13 * np.abs(r).max())
    factorization.release()


def test_the_schur_complement_may_be_singular():
    """Redundant contact points (hp meshes) make W singular: no factorisation of the Schur block is attempted."""
    K, A, B = saddle_point(True)
    B[1] = B[0]  # two equal trace rows
    K[:B.shape[0], B.shape[0]:], K[B.shape[0]:, :B.shape[0]] = B, B.T
    for symmetric in (True, False):
        factorization = pardiso.SchurFactorization(*csr_of(K, symmetric), B.shape[0], symmetric)
        W = B @ np.linalg.solve(A, B.T)
        assert np.allclose(factorization.schur, -W, atol=1e-13 * np.abs(W).max())


def test_symmetric_mode_needs_a_positive_definite_eliminated_block():
    """Cholesky (PARDISO's type 2) refuses an indefinite K_II with PARDISO's error -4; the nonsymmetric type
    factorises the same matrix."""
    K, A, B = saddle_point(True)
    m = B.shape[0]
    K[m, m] = -K[m, m]  # one negative diagonal entry of A: A indefinite
    with pytest.raises(pardiso.PardisoError) as caught:
        pardiso.SchurFactorization(*csr_of(K, True), m, True)
    assert (caught.value.phase, caught.value.code) == (22, -4)
    factorization = pardiso.SchurFactorization(*csr_of(K, False), m, False)
    W = B @ np.linalg.solve(K[m:, m:], B.T)
    assert np.allclose(factorization.schur, -W, atol=1e-12 * np.abs(W).max())


class ThreadSpy:
    """MKL's library, recording MKL's thread count for this thread at every PARDISO call."""

    def __init__(self, real):
        self.real, self.seen = real, []
        self.pardisoinit, self.MKL_Set_Num_Threads_Local = real.pardisoinit, real.MKL_Set_Num_Threads_Local

    def pardiso(self, *args):
        self.seen.append(self.real.MKL_Get_Max_Threads())
        self.real.pardiso(*args)


@pytest.mark.parametrize("size", [50, pardiso.PARALLEL_FROM + 10])
def test_small_systems_run_on_one_mkl_thread_and_the_setting_comes_back(monkeypatch, size):
    real = pardiso._library()
    spy = ThreadSpy(real)
    monkeypatch.setattr(pardiso, "_library", lambda: spy)
    everywhere = real.MKL_Get_Max_Threads()
    K = sparse_identity_saddle(size)
    factorization = pardiso.SchurFactorization(*K, 1, True)
    factorization.solve_eliminated(np.ones(size - 1), np.zeros(1))
    assert factorization.schur[0, 0] == pytest.approx(-1.0, rel=1e-14)  # -B B^T for B = e_1^T
    assert spy.seen == [1 if size < pardiso.PARALLEL_FROM else everywhere] * 4  # analysis, factorisation, 331, 333
    assert real.MKL_Get_Max_Threads() == everywhere


def sparse_identity_saddle(size):
    """Upper triangle of K = [[0, e_1^T], [e_1, I]] (size x size) in CSR: Schur complement -1."""
    cols = np.concatenate([[0, 1], np.arange(1, size)])
    indptr = np.concatenate([[0], 2 + np.arange(size)])
    return indptr, cols, np.concatenate([[0.0, 1.0], np.ones(size - 1)])


def test_bad_schur_size_is_rejected():
    with pytest.raises(ValueError, match="n_schur"):
        pardiso.SchurFactorization(*csr_of(np.eye(3), True), 3, True)


class FailingPardiso:
    """MKL's library with one phase failing: PARDISO's own call, then ``code`` written into its error argument."""

    def __init__(self, real, phase, code):
        self.real, self.phase, self.code = real, phase, code
        self.pardisoinit, self.MKL_Set_Num_Threads_Local = real.pardisoinit, real.MKL_Set_Num_Threads_Local

    def pardiso(self, *args):
        self.real.pardiso(*args)
        if ctypes.cast(args[4], ctypes.POINTER(ctypes.c_int32))[0] == self.phase:  # the phase argument
            ctypes.cast(args[-1], ctypes.POINTER(ctypes.c_int32))[0] = self.code


def test_a_failure_in_a_solve_phase_is_a_solver_error_naming_phase_and_code(monkeypatch):
    real = pardiso._library()
    monkeypatch.setattr(pardiso, "_library", lambda: FailingPardiso(real, 331, -4))
    K = np.array([[0.0, 1.0, 1.0], [1.0, 4.0, 1.0], [1.0, 1.0, 3.0]])
    factorization = pardiso.SchurFactorization(*csr_of(K, True), 1, True)
    message = r"phase 331 \(forward substitution\) with error -4 \(zero or negative pivot\)"
    with pytest.raises(SolverError, match=message) as caught:
        factorization.solve_eliminated(np.ones(2), np.zeros(1))
    assert isinstance(caught.value, pardiso.PardisoError) and (caught.value.phase, caught.value.code) == (331, -4)


@pytest.mark.parametrize("phase", [22, 333])
def test_the_command_line_reports_a_pardiso_failure_as_a_solver_failure(monkeypatch, capsys, tmp_path, phase):
    """Exit code 1 (the solver failed), not 3 (an internal error), with the phase and PARDISO's code."""
    real = pardiso._library()
    monkeypatch.setattr(pardiso, "_library", lambda: FailingPardiso(real, phase, -2))
    assert main(["solve", "6.1", "--h", "0.5", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert f"MKL PARDISO failed in phase {phase}" in err and "error -2 (not enough memory)" in err
    assert "internal error" not in err
