"""The trace matrix B: point values of u . n and u . t at the contact Gauss points."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact.boundary import evaluate_on_contact, normal_tangent


@pytest.mark.parametrize("order", [1, 3])
def test_trace_matrix_gives_the_point_values(order):
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), order=order)
    contact = ndf.Contact(disc)
    traces = contact.traces
    u = ngs.GridFunction(disc.V)
    u.vec.FV().NumPy()[:] = np.random.default_rng(0).standard_normal(disc.V.ndof)
    n, t = normal_tangent()
    points = contact.gauss.points
    exact = np.concatenate([evaluate_on_contact(u * n, points), evaluate_on_contact(u * t, points)])
    assert np.allclose(traces.apply(u.vec.FV().NumPy()), exact, atol=1e-12 * np.abs(exact).max())
    assert traces.M == 4 * (order + 1) and not traces.redundant
    assert traces.omega.sum() == pytest.approx(1.0)  # |Gamma_C| = 1


def test_transpose_is_the_adjoint():
    p = ndf.example_6_2()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), order=2)
    contact = ndf.Contact(disc)
    traces, rng = contact.traces, np.random.default_rng(1)
    u, f = rng.standard_normal(disc.V.ndof), rng.standard_normal(2 * traces.M)
    assert traces.apply(u) @ f == pytest.approx(u @ traces.apply_transpose(f), rel=1e-12)


def test_point_data_of_the_laws():
    p = dataclasses.replace(ndf.example_6_2(), g_a=0.01 * ngs.x, c_n=1 + ngs.x, c_tau=250.0)
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4))
    contact = ndf.Contact(disc)
    x = np.asarray(ngs.x(contact.gauss.points)).ravel()
    traces = contact.traces
    assert np.allclose(traces.g_a, 0.01 * x) and np.allclose(traces.c_n, 1 + x) and np.all(traces.c_tau == 250)


def test_redundant_points_are_detected():
    corner = ndf.Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="contact", top="dirichlet", left="traction")
    p = dataclasses.replace(ndf.example_6_2(), geometry=corner)
    assert ndf.Contact(ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4))).traces.redundant  # two contact edges
    q = ndf.example_6_2()
    mesh = ndf.uniform_mesh(q, 1 / 4)
    orders = np.full(mesh.ne, 3)
    orders[0] = 1  # an element on Gamma_C of lower order than the Gauss rule
    assert ndf.Contact(ndf.Discretization(q, mesh, order=orders)).traces.redundant
