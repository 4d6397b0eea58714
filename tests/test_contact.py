"""Contact terms on Gamma_C: the residual of (3.3) against its weak form, the forms against the point data,
the frozen bound, the KKT residuals and the Gauss-point interpolation of the multiplier."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact import contact_state, kkt_residuals
from ngdgfric.contact.boundary import evaluate_on_contact, normal_tangent
from ngdgfric.contact.forms import compliance_form, frozen_bound, residual


def random_pair(disc, contact, seed):
    """A random u (of the size of Example 6.1's displacements, so that some points penetrate) and lam_tau."""
    rng = np.random.default_rng(seed)
    u, lam_tau = ngs.GridFunction(disc.V), ngs.GridFunction(contact.Q)
    u.vec.FV().NumPy()[:] = 0.05 * rng.standard_normal(disc.V.ndof)
    lam_tau.vec.FV().NumPy()[:] = rng.uniform(-1, 1, contact.Q.ndof)
    return u, lam_tau


@pytest.mark.parametrize("m_n, m_t", [(1.0, 0.0), (2.0, 0.0), (1.0, 1.0), (1.5, 2.0)])
def test_residual_is_the_weak_form_of_3_3(m_n, m_t):
    """residual() against A u + int (c_n d_+^{m_n} v.n + c_tau d_+^{m_t} lam_tau v.t) ds - F, d = u.n - g_a,
    assembled here as a linear form from the formula."""
    p = dataclasses.replace(ndf.example_6_1(), m_n=m_n, m_t=m_t, c_n=1e3)
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), order=2)
    contact = ndf.Contact(disc)
    u, lam_tau = random_pair(disc, contact, 0)
    n, t = normal_tangent()
    v = disc.V.TestFunction()
    d = u * n - p.g_a
    positive = ngs.IfPos(d, d, 0)
    bound = p.c_tau * (positive ** m_t if m_t else 1)
    form = ngs.LinearForm(disc.V)
    form += (p.c_n * positive ** m_n * (v * n) + bound * lam_tau * (v * t)) * contact.dS
    form.Assemble()
    expected = disc.F.CreateVector()
    expected.data = disc.A * u.vec + form.vec - disc.F
    assert np.any(evaluate_on_contact(d, contact.points()) > 0)  # the compliance is active somewhere
    difference = residual(disc, contact, u, lam_tau).FV().NumPy() - expected.FV().NumPy()
    assert np.linalg.norm(difference) <= 1e-12 * np.linalg.norm(expected.FV().NumPy())


@pytest.mark.parametrize("order", [1, 3])
def test_compliance_form_is_the_sum_over_the_gauss_points(order):
    """j_n(u, v) = v^T B^T f with f_n,q = omega_q c_n (u_n - g_a)_+(x_q), f_t = 0 (:mod:`ngdgfric.contact.traces`)."""
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), order=order)
    contact = ndf.Contact(disc)
    u, _ = random_pair(disc, contact, 1)
    trial, test = disc.V.TnT()
    form = ngs.BilinearForm(disc.V)
    form += compliance_form(p, contact.dS, trial, test)
    applied = disc.F.CreateVector()
    form.Apply(u.vec, applied)
    traces = contact.traces
    w_n = traces.apply(u.vec.FV().NumPy())[:traces.M]
    forces = np.concatenate([traces.omega * p.c_n * np.maximum(w_n - p.g_a, 0), np.zeros(traces.M)])
    expected = traces.apply_transpose(forces)
    assert np.allclose(applied.FV().NumPy(), expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_frozen_bound_is_the_bound_at_a_copy_of_u():
    p = dataclasses.replace(ndf.example_6_1(), m_t=1.0)
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4))
    contact = ndf.Contact(disc)
    u, _ = random_pair(disc, contact, 2)
    frozen = frozen_bound(p, u)
    assert frozen.m_t == 0 and dataclasses.replace(frozen, c_tau=p.c_tau, m_t=p.m_t) == p
    points = contact.points()
    n, _ = normal_tangent()
    gap = evaluate_on_contact(u * n, points) - p.g_a
    expected = p.c_tau * np.maximum(gap, 0)
    u.vec[:] = 0.0  # the frozen bound keeps its own copy of u
    assert np.allclose(evaluate_on_contact(frozen.c_tau, points), expected, rtol=1e-14, atol=0)


@pytest.fixture(scope="module")
def solution():
    p = ndf.example_6_1()
    return ndf.solve(p, ndf.uniform_mesh(p, 1 / 8))


def test_contact_state_holds_the_laws_of_the_data(solution):
    state = contact_state(solution)
    p = solution.problem
    assert np.allclose(state["gap"], state["u_n"] - p.g_a, rtol=0, atol=1e-15)
    assert np.allclose(state["pressure"], p.c_n * np.maximum(state["gap"], 0), rtol=1e-14, atol=0)
    assert np.all(state["bound"] == p.c_tau) and np.all(state["c_tau"] == p.c_tau)  # m_t = 0
    slip = np.abs(state["u_tau"]) > 1e-8 * np.abs(state["u_n"]).max()
    assert np.allclose(state["lam_tau"][slip], np.sign(state["u_tau"][slip]), rtol=0, atol=1e-13)


def test_kkt_residuals_see_a_wrong_multiplier(solution):
    """At the solution all three are at round-off; with lam_tau 1.5 times too large |lam_tau| exceeds 1 by 0.5
    (the slip points have |lam_tau| = 1) and equilibrium and complementarity fail."""
    right = kkt_residuals(solution)
    assert right["lam_excess"] <= 1e-14 and right["complementarity"] <= 1e-12 and right["equilibrium"] <= 1e-12
    lam_tau = ngs.GridFunction(solution.lam_tau.space)
    lam_tau.vec.data = 1.5 * solution.lam_tau.vec
    wrong = kkt_residuals(dataclasses.replace(solution, lam_tau=lam_tau))
    assert wrong["lam_excess"] == pytest.approx(0.5, rel=1e-12)
    assert wrong["equilibrium"] > 1e6 * right["equilibrium"] and wrong["complementarity"] > 1e-6


@pytest.mark.parametrize("order", [1, 2, 4])
def test_multiplier_gauss_values_interpolate_polynomials_exactly(order):
    """A degree-p polynomial in x on the contact edge, set through its Gauss values, snapshot and evaluated
    anywhere on Gamma_C (the bottom side of Example 6.1) is the polynomial."""
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), order=order)
    contact = ndf.Contact(disc)
    gauss = contact.gauss
    polynomial = np.polynomial.Polynomial(np.random.default_rng(3).uniform(-0.2, 0.2, order + 1))
    lam_tau = ngs.GridFunction(contact.Q)
    gauss.set_values(lam_tau, polynomial(gauss.xy[..., 0]))
    assert np.allclose(gauss.values(lam_tau), polynomial(gauss.xy[..., 0]), rtol=0, atol=1e-14)
    x = np.linspace(0, 1, 37)
    y = np.full_like(x, p.geometry.bounds[1])
    assert np.allclose(gauss.snapshot(lam_tau)(np.column_stack([x, y])), polynomial(x), rtol=0, atol=1e-13)
