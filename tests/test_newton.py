import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf


def max_rel_diff(a, b):
    a, b = a.u.vec.FV().NumPy(), b.u.vec.FV().NumPy()
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


@pytest.mark.parametrize("example", [ndf.example_6_1, ndf.example_6_2])
def test_newton_agrees_with_uzawa_at_h_1_16(example):
    p = example()
    mesh = ndf.uniform_mesh(p, 1 / 16)
    newton = ndf.solve(p, mesh, solver="newton", tol=1e-12)
    uzawa = ndf.solve(p, mesh, solver="uzawa", tol=1e-12)
    assert max_rel_diff(newton, uzawa) <= 1e-7
    assert newton.iterations <= 10


@pytest.mark.parametrize("method", ["sipg", "nipg"])
@pytest.mark.parametrize("order", [1, 2])
def test_newton_solution_satisfies_kkt(method, order):
    p = ndf.example_6_1()
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), method=method, order=order)
    kkt = ndf.kkt_residuals(sol)
    assert kkt["lam_excess"] <= 1e-12
    assert kkt["complementarity"] <= 1e-8
    assert kkt["equilibrium"] <= 1e-8


def test_newton_with_m_n_2_converges_and_satisfies_kkt():
    p = dataclasses.replace(ndf.example_6_2(), m_n=2.0, c_n=1e5)
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 8))
    state = ndf.contact_state(sol)
    assert (state["gap"] > 0).any()  # the compliance is active
    kkt = ndf.kkt_residuals(sol)
    assert kkt["complementarity"] <= 1e-8
    assert kkt["equilibrium"] <= 1e-8
    uzawa = ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), solver="uzawa", tol=1e-12)
    assert max_rel_diff(sol, uzawa) <= 1e-7


def test_warm_start_from_a_coarser_mesh_needs_few_iterations():
    p = ndf.example_6_1()
    coarse = ndf.solve(p, ndf.uniform_mesh(p, 1 / 8))
    cold = ndf.solve(p, ndf.uniform_mesh(p, 1 / 16))
    warm = ndf.solve(p, ndf.uniform_mesh(p, 1 / 16), initial=coarse)
    assert warm.iterations <= 4 < cold.iterations
    assert max_rel_diff(warm, cold) <= 1e-7


def test_non_convergence_raises_with_history():
    p = ndf.example_6_1()
    with pytest.raises(ndf.SolverError) as err:
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), maxit=1)
    assert len(err.value.history) == 1
    assert err.value.solver == "newton"


def test_spatially_varying_young_modulus_newton_agrees_with_uzawa():
    problem = dataclasses.replace(ndf.example_6_1(), E=2000 + 500 * ngs.x)
    mesh = ndf.uniform_mesh(problem, 1 / 8)
    newton_sol = ndf.solve(problem, mesh)
    uzawa_sol = ndf.solve(problem, mesh, solver="uzawa")
    a, b = newton_sol.u.vec.FV().NumPy(), uzawa_sol.u.vec.FV().NumPy()
    assert np.abs(a - b).max() <= 1e-6 * np.abs(a).max()
    assert ndf.kkt_residuals(newton_sol)["equilibrium"] < 1e-10
