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


@pytest.mark.parametrize("symmetric", [True, False])
def test_schur_complement_and_partial_solves(symmetric):
    rng = np.random.default_rng(3)
    n, m = 80, 10
    A = rng.standard_normal((n, n)) * (rng.random((n, n)) < 0.1)
    A = A @ A.T + n * np.eye(n) if symmetric else A + n * np.eye(n) + 0.3 * A.T
    B = rng.standard_normal((m, n)) * (rng.random((m, n)) < 0.3)
    K = np.block([[A, B.T], [B, np.zeros((m, m))]])
    factorization = pardiso.SchurFactorization(*csr_of(K, symmetric), m, symmetric)
    W = B @ np.linalg.solve(A, B.T)
    assert np.allclose(factorization.schur, -W, atol=1e-13 * np.abs(W).max())
    b, y = rng.standard_normal(n), rng.standard_normal(m)
    x, r = factorization.solve_eliminated(b, y)
    assert np.allclose(x, np.linalg.solve(A, b - B.T @ y), atol=1e-13 * np.abs(x).max())
    assert np.allclose(r, -B @ np.linalg.solve(A, b), atol=1e-13 * np.abs(r).max())
    factorization.release()


def test_bad_schur_size_is_rejected():
    with pytest.raises(ValueError, match="n_schur"):
        pardiso.SchurFactorization(*csr_of(np.eye(3), True), 3, True)


class FailingPardiso:
    """MKL's library with one phase failing: PARDISO's own call, then ``code`` written into its error argument."""

    def __init__(self, real, phase, code):
        self.real, self.phase, self.code = real, phase, code
        self.pardisoinit = real.pardisoinit

    def pardiso(self, *args):
        self.real.pardiso(*args)
        if ctypes.cast(args[4], ctypes.POINTER(ctypes.c_int32))[0] == self.phase:  # the phase argument
            ctypes.cast(args[-1], ctypes.POINTER(ctypes.c_int32))[0] = self.code


def test_a_failure_in_a_solve_phase_is_a_solver_error_naming_phase_and_code(monkeypatch):
    real = pardiso._library()
    monkeypatch.setattr(pardiso, "_library", lambda: FailingPardiso(real, 331, -4))
    K = np.array([[4.0, 1.0, 1.0], [1.0, 3.0, 0.0], [1.0, 0.0, 0.0]])
    factorization = pardiso.SchurFactorization(*csr_of(K, True), 1, True)
    with pytest.raises(SolverError, match=r"phase 331 \(forward substitution\) with error -4 \(zero pivot\)") as caught:
        factorization.solve_eliminated(np.ones(2), np.zeros(1))
    assert isinstance(caught.value, pardiso.PardisoError) and (caught.value.phase, caught.value.code) == (331, -4)


@pytest.mark.parametrize("phase", [12, 333])
def test_the_command_line_reports_a_pardiso_failure_as_a_solver_failure(monkeypatch, capsys, tmp_path, phase):
    """Exit code 1 (the solver failed), not 3 (an internal error), with the phase and PARDISO's code."""
    real = pardiso._library()
    monkeypatch.setattr(pardiso, "_library", lambda: FailingPardiso(real, phase, -2))
    assert main(["solve", "6.1", "--h", "0.5", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert f"MKL PARDISO failed in phase {phase}" in err and "error -2 (not enough memory)" in err
    assert "internal error" not in err
