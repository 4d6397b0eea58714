"""The friction bound c_tau (u_n - g_a)_+^{m_t}, m_t > 0: problem data, coupled Newton, fixed point, estimator."""

import dataclasses
import importlib

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact.boundary import normal_tangent
from ngdgfric.contact.forms import friction_matrix, frozen_bound
from ngdgfric.studies import max_rel_diff
from ngdgfric.studies.manufactured import friction_manufactured


@pytest.mark.parametrize("value", [-1.0, -1e-12, float("nan"), float("inf"), "1", None, ngs.x])
def test_bad_m_t_raises_value_error_naming_the_field(value):
    with pytest.raises(ValueError, match="m_t"):
        dataclasses.replace(ndf.example_6_1(), m_t=value)


def test_default_is_the_reduced_law():
    assert ndf.example_6_1().m_t == 0


@pytest.mark.parametrize("inner", ["newton", "uzawa"])
def test_m_t_0_through_the_fixed_point_is_the_reduced_law_solution(inner):
    p = dataclasses.replace(ndf.example_6_1(), m_t=0.0)
    mesh = ndf.uniform_mesh(p, 1 / 8)
    reduced = ndf.solve(p, mesh, solver=inner, solver_tol=1e-10)
    fixed = ndf.solve(p, mesh, solver="fixed_point", inner=inner, solver_tol=1e-10)
    assert fixed.iterations == 1  # the bound c_tau does not depend on u
    assert max_rel_diff(fixed, reduced) <= 1e-12


def test_frozen_bound_of_the_reduced_law_is_the_same_matrix():
    p = ndf.example_6_1()
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 4))
    disc = sol.discretization
    contact = sol.contact
    frozen, plain = friction_matrix(contact, frozen_bound(disc.problem, sol.u).c_tau), friction_matrix(contact, p.c_tau)
    diff = frozen.AsVector().FV().NumPy() - plain.AsVector().FV().NumPy()
    assert np.max(np.abs(diff)) == 0.0


@pytest.fixture(scope="module")
def example_m_t_1():
    p = dataclasses.replace(ndf.example_6_1(), m_t=1.0)
    mesh = ndf.uniform_mesh(p, 1 / 8)
    return (ndf.solve(p, mesh, solver="newton", solver_tol=1e-10),
            ndf.solve(p, mesh, solver="fixed_point", solver_tol=1e-10))


def test_fixed_point_and_coupled_newton_agree(example_m_t_1):
    newton, fixed = example_m_t_1
    assert max_rel_diff(fixed, newton) <= 1e-7
    assert newton.iterations < fixed.iterations  # Newton: 2-3 steps; the fixed point contracts by ~0.25
    assert fixed.info["inner_iterations"][-1] <= 2  # warm-started reduced-law solves


def test_fixed_point_with_uzawa_inside_agrees_and_satisfies_kkt(example_m_t_1):
    newton = example_m_t_1[0]
    fixed = ndf.solve(newton.problem, newton.mesh, solver="fixed_point", inner="uzawa", solver_tol=1e-10)
    assert max_rel_diff(fixed, newton) <= 1e-7
    kkt = ndf.kkt_residuals(fixed)  # l = sign(u_tau) where the bound is 0
    assert kkt["complementarity"] <= 1e-8 and kkt["equilibrium"] <= 1e-8


def test_state_dependent_bound_vanishes_without_contact(example_m_t_1):
    state = ndf.contact_state(example_m_t_1[0])
    gap = state["gap"]
    assert (gap > 0).any() and (gap <= 0).any()
    np.testing.assert_allclose(state["bound"], 450 * np.maximum(gap, 0), rtol=1e-12)


def test_uzawa_refuses_m_t_above_0():
    p = dataclasses.replace(ndf.example_6_1(), m_t=1.0)
    with pytest.raises(ValueError, match="fixed_point"):
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), solver="uzawa")


def test_fixed_point_fails_for_a_large_friction_coefficient_where_newton_converges():
    # the outer map stops contracting near c_tau = 4 * 450 for m_t = 1 (results/mt.md)
    p = dataclasses.replace(ndf.example_6_1(), m_t=1.0, c_tau=1800.0)
    mesh = ndf.uniform_mesh(p, 1 / 8)
    newton = ndf.solve(p, mesh)
    assert ndf.kkt_residuals(newton)["equilibrium"] <= 1e-10
    with pytest.raises(ndf.SolverError) as err:
        ndf.solve(p, mesh, solver="fixed_point")
    assert err.value.solver == "fixed_point"


def friction_residual(sol):
    """A u + j_n(u) + int c_tau (u_n - g_a)_+^{m_t} l v.t - F, assembled here from scratch."""
    disc = sol.discretization
    contact = sol.contact
    n, t = normal_tangent()
    v = disc.V.TestFunction()
    d = sol.u * n - sol.problem.g_a
    bound = sol.problem.c_tau * ngs.IfPos(d, d, 0)
    form = ngs.LinearForm(disc.V)
    form += (sol.problem.c_n * ngs.IfPos(d, d, 0) * (v * n) + bound * sol.lam_tau * (v * t)) * contact.dS
    form.Assemble()
    r = disc.F.CreateVector()
    r.data = disc.A * sol.u.vec + form.vec - disc.F
    return np.linalg.norm(r.FV().NumPy()) / np.linalg.norm(disc.F.FV().NumPy())


@pytest.mark.parametrize("order", [1, 2])
def test_kkt_with_the_state_dependent_bound_hold_at_the_discrete_solution(order):
    p, _ = friction_manufactured()
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), order=order)
    kkt = ndf.kkt_residuals(sol)
    assert kkt["lam_excess"] <= 1e-12
    assert kkt["complementarity"] <= 1e-8
    assert kkt["equilibrium"] <= 1e-10
    assert friction_residual(sol) <= 1e-10
    state = ndf.contact_state(sol)
    contact, slip = state["gap"] > 0, np.abs(state["u_tau"]) > 1e-8
    # all three zones of the manufactured solution: stick, slip, and no contact with u_tau free
    assert (contact & ~slip).any() and (contact & slip).any() and (~contact & slip).any()
    np.testing.assert_array_equal(state["bound"][~contact], 0.0)


@pytest.mark.slow
@pytest.mark.parametrize("order, levels", [(1, (2, 3, 4, 5)), (2, (1, 2, 3, 4))])
def test_manufactured_m_t_1_converges_at_the_optimal_rate(order, levels):
    p, u_exact = friction_manufactured(m_t=1)
    hs, errors, estimates = [], [], []
    for k in levels:
        sol = ndf.solve(p, ndf.uniform_mesh(p, 2.0**-k), order=order)
        hs.append(2.0**-k)
        errors.append(ndf.energy_norm(sol, u_exact))
        estimates.append(ndf.estimate(sol).eta_h)
    rate = np.polyfit(np.log(hs[1:]), np.log(errors[1:]), 1)[0]
    assert rate == pytest.approx(order, abs=0.2)
    effectivity = np.array(estimates) / np.array(errors)  # eta_4 carries the bound at u_h
    assert effectivity.max() / effectivity.min() <= 2


def test_adaptive_loop_with_m_t_2():
    p = dataclasses.replace(ndf.example_6_1(), m_t=2.0)
    records = ndf.adapt(p, order=1, hp=False, max_levels=4, progress=None).levels
    assert [r["level"] for r in records] == [0, 1, 2, 3]
    assert records[-1]["eta_h"] < records[0]["eta_h"]


@pytest.mark.slow  # runs scripts/mt.py
def test_mt_script(tmp_path):
    result = importlib.import_module("mt").main(["--quick", "--out", str(tmp_path)])
    assert {r["m_t"] for r in result["zones"]} == {0.0, 1.0, 2.0}
    text = (tmp_path / "mt.md").read_text()
    assert "Regenerate" in text and "fixed point" in text
    assert (tmp_path / "mt.png").stat().st_size > 0
