"""Sparse plumbing: contact blocks added to A (Uzawa's Jacobians), and the BLAS thread limit."""

import numpy as np

import ngdgfric as ndf
from ngdgfric.linalg import BlockSum, limit_blas_threads


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
