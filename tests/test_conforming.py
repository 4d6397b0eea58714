"""The conforming baseline ``cg``: continuous spaces (also hp), optimal rates, a contact solver without redundant
points, exact transfer to the DG carrier of the adaptive loop; the singular points (corners, ends of the contact
zones) and the geometric layers towards them."""

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact import Contact
from ngdgfric.contact.boundary import contact_edges
from ngdgfric.dg.discretization import Discretization, conforming_space, edge_orders, element_edges
from ngdgfric.dg.dofs import dg_ndof
from ngdgfric.hp import HPState, containing, hp_refine
from ngdgfric.meshes import element_diameters
from ngdgfric.studies.manufactured import contact_manufactured
from ngdgfric.transfer import discontinuous


def random_orders(mesh, seed=0):
    return np.random.default_rng(seed).integers(1, 5, mesh.ne)


def test_a_variable_order_conforming_space_is_continuous_with_the_edges_of_the_larger_degree():
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    orders = random_orders(mesh)
    raised = contact_edges(problem, mesh)
    space = conforming_space(mesh, orders, raised)
    u = ngs.GridFunction(space)
    u.vec.FV().NumPy()[:] = np.random.default_rng(1).standard_normal(space.ndof)
    jump = ngs.Integrate((u - u.Other()) ** 2 * ngs.dx(element_boundary=True), mesh)
    size = ngs.Integrate(u * u * ngs.dx, mesh)
    assert jump <= 1e-24 * size
    edges = edge_orders(mesh, orders, raised)
    neighbours = element_edges(mesh)
    expected = np.zeros(mesh.nedge, dtype=int)
    for element, p in enumerate(orders):
        for edge in neighbours[element]:
            expected[edge] = max(expected[edge], p)
    expected[raised] = orders.max()
    assert np.array_equal(edges, expected) and len(raised) == 4
    # per component: vertices + edge interiors + element interiors
    count = mesh.nv + np.sum(edges - 1) + np.sum((orders - 1) * (orders - 2) // 2)
    assert space.ndof == 2 * count < dg_ndof(orders)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_cg_converges_at_the_optimal_rate_on_a_manufactured_contact_solution(order):
    problem, exact = contact_manufactured()
    errors = [ndf.energy_norm(ndf.solve(problem, ndf.uniform_mesh(problem, 2.0**-k), method="cg", order=order),
                              exact) for k in (2, 3, 4)]
    assert np.log2(errors[1] / errors[2]) == pytest.approx(order, abs=0.15)


def test_cg_and_sipg_approach_the_same_solution_with_about_half_the_dofs():
    problem = ndf.example_6_2()
    reference = ndf.load_reference("results/reference_6_2.npz", problem)
    mesh = ndf.uniform_mesh(problem, 1 / 8)
    cg, sipg = (ndf.solve(problem, mesh, method=method, order=3) for method in ("cg", "sipg"))
    assert cg.ndof < 0.5 * sipg.ndof
    error_cg, error_sipg = ndf.energy_error(cg, reference), ndf.energy_error(sipg, reference)
    assert error_sipg <= error_cg <= 1.05 * error_sipg  # V_cg is a subspace of V_sipg
    kkt = ndf.kkt_residuals(cg)
    assert kkt["lam_excess"] == 0 and kkt["equilibrium"] <= 1e-12


def test_the_contact_points_of_a_conforming_hp_space_are_independent():
    # p points per edge, traces of degree p on every edge of Gamma_C (raised): the Delassus operator is regular
    # also where the elements along Gamma_C have lower degrees; with p + 1 points or the edges' own degrees the
    # points would be linearly dependent and the solver would need its proximal point method
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    orders = random_orders(mesh, seed=3)
    disc = Discretization(problem, mesh, "cg", orders)
    contact = Contact(disc)
    assert contact.order == orders.max() - 1 and not contact.traces.redundant
    assert contact.traces.M == len(contact_edges(problem, mesh)) * orders.max()
    sol = ndf.solve(problem, mesh, method="cg", order=orders)
    kkt = ndf.kkt_residuals(sol)
    assert kkt["lam_excess"] <= 1e-12 and kkt["equilibrium"] <= 1e-12 and sol.iterations <= 10


def test_discontinuous_copies_a_conforming_hp_solution_exactly():
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    sol = ndf.solve(problem, mesh, method="cg", order=random_orders(mesh, seed=5))
    u, degrees = discontinuous(sol)
    difference = ngs.Integrate((u - sol.u) ** 2 * ngs.dx(bonus_intorder=6), sol.mesh)
    assert difference <= 1e-26 * ngs.Integrate(sol.u * sol.u * ngs.dx, sol.mesh)
    assert np.all(degrees >= sol.discretization.orders) and degrees.max() == sol.discretization.orders.max()


@pytest.mark.parametrize("layers", [0, 2])
def test_geometric_layers_halve_h_at_a_marked_corner_once_more_per_layer(layers):
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    corner = np.array([[0.0, 0.0]])
    at_corner = containing(mesh, corner)
    assert at_corner.sum() >= 1
    h_before = element_diameters(mesh)[at_corner].min()
    far = element_diameters(mesh)[~at_corner].min()
    state = HPState.uniform(mesh, 2)
    marked = at_corner.copy()
    new = hp_refine(mesh, state, np.ones(mesh.ne), marked, 8, singular=problem.geometry.corners, layers=layers)
    h = element_diameters(mesh)
    assert h[containing(mesh, corner)].max() == pytest.approx(h_before / 2 ** (layers + 1), rel=1e-12)
    assert h[~containing(mesh, problem.geometry.corners)].min() >= far / 2 ** (layers + 1) - 1e-12
    assert new.orders.shape == (mesh.ne,) and np.all(new.orders == 2)
    # the other corners were not marked: untouched
    other = containing(mesh, np.array([[1.0, 1.0]]))
    assert h[other].min() == pytest.approx(far if far < h_before else h_before, rel=1e-12)


@pytest.mark.slow
def test_transitions_are_the_ends_of_the_contact_zones_of_a_manufactured_solution():
    # contact and slip for x < 1/4 and x > 1/2, no contact between (incompressible_contact_manufactured)
    from ngdgfric.contact.state import transitions
    from ngdgfric.studies.manufactured import incompressible_contact_manufactured

    problem, _ = incompressible_contact_manufactured()
    h = 1 / 32
    points = transitions(ndf.solve(problem, ndf.uniform_mesh(problem, h), method="cg", order=2))
    assert np.allclose(points[:, 1], 0.0)
    for end in (0.25, 0.5):
        assert np.min(np.abs(points[:, 0] - end)) <= h
    assert np.all(np.min(np.abs(points[:, 0, None] - np.array([0.25, 0.5])), axis=1) <= 2 * h)


def test_corners_are_where_the_boundary_turns_or_its_conditions_change():
    square = ndf.example_6_2().geometry
    assert sorted(map(tuple, square.corners)) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    # a side cut in two with one condition is no corner; with two conditions it is; a circle has none
    same = ndf.Polygon(((0, 0), (1, 0), (2, 0), (2, 1), (0, 1)), ("contact", "contact", "traction", "dirichlet",
                                                                  "traction"))
    assert (1.0, 0.0) not in map(tuple, same.corners) and len(same.corners) == 4
    split = ndf.Polygon(((0, 0), (1, 0), (2, 0), (2, 1), (0, 1)), ("contact", "traction", "traction", "dirichlet",
                                                                   "traction"))
    assert (1.0, 0.0) in map(tuple, split.corners)
    holed = ndf.example("block_with_hole").geometry
    assert len(holed.corners) == 6  # the outline's; the circular hole has none
    assert len(ndf.example("half_disk").geometry.corners) == 2  # the ends of the arc
