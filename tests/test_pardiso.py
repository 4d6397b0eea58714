"""MKL PARDISO's Schur complement and partial solves against dense linear algebra."""

import numpy as np
import pytest

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
