"""The manufactured solutions are what their docstrings say (checked pointwise, not by the solver)."""

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.studies.manufactured import (
    contact_manufactured,
    friction_manufactured,
    incompressible_contact_manufactured,
)


def _on_contact(cf, xs):
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.2))
    return np.array([cf(mesh(x, 0.0)) for x in xs])


@pytest.mark.parametrize("nu", [0.3, 0.4999])
def test_divergence_free_solution_satisfies_compliance_and_friction_pointwise(nu):
    problem, u = incompressible_contact_manufactured(E=1000.0, nu=nu)
    mesh = ndf.uniform_mesh(problem, 1 / 8)
    div = u[0].Diff(ngs.x) + u[1].Diff(ngs.y)
    assert ngs.Integrate(div * div, mesh) < 1e-28
    xs = np.linspace(0.005, 0.995, 199)
    eps = 0.5 * (ngs.CF((u[0].Diff(ngs.x), u[0].Diff(ngs.y), u[1].Diff(ngs.x), u[1].Diff(ngs.y)), dims=(2, 2))
                 + ngs.CF((u[0].Diff(ngs.x), u[1].Diff(ngs.x), u[0].Diff(ngs.y), u[1].Diff(ngs.y)), dims=(2, 2)))
    sigma = 2 * problem.mu * eps  # div u = 0
    # Gamma_C = {y = 0}: n = (0, -1), t = (1, 0)
    sigma_n, sigma_tau = _on_contact(sigma[1, 1], xs), _on_contact(-sigma[0, 1], xs)
    u_n, u_tau = _on_contact(-u[1], xs), _on_contact(u[0], xs)
    g_a, c_tau = _on_contact(problem.g_a, xs), _on_contact(problem.c_tau, xs)
    scale = np.max(np.abs(sigma_n))
    np.testing.assert_allclose(sigma_n, -problem.c_n * np.maximum(u_n - g_a, 0), atol=1e-12 * scale)
    assert np.all(np.abs(sigma_tau) <= c_tau + 1e-12 * scale)
    slip = np.abs(u_tau) > 1e-12
    np.testing.assert_allclose(sigma_tau[slip], -c_tau[slip] * np.sign(u_tau[slip]), atol=1e-12 * scale)
    # all four zones are there: contact + slip on both sides, stick + no contact between
    contact = u_n - g_a > 0
    assert contact[xs < 0.25].all() and contact[xs > 0.5].all() and not contact[(xs > 0.25) & (xs < 0.5)].any()
    assert slip[xs < 0.25].all() and slip[xs > 0.5].all() and not slip[(xs > 0.25) & (xs < 0.5)].any()
    assert np.all(c_tau[(xs > 0.26) & (xs < 0.49)] > 0)


@pytest.mark.slow
@pytest.mark.parametrize("order", [1, 2])
def test_divergence_free_solution_converges_at_the_optimal_rate(order):
    problem, u = incompressible_contact_manufactured()
    errors = [ndf.energy_norm(ndf.solve(problem, ndf.uniform_mesh(problem, 2.0**-k), method="nipg", order=order), u)
              for k in (3, 4)]
    assert np.log2(errors[0] / errors[1]) == pytest.approx(order, abs=0.1)


@pytest.mark.parametrize("build", [contact_manufactured, lambda: friction_manufactured(m_t=1),
                                   lambda: friction_manufactured(m_t=2)])
def test_contact_solutions_satisfy_compliance_and_friction_pointwise(build):
    problem, u = build()
    grad = ngs.CF((u[0].Diff(ngs.x), u[0].Diff(ngs.y), u[1].Diff(ngs.x), u[1].Diff(ngs.y)), dims=(2, 2))
    eps = 0.5 * (grad + grad.trans)
    sigma = 2 * problem.mu * eps + problem.lam * (eps[0, 0] + eps[1, 1]) * ngs.Id(2)
    xs = np.linspace(0.005, 0.995, 199)
    sigma_n, sigma_tau = _on_contact(sigma[1, 1], xs), _on_contact(-sigma[0, 1], xs)  # n = (0, -1), t = (1, 0)
    u_n, u_tau = _on_contact(-u[1], xs), _on_contact(u[0], xs)
    penetration = np.maximum(u_n - _on_contact(problem.g_a, xs), 0)
    c_tau = _on_contact(problem.c_tau, xs) if isinstance(problem.c_tau, ngs.CoefficientFunction) else problem.c_tau
    bound = c_tau * penetration**problem.m_t
    scale = np.max(np.abs(sigma_n))
    np.testing.assert_allclose(sigma_n, -problem.c_n * penetration, atol=1e-12 * scale)
    assert np.all(np.abs(sigma_tau) <= bound + 1e-12 * scale)
    slip = np.abs(u_tau) > 1e-12
    np.testing.assert_allclose(sigma_tau[slip], -bound[slip] * np.sign(u_tau[slip]), atol=1e-12 * scale)
    # contact and no contact, stick and slip all occur along Gamma_C
    assert (penetration > 0).any() and (penetration == 0).any() and slip.any() and (~slip & (penetration > 0)).any()
