"""Forces on the body (ngdgfric.forces): global equilibrium of the discrete problem (3.3) for all five methods,
contact resultants against an independent integration, per-side reactions against an exact stress and a
symmetric scene, and the contact/stick/slip zones."""

import dataclasses
import math

import ngsolve as ngs
import numpy as np
import pytest
from mirror import mirrored

import ngdgfric as ndf
from ngdgfric.contact.boundary import normal_tangent
from ngdgfric.contact.forces import constant_vectors
from ngdgfric.contact.forms import residual_terms
from ngdgfric.domain import Domain, Loop
from ngdgfric.forces import force_balance

METHODS = list(ndf.METHODS)  # the five DG methods and the conforming baseline
COMMON = dict(E=1.0, nu=0.3, c_n=1e2, m_n=1)

# two Dirichlet sides (u_D != 0 on the wall), a floor of two contact sides with a curved gap, friction sticking
# and slipping
TWO_WALLS = ndf.ContactProblem(
    **COMMON, g_a=0.004 * (ngs.x - 1) ** 2, f=(0.1, -0.2), g=(0.05, -0.1), c_tau=0.05,
    geometry=ndf.Polygon([(0, 0), (1, 0), (2, 0), (2, 1), (0, 1)], ["floor_a", "floor_b", "pin", "lid", "wall"]),
    dirichlet=["wall", "pin"], traction="lid", contact=["floor_a", "floor_b"], u_D={"wall": (0.02, -0.03)})
# a Dirichlet side with u_D != 0 and a symmetry side
HALF = ndf.ContactProblem(
    **COMMON, g_a=0.0, f=(0.0, -0.1), g=(0.02, 0.0), c_tau=0.025,
    geometry=ndf.Polygon.rectangle(0, 0, 1, 1, bottom="floor", right="free", top="lid", left="axis"),
    dirichlet="lid", traction="free", contact="floor", symmetry="axis", u_D=(0.01, -0.05))


@pytest.fixture(scope="module")
def meshes():
    return {"two walls": ndf.netgen_mesh(TWO_WALLS, 0.3), "half": ndf.netgen_mesh(HALF, 0.3)}


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("order", [1, 3])
@pytest.mark.parametrize("scene", ["two walls", "half"])
def test_global_equilibrium_to_round_off(meshes, scene, method, order):
    problem = {"two walls": TWO_WALLS, "half": HALF}[scene]
    sol = ndf.solve(problem, meshes[scene], method=method, order=order)
    balance = force_balance(sol)
    assert set(balance.reactions) == set(problem.sides("dirichlet")) | set(problem.sides("symmetry"))
    assert set(balance.contact) == set(problem.sides("contact")) and set(balance.traction) == {problem.traction}
    # sum of reactions + body force + traction + contact forces = 0 (measured <= 3e-13 of the largest force)
    assert balance.relative_residual < 1e-11
    # and it is minus the residual of (3.3) at v = e_x, e_y: the forces are the terms of the discrete problem
    terms = [term.FV().NumPy() for term in residual_terms(sol.discretization, sol.contact, sol.u, sol.lam_tau)]
    residual = constant_vectors(sol.discretization.V) @ np.sum(terms, axis=0)
    assert np.linalg.norm(balance.residual + residual) < 1e-11 * balance.scale
    # friction active: both zones present, and every force nonzero
    assert sum(c.stick.length for c in balance.contact.values()) > 0.1
    assert sum(c.slip.length for c in balance.contact.values()) > 0.1
    assert min(np.linalg.norm(r.force) for r in balance.reactions.values()) > 1e-3
    if scene == "half":  # the symmetry support pushes along its normal only
        assert abs(balance.reactions["axis"].force[1]) < 1e-12 * balance.scale


def test_reactions_are_the_exact_stress_resultants():
    """u = a rigid rotation plus a uniaxial strain, prescribed on top and bottom, nu = 0, free sides, no contact:
    u_h = u, sigma = diag(0, -0.02 E), so the top's reaction is int sigma n ds = (0, -0.02 E) and the bottom's the
    opposite, for every method (penalty and lifting terms vanish with u_h = u_D; c_tau = 0: no friction on the
    contact side either, which the reduced law (1.10) would apply without contact)."""
    u = ngs.CF((-0.01 * ngs.y, 0.01 * ngs.x - 0.02 * ngs.y))
    geometry = ndf.Polygon.rectangle(0, 0, 1, 1, bottom="bottom", right="free", top="top", left="contact")
    problem = ndf.ContactProblem(E=3.0, nu=0.0, f=(0, 0), g=(0, 0), c_n=1e2, m_n=1, g_a=1.0, c_tau=0.0,
                                 geometry=geometry, dirichlet=["bottom", "top"], traction="free", u_D=u)
    mesh = ndf.netgen_mesh(problem, 0.4)
    for method in METHODS:
        balance = force_balance(ndf.solve(problem, mesh, method=method, order=1))
        assert balance.reactions["top"].force == pytest.approx([0.0, -0.06], abs=1e-12), method
        assert balance.reactions["bottom"].force == pytest.approx([0.0, 0.06], abs=1e-12), method
        assert balance.contact["contact"].normal == 0 and balance.contact["contact"].contact.length == 0


@pytest.mark.parametrize("order", [1, 2])
def test_contact_resultants_equal_the_integrals_of_the_tractions(order):
    """Penetration everywhere (g_a < 0), m_n = 2 on a straight side: the pressure has degree 2p, lam_tau degree
    p, so the (p + 1)-point rule of (3.3) is exact and NGSolve's Integrate with a higher rule gives the same."""
    problem = ndf.ContactProblem(**{**COMMON, "m_n": 2}, g_a=-0.01, f=(0.0, -0.1), g=(0.05, 0.0), c_tau=0.05,
                                 geometry=ndf.Polygon.rectangle(0, 0, 1, 1, bottom="floor", right="free", top="lid",
                                                                left="free"),
                                 dirichlet="lid", traction="free", contact="floor")
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.3), order=order)
    side = force_balance(sol).contact["floor"]
    assert side.contact.length == pytest.approx(1.0, rel=1e-12)
    assert 0.1 < side.slip.length < 0.9  # friction sticks and slips
    n, t = normal_tangent()
    pressure = problem.c_n * (ngs.BoundaryFromVolumeCF(sol.u) * n - problem.g_a) ** 2
    friction = problem.c_tau * sol.lam_tau

    def integral(cf):
        return np.asarray(ngs.Integrate(cf, sol.mesh, ngs.BND, order=2 * order + 6,
                                        definedon=sol.mesh.Boundaries("floor")))

    assert side.normal == pytest.approx(integral(pressure), rel=1e-12)
    assert side.tangential == pytest.approx(-integral(friction), rel=1e-12)
    assert side.force == pytest.approx(-integral(pressure * n + friction * t), rel=1e-12)
    assert side.force == pytest.approx([side.tangential, side.normal], rel=1e-12)  # floor: n = -e_y, t = e_x
    state = ndf.contact_state(sol)
    assert np.all(-state["c_tau"] * state["lam_tau"] * state["u_tau"] <= 1e-15)  # friction opposes the slip


def test_a_symmetric_scene_has_opposite_wall_reactions_and_its_half_the_same_forces():
    data = dict(**{**COMMON, "c_n": 10.0}, g_a=0.0, f=(0.0, -0.1), g=(0.0, -0.2), c_tau=0.05, traction="lid",
                contact="floor")
    half = ndf.ContactProblem(**data, dirichlet="east", symmetry="axis", geometry=ndf.Polygon.rectangle(
        0, 0, 1, 1, bottom="floor", right="east", top="lid", left="axis"))
    full = ndf.ContactProblem(**data, dirichlet=["east", "west"], geometry=ndf.Polygon.rectangle(
        -1, 0, 1, 1, bottom="floor", right="east", top="lid", left="west"))
    half_mesh, full_mesh = mirrored(half, full, {"east": "west"})
    for method in ("sipg", "bassi"):
        a = force_balance(ndf.solve(half, half_mesh, method=method, order=2))
        b = force_balance(ndf.solve(full, full_mesh, method=method, order=2))
        east, west = b.reactions["east"].force, b.reactions["west"].force
        assert abs(east[0]) > 1e-3 and east[0] + west[0] == pytest.approx(0, abs=1e-12 * abs(east[0]))
        assert east[1] == pytest.approx(west[1], rel=1e-12)
        floor = b.contact["floor"]
        assert abs(floor.force[0]) < 1e-12 * floor.normal and floor.contact.length > 0
        assert floor.contact.start[0] == pytest.approx(-floor.contact.end[0], abs=1e-12)
        # the half: the same wall reaction, half the contact force; the axis carries the rest in x
        assert a.reactions["east"].force == pytest.approx(east, rel=1e-10)
        assert a.contact["floor"].normal == pytest.approx(floor.normal / 2, rel=1e-10)
        assert a.relative_residual < 1e-12 and b.relative_residual < 1e-12


@pytest.fixture(scope="module")
def example():
    """SIPG P1 on Example 6.1, h = 1/4: contact on part of Gamma_C, friction sticking and slipping."""
    problem = ndf.example_6_1()
    return ndf.solve(problem, ndf.uniform_mesh(problem, 0.25))


def test_zones_are_unions_of_gauss_cells(example):
    side = force_balance(example).contact["contact"]
    state = ndf.contact_state(example)
    x = state["x"][side.points]
    assert np.all(np.diff(x) > 0)  # the floor walked along t = e_x
    assert np.array_equal(side.cells[1:, 0], side.cells[:-1, 1]) and side.cells[0, 0] == 0
    assert side.cells[-1, 1] == pytest.approx(1.0, rel=1e-14) == side.length
    assert np.all((side.cells[:, 0] < side.arc) & (side.arc < side.cells[:, 1]))
    assert side.arc == pytest.approx(x, abs=1e-14)  # the floor starts at x = 0: arc length is x
    assert np.array_equal(side.in_contact, state["gap"][side.points] > 0)
    # m_t = 0: friction everywhere on Gamma_C, every point sticks or slips
    assert np.array_equal(side.sticking, ~side.slipping)
    assert side.stick.length + side.slip.length == pytest.approx(side.length, rel=1e-14)
    assert 0 < side.contact.length < side.length and side.stick.length > 0 and side.slip.length > 0
    lam_tau, u_tau = state["lam_tau"][side.points], state["u_tau"][side.points]
    assert np.all(np.abs(lam_tau[side.slipping]) == pytest.approx(1, abs=1e-14))
    assert np.all(np.abs(lam_tau[side.sticking]) < 0.99) and np.all(u_tau[side.slipping] != 0)
    for zone, mask in ((side.contact, side.in_contact), (side.stick, side.sticking), (side.slip, side.slipping)):
        # straight side: the pieces are the cells of the points, so their lengths add up to the zone's
        drawn = sum(np.linalg.norm(np.diff(piece, axis=0), axis=1).sum() for piece in zone.pieces)
        assert drawn == pytest.approx(zone.length, rel=1e-12)
        assert zone.length == pytest.approx(np.diff(side.cells[mask], axis=1).sum(), rel=1e-14)
        inside = x[mask]
        for a, b in zip(inside[:-1], inside[1:], strict=True):  # a run of points is one piece
            if not np.any((x > a) & (x < b) & ~mask):
                assert any(piece[0, 0] < a < b < piece[-1, 0] for piece in zone.pieces)
        x0, _, x1, _ = zone.bounds
        assert x0 < inside.min() and inside.max() < x1
        assert (zone.start[0], zone.end[0]) == (x0, x1)


def test_with_a_friction_bound_depending_on_contact_stick_and_slip_split_the_contact_zone(example):
    problem = dataclasses.replace(example.problem, m_t=1.0, c_tau=4000.0)
    sol = ndf.solve(problem, example.mesh)
    side = force_balance(sol).contact["contact"]
    assert np.array_equal(side.sticking | side.slipping, side.in_contact)
    assert 0 < side.contact.length < side.length
    assert side.stick.length + side.slip.length == pytest.approx(side.contact.length, rel=1e-14)


def test_curved_contact_side():
    """A half disk on its arc: the side's length and the zones come from the curved element mapping."""
    disk = Loop([(-1, 1), (1, 1)], ["contact", "dirichlet"], arcs={0: (0.0, 0.0)})
    problem = ndf.ContactProblem(**COMMON, g_a=0.01 * ngs.y, f=(0.01, 0), g=(0, 0), c_tau=0.05,
                                 geometry=Domain({"omega": disk}),
                                 u_D=(0.0, -0.02))
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.4), method="nipg", order=2)
    balance = force_balance(sol)
    side = balance.contact["contact"]
    assert side.length == pytest.approx(math.pi, rel=1e-4)
    assert balance.relative_residual < 1e-12
    ends = np.concatenate([piece for zone in (side.contact, side.stick, side.slip) for piece in zone.pieces])
    assert np.linalg.norm(ends - (0, 1), axis=1) == pytest.approx(1, abs=1e-3)  # on the circle
    assert 0 < side.contact.length < side.length
    x = ndf.contact_state(sol)["x"][side.points]
    assert np.all(np.diff(x) > 0)  # counter-clockwise around the body: left to right along the bottom


@pytest.mark.parametrize("method", ["nipg", "brezzi"])
def test_equilibrium_with_a_degree_per_element(meshes, method):
    mesh = meshes["two walls"]
    orders = np.random.default_rng(0).integers(1, 4, mesh.ne)
    balance = force_balance(ndf.solve(TWO_WALLS, mesh, method=method, order=orders))
    assert balance.relative_residual < 1e-11  # measured 1e-14 (nipg), 1e-14 (brezzi)


def test_newton_and_uzawa_give_the_same_zones():
    """Uzawa stops at a relative change of 1e-8 (Section 6) with u_tau up to 2e-6 max |u_h| at sticking points
    (a zero test on u_tau alone called 4 of them slipping); the zones, decided by |lam_tau|, are Newton's."""
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 0.125)
    newton, uzawa = (force_balance(ndf.solve(problem, mesh, solver=solver)).contact["contact"]
                     for solver in ("newton", "uzawa"))
    assert np.array_equal(newton.slipping, uzawa.slipping) and np.array_equal(newton.sticking, uzawa.sticking)
    assert 0 < uzawa.stick.length < uzawa.length
    assert uzawa.tangential == pytest.approx(newton.tangential, rel=1e-6)
    assert uzawa.normal == pytest.approx(newton.normal, rel=1e-5)


def test_a_hole_as_contact_side_is_walked_around_with_the_body_on_the_left():
    """A block pulled to the right around a pin in a hole: the pin side is a closed loop, walked clockwise (along
    t with the body on its left), and a zone running through the walk's start is one piece."""
    outer = Loop([(-1, -1), (1, -1), (1, 1), (-1, 1)], ["wall", "free", "free", "free"])
    pin = Loop.circle((0, 0), 0.3, "pin")
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0.0, 0), g=(0.05, 0.0), c_n=1e2, m_n=1, g_a=-0.01, c_tau=0.02,
                                 geometry=Domain({"omega": outer}, holes=(pin,)), dirichlet="wall", traction="free",
                                 contact="pin")
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.3), order=2)
    balance = force_balance(sol)
    side = balance.contact["pin"]
    assert side.length == pytest.approx(2 * math.pi * 0.3, rel=1e-3) and balance.relative_residual < 1e-11
    state = ndf.contact_state(sol)
    angle = np.unwrap(np.arctan2(state["y"], state["x"])[side.points])
    assert np.all(np.diff(angle) < 0)  # clockwise
    assert side.slip.length == pytest.approx(side.length, rel=1e-14) and len(side.slip.pieces) == 1
    assert side.slip.start == pytest.approx(side.slip.end, abs=1e-14)  # all around
    assert len(side.contact.pieces) == 1 and 0 < side.contact.length < side.length
    assert side.force[0] < 0  # the pin holds the block against the pull to the right
