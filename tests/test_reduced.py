"""The condensed contact problem at the Gauss points: the laws G(f), the Newton direction, the multiplier."""

import numpy as np
import pytest
from reduced_problems import law_violation, random_problem

from ngdgfric.solvers.semismooth import solve


@pytest.mark.parametrize("symmetric, redundant", [(True, False), (False, False), (True, True)])
@pytest.mark.parametrize("m_n, m_t", [(1.0, 0.0), (2.0, 0.0), (1.0, 1.0), (1.5, 2.0)])
def test_newton_direction_solves_the_full_jacobian_system(symmetric, redundant, m_n, m_t):
    """The direction with the identity rows eliminated solves J d = -G with the full generalised Jacobian."""
    reduced, _ = random_problem(11, symmetric=symmetric, redundant=redundant, m_n=m_n, m_t=m_t)
    rng = np.random.default_rng(2)
    for _ in range(5):
        s = reduced.evaluate(rng.standard_normal(2 * reduced.M) * 10)
        d = reduced.newton_direction(s)
        assert np.linalg.norm(reduced.jacobian(s) @ d + s.G) <= 1e-9 * np.linalg.norm(s.G)


@pytest.mark.parametrize("symmetric", [True, False])
def test_newton_step_with_the_final_sets_is_exact(symmetric):
    """m_n = 1, m_t = 0: G is affine on each set of penetrating and sticking points, so from a point near
    the solution (the same sets) one Newton step lands on it."""
    reduced, _ = random_problem(12, symmetric=symmetric)
    f, _ = solve(reduced, solver_tol=1e-13)
    start = f + 1e-7 * np.abs(f).max() * np.random.default_rng(3).standard_normal(f.size)
    s = reduced.evaluate(start)
    assert np.array_equal(s.stick, reduced.evaluate(f).stick)
    assert np.array_equal(s.penetrating, reduced.evaluate(f).penetrating)
    assert reduced.residual(s) > 1e-9
    assert reduced.residual(reduced.evaluate(start + reduced.newton_direction(s))) <= 1e-12


@pytest.mark.parametrize("m_t", [0.0, 1.0])
def test_multiplier_and_forces_at_a_solution(m_t):
    """|lam_tau| <= 1, lam_tau w_t = |w_t| (Lemma 3.1), and the forces of the laws at the traces of the
    solution with its multiplier (the warm start) are the solution's forces."""
    reduced, _ = random_problem(13, m_t=m_t)
    f, _ = solve(reduced, solver_tol=1e-13)
    lam_tau, w = reduced.multiplier(f), reduced.traces(f)
    assert law_violation(reduced, f)[1] <= 0
    w_t = w[reduced.M:]
    assert np.allclose(lam_tau * w_t, np.abs(w_t), atol=1e-12 * np.abs(w).max())
    assert np.allclose(reduced.forces(w, lam_tau), f, atol=1e-11 * np.abs(f).max())


def test_stopping_test_and_linearization_estimate():
    """converged() is the relative KKT residual against solver_tol away from round-off; eta_lin^2 is the
    work sum_q W_qq G_q^2."""
    reduced, _ = random_problem(14)
    s = reduced.evaluate(np.zeros(2 * reduced.M))
    residual = reduced.residual(s)
    assert reduced.converged(s, 1.01 * residual) and not reduced.converged(s, 0.99 * residual)
    assert reduced.linearization(s) ** 2 == pytest.approx(np.sum(np.diag(reduced.W) * s.G ** 2), rel=1e-12)
    assert reduced.done(s, 1e-12, energy_tol=1.01 * reduced.linearization(s))
