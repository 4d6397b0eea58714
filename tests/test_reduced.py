"""The condensed contact problem at the Gauss points: the laws G(f), the Newton direction, the multiplier."""

import numpy as np
import pytest
from reduced_problems import law_violation, random_problem

from ngdgfric.errors import SolverError, SolverWarning
from ngdgfric.solvers.reduced import ReducedContact
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


def test_a_singular_newton_system_is_solved_by_least_squares_and_counted():
    """Two points with the same traces (W singular) both sticking, without the regularisation of redundant
    problems: J's block is singular; the direction is the least-squares one, and the count says so."""
    reduced, _ = random_problem(5, symmetric=False, redundant=True, c_tau=1e6)
    plain = reduced.variant(redundant=False)  # regularisation 0; shares the counts
    s = plain.evaluate(np.zeros(2 * plain.M))
    assert s.stick[-2:].all()
    d = plain.newton_direction(s)
    assert reduced.diagnostics["least_squares_solves"] == 1
    J = plain.jacobian(s)
    assert np.linalg.norm(J.T @ (J @ d + s.G)) <= 1e-8 * np.linalg.norm(J.T @ s.G)  # the normal equations


def test_a_newton_solve_with_singular_systems_warns_and_counts_them(monkeypatch):
    """A solve whose dense Newton systems fail by LU (simulated) still converges, with a SolverWarning and
    info["least_squares_solves"]."""
    import ngdgfric as ndf
    from ngdgfric.solvers import reduced as reduced_module
    from ngdgfric.solvers.newton import newton

    real = np.linalg.solve

    def singular(matrix, rhs):  # the dense Newton systems; batched small solves elsewhere go through
        if np.ndim(matrix) == 2:
            raise np.linalg.LinAlgError("Singular matrix")
        return real(matrix, rhs)

    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4))
    contact = ndf.Contact(disc)
    monkeypatch.setattr(reduced_module.np.linalg, "solve", singular)
    with pytest.warns(SolverWarning, match=r"\d+ Newton systems were singular"):
        _, _, info = newton(disc, contact)
    assert info["converged"] and info["least_squares_solves"] >= info["iterations"] > 0  # one per direction
    monkeypatch.undo()
    assert newton(disc, contact)[2]["least_squares_solves"] == 0


def test_a_tiny_delassus_diagonal_is_raised_visibly_and_a_negative_one_refused():
    reduced, _ = random_problem(3)
    M, W = reduced.M, reduced.W.copy()
    data = dict(w0=reduced.w0, omega=reduced.omega, g_a=reduced.g_a, c_n=reduced.c_n, c_tau=reduced.c_tau, m_n=1.0,
                m_t=0.0, symmetric=True)
    W[0, :] = W[:, 0] = 0.0  # a point whose normal trace does not move
    with pytest.warns(SolverWarning, match="1 of 24 diagonal entries below 1e-14"):
        clamped = ReducedContact(W=W, **data)
    assert clamped.diagnostics["clamped_points"] == 1 and clamped.diagonal[0] == 1e-14 * np.max(np.diag(W))
    assert clamped.variant(c_tau=2 * reduced.c_tau).diagnostics is clamped.diagnostics  # no second warning
    W[M, M] = -1e-3 * np.max(np.diag(W))
    with pytest.raises(SolverError, match="1 negative diagonal entries"):
        ReducedContact(W=W, **data)



def test_the_condensed_problem_is_built_by_keywords_or_from_a_condensation():
    """Ten arrays and numbers that are easy to swap: keywords only, or ReducedContact.condensed."""
    import ngdgfric as ndf
    from ngdgfric.solvers.condensation import Condensation

    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4))
    contact = ndf.Contact(disc)
    traces = contact.traces
    condensation = Condensation(disc.A, disc.F, traces, disc.symmetric)
    reduced = ReducedContact.condensed(condensation, traces, disc.symmetric)
    assert np.array_equal(reduced.W, condensation.W) and np.array_equal(reduced.w0, condensation.w0)
    for name in ("omega", "g_a", "c_n", "c_tau"):
        assert np.array_equal(getattr(reduced, name), getattr(traces, name))
    assert (reduced.redundant, reduced.energy_symmetric) == (traces.redundant, True)
    with pytest.raises(TypeError, match="positional"):
        ReducedContact(condensation.W, condensation.w0, traces.omega, traces.g_a, traces.c_n, traces.c_tau,
                       traces.m_n, traces.m_t, True, traces.redundant)
