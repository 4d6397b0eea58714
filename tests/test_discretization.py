"""The discrete problem's spaces and matrices: dimensions, symmetry of B_h, the multiplier mass matrix,
the contact element groups and the checks before assembly."""

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.dg.discretization import check_order, dg_space
from ngdgfric.dg.dofs import dg_ndof


def test_dimension_of_the_dg_space():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    assert dg_space(mesh, 3).ndof == 2 * mesh.ne * 10  # (p + 1)(p + 2) / 2 per component
    orders = np.random.default_rng(0).integers(1, 5, mesh.ne)
    assert dg_space(mesh, orders).ndof == dg_ndof(orders)


@pytest.mark.parametrize("method", ndf.DG_METHODS)
def test_matrix_of_b_h_is_symmetric_for_every_method_but_nipg(method):
    p = ndf.example_6_1()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), method=method, order=2)
    A = disc.A.ToDense().NumPy()
    asymmetry = np.abs(A - A.T).max() / np.abs(A).max()
    assert disc.symmetric == (method != "nipg")
    assert asymmetry <= 1e-13 if disc.symmetric else asymmetry > 1e-3


def test_inverse_multiplier_mass_matrix():
    p = ndf.example_6_2()
    disc = ndf.Discretization(p, ndf.uniform_mesh(p, 1 / 4), order=2)
    contact = ndf.Contact(disc)
    lam_tau, q = contact.Q.TnT()
    mass = ngs.BilinearForm(contact.Q)
    mass += lam_tau * q * contact.dS
    mass.Assemble()
    x = ngs.GridFunction(contact.Q).vec
    x.FV().NumPy()[:] = np.random.default_rng(1).standard_normal(contact.Q.ndof)
    y = x.CreateVector()
    y.data = contact.M_inv * (mass.mat * x)
    assert np.allclose(y.FV().NumPy(), x.FV().NumPy(), rtol=0, atol=1e-12 * np.abs(x.FV().NumPy()).max())


@pytest.mark.parametrize("order", [1, 2])
def test_contact_groups_are_the_elements_at_the_contact_edges(order):
    p = ndf.example_6_1()  # Gamma_C: the bottom side, of length 1
    mesh = ndf.uniform_mesh(p, 1 / 4)
    disc = ndf.Discretization(p, mesh, order=order)
    contact = ndf.Contact(disc)
    groups = contact.groups()
    assert len(groups) == 4 and all(len(g) == dg_ndof(order) for g in groups)
    assert len(set(np.concatenate(groups))) == dg_ndof(order, 4)  # four different elements
    y_bottom = p.geometry.bounds[1]
    for group in groups:
        element = next(el for el in mesh.Elements(ngs.VOL) if list(disc.V.GetDofNrs(el)) == group)
        assert sum(abs(mesh[v].point[1] - y_bottom) < 1e-12 for v in element.vertices) == 2


def test_checks_before_assembly():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 2)
    for bad in (0, 1.5, "2", np.ones(mesh.ne + 1, dtype=int), np.zeros(mesh.ne, dtype=int)):
        with pytest.raises(ValueError, match="order"):
            check_order(bad, mesh)
    with pytest.raises(ValueError, match="ContactProblem"):
        ndf.Discretization("example 6.1", mesh)
    with pytest.raises(ValueError, match="eta"):
        ndf.Discretization(p, mesh, eta=-1.0)


def test_hp_orders_and_lazily_built_contact_data():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    orders = np.random.default_rng(2).integers(1, 4, mesh.ne)
    disc = ndf.Discretization(p, mesh, order=orders)
    contact = ndf.Contact(disc)
    assert disc.order == orders.max() and np.array_equal(disc.orders, orders)
    assert disc.V.ndof == dg_ndof(orders)
    assert contact.Q.ndof == 4 * (disc.order + 1)  # the multiplier has the largest degree on every contact edge
    assert contact.traces is contact.traces and contact.gauss is contact.gauss
