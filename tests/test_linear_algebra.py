"""Factorisation reuse: low-rank corrections of contact Jacobians, and the BLAS thread limit."""

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.linalg import BlockSum, direct_inverse, limit_blas_threads
from ngdgfric.lowrank import LowRankUpdate


def change_blocks(bs, changes):
    """Add to J the dense block changes {group: (m x m) matrix in the diagonal scaling}."""
    values = bs.J.AsVector().FV().NumPy()
    for g, scaled in changes.items():
        r = bs.root_diagonal[bs.dofs[g]]
        np.add.at(values, bs._group_pos[g], scaled * np.outer(r, r))


def solve_direct(mat, symmetric, b):
    x = b.CreateVector()
    x.data = direct_inverse(mat, symmetric) * b
    return x.FV().NumPy().copy()


@pytest.mark.parametrize("method", ["sipg", "nipg"])
def test_low_rank_update_solves_the_changed_jacobian(method):
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 8), method, 1)
    bs = BlockSum(disc.A, disc.contact_groups())
    symmetric = disc.symmetric
    inverse = direct_inverse(bs.J, symmetric)
    update = LowRankUpdate(inverse, bs.dofs, bs.root_diagonal, bs.scaled_blocks(), disc.F, tol=1e-2)
    rng = np.random.default_rng(1)
    m = bs.dofs.shape[1]
    # stick-penalty-like rank-one changes 1e4 times the diagonal, one nonsymmetric (m_t > 0 slip term)
    u, v, w = rng.standard_normal((3, m))
    changes = {0: 1e4 * np.outer(u, u), 3: 1e4 * np.outer(v, v) + 1e3 * np.outer(w, w), 5: 50 * np.outer(u, v)}
    if symmetric:
        changes[5] = 50 * np.outer(v, v)
    change_blocks(bs, changes)
    assert update.columns_needed(bs.scaled_blocks()) == 4
    update.prepare(bs.scaled_blocks())
    assert update.rank == 4
    b = disc.F.CreateVector()
    b.FV().NumPy()[:] = rng.standard_normal(len(b))
    x = b.CreateVector()
    update.apply(b, x)
    exact = solve_direct(bs.J, False, b)
    assert np.max(np.abs(x.FV().NumPy() - exact)) <= 1e-9 * np.max(np.abs(exact))
    # undo one change: its columns are dropped, the others are reused without new back-substitutions
    change_blocks(bs, {5: -changes[5]})
    assert update.columns_needed(bs.scaled_blocks()) == 0
    update.prepare(bs.scaled_blocks())
    assert update.rank == 3
    update.apply(b, x)
    exact = solve_direct(bs.J, False, b)
    assert np.max(np.abs(x.FV().NumPy() - exact)) <= 1e-9 * np.max(np.abs(exact))


@pytest.mark.parametrize("method", ["sipg", "nipg"])
def test_newton_with_and_without_low_rank_updates_agree(method):
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 16)
    plain = ndf.solve(p, mesh, method=method, tol=1e-12, low_rank=False)
    updated = ndf.solve(p, mesh, method=method, tol=1e-12)
    a, b = updated.u.vec.FV().NumPy(), plain.u.vec.FV().NumPy()
    assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(b))
    assert updated.info["factorizations"] < plain.info["factorizations"]


def test_blas_thread_limit_touches_only_openblas():
    limited = limit_blas_threads(1)
    assert all("openblas" in path.rsplit("/", 1)[-1].lower() for path in limited)
