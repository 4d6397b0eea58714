"""Sparse plumbing: contact blocks added to A (Uzawa's Jacobians), and the BLAS thread limit."""

import ctypes
import os

import numpy as np

import ngdgfric as ndf
from ngdgfric.linalg import BlockSum, dense_threads, limit_blas_threads


def test_block_sum_adds_the_contact_blocks_only():
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4))
    groups = disc.contact_groups()
    bs = BlockSum(disc.A, groups)
    K = disc.A.CreateMatrix()
    K.AsVector().FV().NumPy()[:] = 1.0  # a matrix with A's pattern, ones everywhere
    J = bs.update(K)
    x = disc.F.CreateVector()
    x.FV().NumPy()[:] = np.random.default_rng(0).standard_normal(len(x))
    y, z = x.CreateVector(), x.CreateVector()
    y.data = J * x
    z.data = disc.A * x
    inside = np.zeros(len(x), dtype=bool)
    inside[np.concatenate(groups)] = True
    expected = z.FV().NumPy().copy()
    block_sum = {}
    for g in groups:
        for i in g:
            block_sum[i] = sum(x.FV().NumPy()[j] for j in g)
    for i, value in block_sum.items():
        expected[i] += value
    assert np.allclose(y.FV().NumPy(), expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    assert not inside.all()


def test_blas_thread_limit_touches_only_openblas():
    limited = limit_blas_threads(1)
    assert all("openblas" in path.rsplit("/", 1)[-1].lower() for path in limited)


def openblas_threads(paths):
    """The thread count each OpenBLAS reports (openblas_get_num_threads), where it has that function."""
    counts = []
    for path in paths:
        library = ctypes.CDLL(path)
        names = ("openblas_get_num_threads", "scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads")
        getter = next((getattr(library, name) for name in names if hasattr(library, name)), None)
        if getter is not None:
            counts.append(getter())
    return counts


def test_dense_threads_gives_all_cores_to_large_dense_solves_and_restores_the_limit():
    paths = limit_blas_threads(1)
    rng = np.random.default_rng(0)
    matrix, rhs = rng.random((1200, 1200)) + 1200 * np.eye(1200), rng.random(1200)
    expected = np.linalg.solve(matrix, rhs)
    with dense_threads(1200):
        inside = openblas_threads(paths)
        solution = np.linalg.solve(matrix, rhs)
    assert np.allclose(solution, expected, rtol=1e-12, atol=0)
    assert set(openblas_threads(paths)) <= {1}
    if os.cpu_count() and os.cpu_count() > 1 and inside:
        assert min(inside) > 1
    with dense_threads(999):  # small work keeps the limit
        assert set(openblas_threads(paths)) <= {1}
