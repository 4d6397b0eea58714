import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf


@pytest.fixture(scope="module")
def solution_6_1():
    p = ndf.example_6_1()
    return ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), solver="uzawa", solver_tol=1e-12)


def test_kkt_conditions_of_example_6_1(solution_6_1):
    state = ndf.contact_state(solution_6_1)
    kkt = ndf.kkt_residuals(solution_6_1)
    assert np.max(np.abs(state["lam_tau"])) <= 1 + 1e-12
    assert kkt["complementarity"] < 1e-8
    assert kkt["equilibrium"] < 1e-10
    # the example has both stick and slip points
    slipping = np.abs(state["u_tau"]) > 1e-6 * np.max(np.abs(state["u_n"]))
    assert slipping.any() and (~slipping).any()


def test_uzawa_reports_iterations_history_and_timings(solution_6_1):
    s = solution_6_1
    assert s.iterations == len(s.history) > 10
    assert s.history[-1] <= 1e-12
    assert s.ndof == 2 * 64 * 6
    assert {"assemble", "solve", "total"} <= set(s.timings)


def test_frictionless_without_contact_is_linear_elasticity():
    p = dataclasses.replace(ndf.example_6_1(), c_tau=0.0, g_a=1e6)
    mesh = ndf.uniform_mesh(p, 1 / 4)
    sol = ndf.solve(p, mesh, solver="uzawa")
    disc = sol.discretization
    u = disc.F.CreateVector()
    u.data = disc.A.Inverse(inverse="umfpack") * disc.F
    assert np.max(np.abs(sol.u.vec.FV().NumPy() - u.FV().NumPy())) <= 1e-10 * np.max(np.abs(u.FV().NumPy()))


def test_huge_friction_bound_sticks():
    p = dataclasses.replace(ndf.example_6_1(), c_tau=1e7)
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), solver="uzawa", solver_tol=1e-10)
    state = ndf.contact_state(sol)
    assert np.max(np.abs(state["u_tau"])) <= 1e-7 * np.max(np.abs(sol.u.vec.FV().NumPy()))
    assert np.max(np.abs(state["lam_tau"])) < 1


@pytest.mark.slow
def test_spatially_varying_data_work():
    p = dataclasses.replace(ndf.example_6_2(), g_a=0.01 * ngs.x, c_tau=250 * (1 + ngs.x),
                            c_n=1 + ngs.x, f=(0, -10 * ngs.y), g=(880 * ngs.y, 0))
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), solver="uzawa", solver_tol=1e-10)
    assert ndf.kkt_residuals(sol)["equilibrium"] < 1e-10


def test_non_convergence_raises_with_history():
    p = ndf.example_6_1()
    with pytest.raises(ndf.SolverError) as err:
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), solver="uzawa", maxit=5)
    assert len(err.value.history) == 5


@pytest.mark.slow
def test_too_large_rho_is_reported_as_divergence():
    p = ndf.example_6_1()
    with pytest.raises(ndf.SolverError, match="rho"):
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), solver="uzawa", rho=1.0, maxit=2000)


def test_tiny_rho_cannot_report_convergence():
    """With rho = 1e-12 u hardly moves: the change alone reported convergence after 2 iterations, 45 % off."""
    p = ndf.example_6_1()
    with pytest.raises(ndf.SolverError, match="too small") as err:
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), solver="uzawa", rho=1e-12)
    assert len(err.value.history) <= 500


@pytest.mark.slow
def test_huge_rho_fails_within_a_few_hundred_iterations():
    """With rho = 1e6 the multiplier oscillates between -1 and 1; it used to run for minutes."""
    p = ndf.example_6_1()
    with pytest.raises(ndf.SolverError, match="too large") as err:
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), solver="uzawa", rho=1e6)
    assert len(err.value.history) <= 500


def test_kkt_test_is_part_of_the_stopping_rule(solution_6_1):
    assert solution_6_1.info["kkt_history"][-1] <= 1e-6
    assert ndf.solvers.uzawa.complementarity(solution_6_1.contact, solution_6_1.u, solution_6_1.lam_tau) \
        == pytest.approx(solution_6_1.info["kkt_history"][-1], rel=1e-12)


def test_the_stopping_test_is_a_predicate_and_failures_are_raised_apart():
    """Reporting, testing and raising are separate steps of the iteration (issue 30)."""
    from ngdgfric.solvers.uzawa import UzawaOptions, _check_divergence, _converged, _report

    options = UzawaOptions(solver_tol=1e-8, kkt_tol=1e-6)
    assert _converged(options, [1.0, 1e-9], [1e-3, 1e-7], 2)
    assert not _converged(options, [1.0, 1e-9], [1e-3, 1e-5], 2)  # the complementarity is not small yet
    assert not _converged(options, [1e-9], [1e-7], 1)  # never after the first iteration
    lines = []
    _report(lines.append, 100, [1e-3], [2e-3])
    _report(lines.append, 101, [1e-3], [2e-3])
    assert lines == ["uzawa 100: relative change 1.00e-03, complementarity 2.00e-03"]
    _check_divergence(0.1, [1.0, 0.5], 2)  # no error
    with pytest.raises(ndf.SolverError, match=r"Uzawa \(rho = 0.1\) diverged at iteration 2"):
        _check_divergence(0.1, [1.0, float("nan")], 2)
