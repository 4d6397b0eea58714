"""The globalised semismooth Newton method on condensed contact problems: its solutions satisfy the laws."""

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from reduced_problems import law_violation, random_problem, redundant_edges_problem

import ngdgfric as ndf
from ngdgfric.solvers.semismooth import solve


@pytest.mark.parametrize("symmetric", [True, False])
@pytest.mark.parametrize("m_n, m_t", [(1.0, 0.0), (2.0, 0.0), (1.0, 1.0), (1.5, 2.0)])
def test_solution_satisfies_the_laws(symmetric, m_n, m_t):
    reduced, _ = random_problem(1, symmetric=symmetric, m_n=m_n, m_t=m_t)
    f, info = solve(reduced, solver_tol=1e-12)
    s = reduced.evaluate(f)
    M = reduced.M
    w_n, w_t = s.w[:M], s.w[M:]
    pressure = reduced.omega * reduced.c_n * np.maximum(w_n - reduced.g_a, 0) ** m_n
    bound = reduced.omega * reduced.c_tau * (np.maximum(w_n - reduced.g_a, 0) ** m_t if m_t else 1)
    scale = np.abs(f).max()
    assert np.allclose(f[:M], pressure, atol=1e-10 * scale)
    assert np.all(np.abs(f[M:]) <= bound * (1 + 1e-12) + 1e-12 * scale)
    slipping = np.abs(w_t) > 1e-9 * np.abs(s.w).max()
    assert np.allclose(f[M:][slipping], (bound * np.sign(w_t))[slipping], atol=1e-10 * scale)
    assert info["history"][-1] <= 1e-10


def test_energy_and_merit_globalisations_agree_on_a_symmetric_problem():
    reduced, _ = random_problem(2)
    f_energy, _ = solve(reduced, solver_tol=1e-13)
    reduced.energy_merit = False
    f_merit, _ = solve(reduced, solver_tol=1e-13)
    assert np.allclose(f_energy, f_merit, atol=1e-9 * np.abs(f_energy).max())


def test_redundant_points_converge_and_the_traces_are_unique():
    reduced, _ = random_problem(4, redundant=True)
    f, info = solve(reduced, solver_tol=1e-12)
    assert info["steps"][0].startswith("proximal")  # the proximal point method (symmetric, m_t = 0)
    assert law_violation(reduced, f)[0] <= 1e-10
    other, _ = solve(reduced, f0=f + 1.0, solver_tol=1e-12)
    assert np.allclose(reduced.traces(f), reduced.traces(other), atol=1e-9 * np.abs(reduced.traces(f)).max())


def test_nonsymmetric_redundant_points_are_solved_when_the_proximal_method_fails():
    """A random NIPG-like problem with 3 of 8 points per edge redundant (M = 240): the proximal point method alone
    failed on it (as on every such problem tried); the plain iteration after it solves it."""
    reduced = redundant_edges_problem(8)
    f, info = solve(reduced, solver_tol=1e-13)
    assert info["converged"]  # the stopping test, with its round-off allowance (the residual itself was 1.1e-9)
    assert law_violation(reduced, f)[1] <= 1e-14
    assert not any(step.startswith("continuation") for step in info["steps"])


@pytest.mark.parametrize("redundant", [False, True])
def test_progress_reports_every_iteration_with_its_kkt_residual(redundant):
    reduced, _ = random_problem(4, redundant=redundant)
    messages = []
    f, info = solve(reduced, solver_tol=1e-12, progress=messages.append)
    assert len(messages) == info["iterations"] == len(info["history"]) > 1
    assert messages == [f"newton {k + 1}: KKT residual {r:.2e}" for k, r in enumerate(info["history"])]


def test_no_solution_within_maxit_raises_with_the_history():
    reduced, _ = random_problem(5, symmetric=False)
    with pytest.raises(ndf.SolverError, match="solver_tol = 1e-12") as err:
        solve(reduced, solver_tol=1e-12, maxit=1)
    assert len(err.value.history) >= 1 and err.value.solver == "newton"


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), symmetric=st.booleans(), c_n=st.sampled_from([0.0, 1e-6, 1.0, 1e3, 1e6, 1e10]),
       c_tau=st.sampled_from([0.0, 1e-3, 1.0, 1e2, 1e6]), m_n=st.sampled_from([1.0, 1.5, 2.0, 3.0]),
       m_t=st.sampled_from([0.0, 0.0, 1.0, 2.0]), gap=st.floats(-1.0, 1.0))
def test_random_problems_are_solved(seed, symmetric, c_n, c_tau, m_n, m_t, gap):
    # m_t > 0 makes the problem a quasi-variational inequality, solvable for a friction bound that grows
    # slowly with the penetration: without compliance, or with c_tau >> c_n, these random data need not
    # have a solution (seen: c_n = 0, c_tau = 1e6, m_t = 1, none found from 2000 random starts);
    # 0 < m_t < 1 (a non-Lipschitz bound) is left to the DG cases of scripts/solver_robustness.py
    assume(m_t == 0 or (c_n > 0 and c_tau <= 1e2))
    reduced, _ = random_problem(seed, symmetric=symmetric, c_n=c_n, c_tau=c_tau, m_n=m_n, m_t=m_t, gap=gap)
    f, _ = solve(reduced, solver_tol=1e-12)
    residual, excess = law_violation(reduced, f)
    assert reduced.converged(reduced.evaluate(f), 1e-12)  # |G_q| <= max(1e-12 S, its round-off)
    if c_n <= 1e3 and c_tau <= 1e2:  # where round-off of the laws (omega c_n w, c_tau m_t w^(m_t - 1)) is small
        assert residual <= 1e-11
    assert excess <= 1e-12


@pytest.mark.slow
@pytest.mark.parametrize("E, nu, h, method", [(1e3, 0.49, 1 / 8, "brezzi"), (1e3, 0.3, 1 / 16, "sipg"),
                                               (1e6, 0.3, 1 / 16, "brezzi")])
def test_degenerate_stick_slip_transitions_converge(E, nu, h, method):
    # the divergence-free manufactured solution has c_tau = |sigma_tau| in its slip zones, down to 0 at their
    # ends: points with |z| = beta where stick and slip both hold.  Newton steps alternated between two
    # states (Theta equal to round-off) or between two sets until these points were handled (P4)
    from ngdgfric.studies.manufactured import incompressible_contact_manufactured

    problem, _ = incompressible_contact_manufactured(E=E, nu=nu, c_n=10.0 * E / 1e3)
    sol = ndf.solve(problem, ndf.uniform_mesh(problem, h), method=method, order=4)
    kkt = ndf.kkt_residuals(sol)
    assert kkt["lam_excess"] <= 1e-12 and kkt["complementarity"] <= 1e-12 and kkt["equilibrium"] <= 1e-9
