"""The Delassus operator W = B A^-1 B^T, w0 and the recovery of u, by both linear solvers."""

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.solvers import pardiso
from ngdgfric.solvers.condensation import Condensation, augmented_matrix

SOLVERS = ["ngsolve"] + (["pardiso"] if pardiso.available() else [])


def dense(mat):
    values, cols, rowptr = mat.CSR()
    out = np.zeros((mat.height, mat.width))
    rows = np.repeat(np.arange(mat.height), np.diff(np.asarray(rowptr, dtype=np.int64)))
    out[rows, np.asarray(cols)] = np.asarray(values)
    return out


@pytest.fixture(scope="module", params=["sipg", "nipg"])
def problem(request):
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), method=request.param, order=2)
    contact = ndf.Contact(disc)
    traces = contact.traces
    A = dense(disc.A)
    B = np.zeros((2 * traces.M, disc.V.ndof))
    B[traces.rows, traces.cols] = traces.values
    return disc, contact, A, B, disc.F.FV().NumPy().copy()


def test_augmented_matrix(problem):
    disc, contact, A, B, _ = problem
    indptr, cols, values = augmented_matrix(disc.A, contact.traces, disc.symmetric)
    n, m = A.shape[0], B.shape[0]
    K = np.zeros((n + m, n + m))
    K[np.repeat(np.arange(n + m), np.diff(indptr)), cols] = values
    full = np.block([[A, B.T], [B, np.zeros((m, m))]])
    assert np.array_equal(K, np.triu(full) if disc.symmetric else full)
    assert all(np.all(np.diff(cols[indptr[i]:indptr[i + 1]]) > 0) for i in range(n + m))  # sorted rows


@pytest.mark.parametrize("linear_solver", SOLVERS)
def test_delassus_operator_and_recovery(problem, linear_solver):
    disc, contact, A, B, F = problem
    condensation = Condensation(disc.A, disc.F, contact.traces, disc.symmetric, linear_solver)
    W = B @ np.linalg.solve(A, B.T)
    assert np.allclose(condensation.W, W, atol=1e-11 * np.abs(W).max())
    assert np.allclose(condensation.w0, B @ np.linalg.solve(A, F), atol=1e-11 * np.abs(condensation.w0).max())
    f = np.random.default_rng(0).standard_normal(B.shape[0])
    u = condensation.displacement(f)
    assert np.linalg.norm(A @ u + B.T @ f - F) <= 1e-12 * np.linalg.norm(F)
    df = 1e-3 * f
    assert np.allclose(condensation.correction(df), -np.linalg.solve(A, B.T @ df), atol=1e-14 * np.abs(u).max())


def test_unknown_linear_solver_is_rejected(problem):
    disc, contact = problem[:2]
    with pytest.raises(ValueError, match="linear_solver"):
        Condensation(disc.A, disc.F, contact.traces, disc.symmetric, "mumps")
