"""Transfers between spaces: the coefficient copy between L2 orders against NGSolve's Set; warm starts."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.dg.discretization import dg_space
from ngdgfric.transfer import WarmStart, copy_orders, initial_guess, starting_point


@pytest.mark.parametrize("mesh_kind", ["uniform", "netgen"])
def test_copy_between_orders_equals_the_l2_projection(mesh_kind):
    """Random p_T in 1..6 up into p = 8 (exact), and down into random lower orders (the element-wise L2
    projection, which ``Set`` computes by quadrature of degree 2 p_T + bonus)."""
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4) if mesh_kind == "uniform" else ndf.netgen_mesh(problem, 0.3)
    rng = np.random.default_rng(5)
    low = rng.integers(1, 7, mesh.ne)
    u = ngs.GridFunction(dg_space(mesh, low))
    u.vec.FV().NumPy()[:] = rng.standard_normal(len(u.vec))
    high = ngs.GridFunction(ngs.L2(mesh, order=8) ** 2)
    copy_orders(u, low, high, np.full(mesh.ne, 8))
    expected = ngs.GridFunction(high.space)
    expected.Set(u)
    scale = np.abs(expected.vec.FV().NumPy()).max()
    assert np.abs(high.vec.FV().NumPy() - expected.vec.FV().NumPy()).max() <= 1e-12 * scale
    lower = np.minimum(low, rng.integers(1, 7, mesh.ne))
    down = ngs.GridFunction(dg_space(mesh, lower))
    copy_orders(high, np.full(mesh.ne, 8), down, lower)
    projected = ngs.GridFunction(down.space)
    projected.Set(u, bonus_intorder=8)  # exact quadrature (Set's default rule is exact only for p(source) <= p)
    assert np.abs(down.vec.FV().NumPy() - projected.vec.FV().NumPy()).max() <= 1e-12 * scale


def test_copy_refuses_orders_that_do_not_fit_the_space():
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 2)
    u = ngs.GridFunction(dg_space(mesh, 2))
    v = ngs.GridFunction(dg_space(mesh, 3))
    with pytest.raises(ValueError, match="orders"):
        copy_orders(u, np.full(mesh.ne, 3), v, np.full(mesh.ne, 3))


@pytest.fixture(scope="module")
def coarse_solution():
    p = ndf.example_6_1()
    return ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), order=1)


def test_warm_start_on_the_same_spaces_is_an_exact_copy(coarse_solution):
    sol = coarse_solution
    u, lam_tau = initial_guess(WarmStart.from_solution(sol), sol.contact)
    assert u is not sol.u and lam_tau is not sol.lam_tau
    assert np.array_equal(u.vec.FV().NumPy(), sol.u.vec.FV().NumPy())
    assert np.array_equal(lam_tau.vec.FV().NumPy(), sol.lam_tau.vec.FV().NumPy())
    with pytest.raises(dataclasses.FrozenInstanceError):
        WarmStart.from_solution(sol).u = u


def test_warm_start_onto_a_nested_finer_mesh_and_higher_order(coarse_solution):
    """u (P1 on h = 1/4) interpolated into P2 on h = 1/8 is the same function; the multiplier takes the old
    values at the new Gauss points."""
    sol = coarse_solution
    p = sol.problem
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 8), order=2)
    contact = ndf.Contact(disc)
    start = WarmStart.from_solution(sol)
    u, lam_tau = initial_guess(start, contact)
    rng = np.random.default_rng(7)
    x0, y0, x1, y1 = p.geometry.bounds
    for x, y in rng.uniform((x0, y0), (x1, y1), (20, 2)):
        old, new = sol.u(sol.mesh(x, y)), u(disc.mesh(x, y))
        assert np.allclose(new, old, rtol=0, atol=1e-12 * np.abs(sol.u.vec.FV().NumPy()).max())
    expected = np.clip(start.multiplier(contact.gauss.xy.reshape(-1, 2)), -1, 1)
    assert np.allclose(contact.gauss.values(lam_tau).ravel(), expected, rtol=0, atol=1e-12)


def test_starting_point_copies_and_leaves_the_pair_alone(coarse_solution):
    sol = coarse_solution
    u, lam_tau = starting_point(sol.contact, (sol.u, sol.lam_tau))
    u.vec[:] = 0.0
    assert np.abs(sol.u.vec.FV().NumPy()).max() > 0
    zero = starting_point(sol.contact)
    assert not np.any(zero[0].vec.FV().NumPy()) and not np.any(zero[1].vec.FV().NumPy())


def _states(sol):
    """The state of the laws at every contact point of ``sol`` (0 no contact, 1 stick, 2 slip), read from
    ``contact_state`` (the GridFunctions evaluated at the points), not from the traces B that
    ``Contact.point_states`` applies."""
    state = ndf.contact_state(sol)
    touching = state["gap"] > 0
    return np.where(touching, np.where(np.abs(state["lam_tau"]) < 1 - 1e-8, 1, 2), 0)


def test_the_points_a_warm_start_changes_are_counted():
    """A start from the solution of another friction bound on the same mesh (its u and lam_tau copied exactly):
    ``changed_points`` counts the points whose state differs between the two solutions, each state read from
    ``contact_state``; from the solution itself nothing changes."""
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 0.25)
    other = ndf.solve(dataclasses.replace(problem, c_tau=0.3 * problem.c_tau), mesh, method="sipg", order=2)
    sol = ndf.solve(problem, mesh, method="sipg", order=2, initial=other)
    expected = int(np.sum(_states(other) != _states(sol)))
    assert expected > 0  # the friction bound moved the stick zone
    assert sol.info["changed_points"] == expected
    again = ndf.solve(problem, mesh, method="sipg", order=2, initial=sol)
    assert again.info["changed_points"] == 0
    cold = ndf.solve(problem, mesh, method="sipg", order=2)  # from zero, u = 0 short of the gap g_a = 0.05: no contact
    assert problem.g_a > 0
    assert cold.info["changed_points"] == int(np.sum(_states(cold) > 0)) > 0


def test_adapt_reports_the_changed_points_per_level():
    """Every level records its changed points (the first from zero) and the progress line says them."""
    lines = []
    run = ndf.adapt(ndf.example_6_2(), max_levels=3, progress=lines.append)
    assert all(isinstance(level["changed_points"], int) for level in run.levels)
    assert all(f"({level['changed_points']} points changed state)" in line
               for level, line in zip(run.levels, lines[-3:], strict=True))
