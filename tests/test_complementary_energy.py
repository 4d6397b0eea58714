"""The complementary energy Theta of the condensed problem: its minimiser, gradient, conjugate and descent."""

import numpy as np
import pytest
from reduced_problems import law_violation, nearly_incompressible_data, random_problem

from ngdgfric.solvers.complementary_energy import conjugate, energy_change, gradient
from ngdgfric.solvers.reduced import ReducedContact
from ngdgfric.solvers.semismooth import solve


def test_solution_minimises_the_complementary_energy():
    reduced, _ = random_problem(3)
    f, _ = solve(reduced, solver_tol=1e-13)
    s = reduced.evaluate(f)
    rng = np.random.default_rng(0)
    for _ in range(50):
        other = reduced.project(f + 0.1 * rng.standard_normal(f.size) * np.abs(f).max())
        assert energy_change(reduced, s, other)[0] >= -1e-10 * np.abs(f).max() ** 2


@pytest.mark.parametrize("m_n", [1.0, 2.0])
def test_gradient_is_the_derivative_of_the_energy(m_n):
    """Central differences of Theta (by energy_change) at a point with all f_n > 0 against grad Theta."""
    reduced, _ = random_problem(6, m_n=m_n)
    rng = np.random.default_rng(1)
    f = np.concatenate([rng.uniform(1.0, 2.0, reduced.M), rng.uniform(-1.0, 1.0, reduced.M)])
    s = reduced.evaluate(f)
    h = 1e-5
    for i in rng.choice(2 * reduced.M, 6, replace=False):
        step = np.zeros_like(f)
        step[i] = h
        difference = (energy_change(reduced, s, f + step)[0] - energy_change(reduced, s, f - step)[0]) / (2 * h)
        assert difference == pytest.approx(gradient(reduced, s)[i], rel=1e-6, abs=1e-8)


@pytest.mark.parametrize("m_n", [1.0, 1.5, 3.0])
def test_conjugate_inverts_the_compliance_law(m_n):
    """(Phi*)'(N(w_n)) = w_n for a penetration w_n > g_a: the conjugate's derivative is the inverse law."""
    reduced, _ = random_problem(7, m_n=m_n)
    w_n = reduced.g_a + np.linspace(0.1, 2.0, reduced.M)
    pressure = reduced.omega * reduced.c_n * (w_n - reduced.g_a) ** m_n
    h = 1e-6 * pressure
    derivative = (conjugate(reduced, pressure + h) - conjugate(reduced, pressure - h)) / (2 * h)
    assert np.allclose(derivative, w_n, rtol=1e-7)


def test_plain_semismooth_newton_cycles_where_the_globalised_one_converges():
    reduced = ReducedContact(**nearly_incompressible_data())
    f = np.zeros(2 * reduced.M)
    residuals = []
    for _ in range(40):  # full steps, no globalisation: the active sets cycle
        s = reduced.evaluate(f)
        residuals.append(reduced.residual(s))
        f = f + reduced.newton_direction(s)
    assert min(residuals[20:]) > 1e-6
    f, info = solve(reduced, solver_tol=1e-12)
    assert info["iterations"] <= 30 and law_violation(reduced, f)[0] <= 1e-12
    assert any(step.startswith("projected newton") for step in info["steps"])
