"""Uzawa's inner problem on the full sparse system: the contact operator against the residual of (3.3), its
Jacobian against finite differences, the reused factorisation and the multiplier update."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact.boundary import evaluate_on_contact, normal_tangent
from ngdgfric.contact.forms import residual
from ngdgfric.contact.laws import project_unit
from ngdgfric.problem import coefficient
from ngdgfric.solvers.nonlinear import ContactOperator, ReusedFactorization, multiplier_update, relative_change


def setup(m_n=1.0, order=2):
    p = dataclasses.replace(ndf.example_6_1(), m_n=m_n, c_n=1e3)
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), order=order)
    contact = ndf.Contact(disc)
    rng = np.random.default_rng(0)
    u, lam_tau = ngs.GridFunction(disc.V), ngs.GridFunction(contact.Q)
    u.vec.FV().NumPy()[:] = 0.05 * rng.standard_normal(disc.V.ndof)
    lam_tau.vec.FV().NumPy()[:] = rng.uniform(-1, 1, contact.Q.ndof)
    c_tau = coefficient(p.c_tau)
    return disc, contact, u, lam_tau, ContactOperator(disc, contact, u, c_tau, lam_tau)


def test_operator_is_the_residual_of_3_3():
    """F(u) of Uzawa's operator (nonlinear form applied) and contact.residual (matrices) agree."""
    disc, contact, u, lam_tau, op = setup()
    expected = residual(disc, contact, u, lam_tau).FV().NumPy()
    assert np.allclose(op.residual().FV().NumPy(), expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_jacobian_is_the_derivative_of_the_operator():
    """m_n = 2 (differentiable): central differences of F in a random direction against J v."""
    disc, contact, u, _, op = setup(m_n=2.0)
    direction = u.vec.CreateVector()
    direction.FV().NumPy()[:] = np.random.default_rng(1).standard_normal(len(direction))
    J_v = direction.CreateVector()
    J_v.data = op.jacobian() * direction
    h = 1e-6
    shifted = u.vec.CreateVector()
    shifted.data = u.vec + h * direction
    plus = op.residual(shifted).FV().NumPy().copy()
    shifted.data = u.vec - h * direction
    minus = op.residual(shifted).FV().NumPy().copy()
    expected = J_v.FV().NumPy()
    assert np.allclose((plus - minus) / (2 * h), expected, rtol=0, atol=1e-6 * np.abs(expected).max())


def test_factorisation_is_reused_while_the_state_is_unchanged():
    disc, contact, u, _, op = setup()
    solver = ReusedFactorization(op.jacobian, disc.symmetric)
    b, x = u.vec.CreateVector(), u.vec.CreateVector()
    b.FV().NumPy()[:] = np.random.default_rng(2).standard_normal(len(b))
    state = op.state()
    for _ in range(2):
        solver.solve(state, b, x)
    assert solver.counts == dict(factorizations=1, solves=2)
    solver.solve(~state, b, x)
    assert solver.counts == dict(factorizations=2, solves=3)
    check = b.CreateVector()
    check.data = op.jacobian() * x - b
    assert np.linalg.norm(check.FV().NumPy()) <= 1e-10 * np.linalg.norm(b.FV().NumPy())


def test_multiplier_update_interpolates_at_the_gauss_points():
    disc, contact, u, lam_tau, _ = setup()
    _, t = normal_tangent()
    value = project_unit(lam_tau + 5 * (u * t))
    gauss = contact.gauss
    expected = np.clip(gauss.values(lam_tau).ravel() + 5 * evaluate_on_contact(u * t, gauss.points), -1, 1)
    assert 0 < np.sum(np.abs(expected) == 1) < len(expected)  # some values projected, some not
    multiplier_update(contact, lam_tau, value)()
    assert np.allclose(contact.gauss.values(lam_tau).ravel(), expected, rtol=0, atol=1e-12)


def test_relative_change_is_the_max_norm_ratio():
    _, _, u, _, _ = setup(order=1)
    du = u.vec.CreateVector()
    du.data = 1e-3 * u.vec
    assert relative_change(du, u.vec) == pytest.approx(1e-3, rel=1e-14)
    u.vec[:] = 0.0  # no scale: the change itself
    assert relative_change(du, u.vec) == np.abs(du.FV().NumPy()).max()
