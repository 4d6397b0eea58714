"""What an engineer reads of two bodies in contact (issue 49): the force balance of each body and each pair's action
and reaction (ngdgfric.forces, ngdgfric.contact.pair_zones), the pair's state, zones and pressure on both sides
(ngdgfric.contact.pair_state), the KKT residuals at the pair's points, the PNGs and the VTK file of both bodies."""

import dataclasses

import matplotlib.image
import ngsolve as ngs
import numpy as np
import pytest
from test_output import read_vtu
from test_pairs import C_N, P, patch_problem, stacked

import ngdgfric as ndf
from ngdgfric.contact.state import rounding_residual, transitions
from ngdgfric.output import write_contact_png, write_deformed_png, write_vtk

C_TAU = 0.001  # the sliding block: friction c_tau per unit length, 10 times too little to hold it
LIFT = 0.002  # the tilted press: the upper body starts this far above the lower one
WEIGHT = 0.001  # and its bodies' weight per unit area
H = {"lower": 1 / 8, "upper": 1 / 10}


@pytest.fixture(scope="module")
def patch():
    """The patch test with the load (uniform pressure P on top, rollers), h = 1/3 below, 1/5 above, P2."""
    problem = patch_problem(load=True)
    return ndf.solve(problem, ndf.netgen_mesh(problem, {"lower": 1 / 3, "upper": 1 / 5}), order=2)


@pytest.fixture(scope="module")
def sliding():
    """The block of tests/test_pairs.py pulled sideways past the friction bound: every point slips."""
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                                 geometry=stacked(), dirichlet=("bottom", "top"),
                                 traction=("right1", "left1", "right2", "left2"), contact=(),
                                 pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=C_TAU)],
                                 u_D={"top": (0.05, -0.01)})
    return ndf.solve(problem, ndf.netgen_mesh(problem, {"lower": 1 / 3, "upper": 1 / 5}), order=2)


def tilted(swap=False):
    """The upper body LIFT above the lower one, its top pressed down by 0.008 x and shifted by 0.001 x, friction
    30 ([u]_n - g)_+ (m_t = 1), the weight WEIGHT per unit area: the right part of the interface closes, the left
    stays open; stick and slip."""
    lower = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "right1", "c1", "left1"])
    upper = ndf.Loop([(0, 1 + LIFT), (1, 1 + LIFT), (1, 1.5 + LIFT), (0, 1.5 + LIFT)], ["c2", "right2", "top", "left2"])
    pair = ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=30.0, m_t=1.0)
    return ndf.ContactProblem(E=1.0, nu=0.3, f=(0, -WEIGHT), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                              geometry=ndf.Domain({"lower": lower, "upper": upper}), dirichlet=("bottom", "top"),
                              traction=("right1", "left1", "right2", "left2"), contact=(),
                              pairs=[pair.swapped() if swap else pair],
                              u_D={"top": ngs.CF((0.001 * ngs.x, -0.008 * ngs.x))})


@pytest.fixture(scope="module")
def tilted_solutions():
    """The tilted press solved with the pair (c2, c1) and with the pair swapped (c1, c2), on one mesh, P2."""
    mesh = ndf.netgen_mesh(tilted(), H)
    return [ndf.solve(tilted(swap), mesh, order=2) for swap in (False, True)]


def test_each_body_of_the_patch_test_is_in_balance_and_the_pair_carries_p(patch):
    """Each body's supports, loads and pair force add up to zero (measured 3.7e-14 and 1.2e-13 of the largest
    force); the pair's normal resultant is P on both sides (measured 1.2e-13 relative), as (0, P) on the upper body
    and (0, -P) on the lower one; the rollers below take P."""
    balance = ndf.force_balance(patch)
    lower, upper = balance.bodies
    assert (lower.name, upper.name) == ("body 0 (lower)", "body 1 (upper)")
    assert max(lower.relative_residual, upper.relative_residual) < 1e-12
    assert sorted(lower.pairs) == ["c1"] and sorted(upper.pairs) == ["c2"]
    assert sorted(lower.reactions) == ["bottom", "left1"] and sorted(upper.reactions) == ["left2"]
    for side, sign in (("c2", 1.0), ("c1", -1.0)):
        c = balance.pairs[side]
        assert c.normal == pytest.approx(P, rel=1e-12)
        assert np.allclose(c.force, (0.0, sign * P), rtol=0, atol=1e-12 * P)
        assert np.allclose(c.pressure, P, rtol=1e-10)  # uniform along the pair
    assert np.allclose(balance.reactions["bottom"].force, (0.0, P), rtol=0, atol=1e-12 * P)
    (side, other, force, reaction, total), = balance.pair_resultants()
    assert (side, other) == ("c2", "c1")
    assert np.linalg.norm(total) < 1e-14 * P  # action and reaction, measured 3.5e-18
    assert balance.relative_residual < 1e-12


def test_the_pair_force_on_each_body_is_what_its_supports_and_loads_leave(patch):
    """The independent measure of the pair's force on each body: minus the sum of that body's reactions and loads
    (not the pair's own traces); both agree with the pair's force on that side to 1e-12 of P."""
    balance = ndf.force_balance(patch)
    for body in balance.bodies:
        (side, c), = body.pairs.items()
        others = sum(vector for kind, _, vector in body.vectors() if kind != "pair")
        assert np.allclose(c.force, -others, rtol=0, atol=1e-12 * P)


def test_the_sliding_block_slips_along_the_whole_pair_with_c_tau_on_both_sides(sliding):
    """The friction resultant is c_tau times the length on both sides: -c_tau along x on the upper body (pulled
    along +x), +c_tau on the lower one (measured to 1e-15 relative); the whole pair in contact and slipping on
    both sides, no stick."""
    balance = ndf.force_balance(sliding)
    for side, sign, y in (("c2", -1.0, 1.0), ("c1", 1.0, 1.0)):
        c = balance.pairs[side]
        assert c.tangential == pytest.approx(-C_TAU, rel=1e-12)
        assert c.force[0] == pytest.approx(sign * C_TAU, rel=1e-12)
        assert c.length == pytest.approx(1.0, rel=1e-12)
        assert c.contact.length == pytest.approx(1.0, rel=1e-12) and c.slip.length == pytest.approx(1.0, rel=1e-12)
        assert c.stick.length == 0 and len(c.contact.pieces) == len(c.slip.pieces) == 1
        assert np.allclose(c.slip.bounds, (0.0, y, 1.0, y), atol=1e-12)
        assert np.all(np.diff(c.arc) > 0) and np.all(c.pressure > 0)
    assert balance.pairs["c2"].slip.start == pytest.approx((0.0, 1.0))  # t = (1, 0) on the upper body's bottom
    assert balance.pairs["c1"].slip.start == pytest.approx((1.0, 1.0))  # t = (-1, 0) on the lower body's top
    assert max(body.relative_residual for body in balance.bodies) < 1e-12


def zone_x(c, name):
    """The x range (start, end) of a zone of a ContactSide in one piece."""
    zone = getattr(c, name)
    assert len(zone.pieces) >= 1
    x0, _, x1, _ = zone.bounds
    return x0, x1


def test_a_partly_closed_pair_has_the_same_zones_on_both_sides(tilted_solutions):
    """The tilted press closes the interface from x = 0.48 to 1 (measured), with stick (length 0.20) and slip
    (0.32) in it; each body in balance with its weight (measured 6.5e-14 and 2.5e-13 of the largest force).  The
    zones found on the other side (through the pairing) lie at the x of those on the pair's side, each on its own side
    (y = 1 + LIFT above, 1 below), and match the zones found directly on that side when the pair is swapped, to
    within the mesh size."""
    first, swapped = (ndf.force_balance(sol) for sol in tilted_solutions)
    h = max(H.values())
    for name in ("contact", "stick", "slip"):
        for balance in (first, swapped):
            upper, lower = zone_x(balance.pairs["c2"], name), zone_x(balance.pairs["c1"], name)
            assert np.allclose(upper, lower, atol=h)
        assert np.allclose(zone_x(first.pairs["c1"], name), zone_x(swapped.pairs["c1"], name), atol=h)
        assert np.allclose(zone_x(first.pairs["c2"], name), zone_x(swapped.pairs["c2"], name), atol=h)
    contact = first.pairs["c2"].contact
    assert 0.3 < contact.start[0] < 0.6 and contact.end[0] == pytest.approx(1.0)
    assert 0.3 < contact.length < 0.7
    for side, y in (("c2", 1 + LIFT), ("c1", 1.0)):
        c = first.pairs[side]
        assert np.allclose(np.concatenate(c.contact.pieces)[:, 1], y, atol=1e-12)
        assert np.allclose(c.xy[:, 1], y, atol=1e-12)
        assert c.stick.length > 0.05 and c.slip.length > 0.05
        assert np.all(c.pressure[~c.in_contact] == 0) and np.all(c.pressure[c.in_contact] > 0)
    for body, area in zip(first.bodies, (1.0, 0.5), strict=True):  # each body carries its own weight
        assert np.allclose(body.body, (0.0, -WEIGHT * area), rtol=1e-12, atol=1e-18)
        assert body.relative_residual < 1e-12


def test_the_pair_state_and_the_kkt_residuals_at_the_pair_points(tilted_solutions, sliding):
    """|lam_tau| <= 1, lam_tau [u]_tau = |[u]_tau| and the equilibrium of (3.3) with the pairs' forces by the laws
    at u_h hold to round-off (measured: 0, at most 2.8e-14 (Newton's tolerance), at most 1.9e-15 against rounding
    floors of 2.3e-15 and 3e-15); a multiplier that is wrong at one slipping point breaks the equilibrium and the
    complementarity."""
    sol = tilted_solutions[0]
    for solution in (sol, sliding):
        residuals = ndf.kkt_residuals(solution)
        assert residuals["lam_excess"] == 0 and residuals["complementarity"] < 1e-12
        assert residuals["equilibrium"] < 1e-13 and rounding_residual(solution) < 1e-13
    state, = ndf.pair_state(sol)
    assert np.allclose(state["pressure"], C_N * np.maximum(state["penetration"], 0), rtol=1e-10, atol=1e-14)
    assert np.allclose(state["gap"], LIFT, rtol=1e-12) and np.allclose(state["other_y"], 1.0)
    broken = dataclasses.replace(sliding, info=dict(sliding.info))
    broken.info["pair_multiplier"] = broken.info["pair_multiplier"].copy()
    broken.info["pair_multiplier"][0] *= -1
    residuals = ndf.kkt_residuals(broken)
    assert residuals["equilibrium"] > 1e-6 and residuals["complementarity"] > 1e-6


def test_both_bodies_are_drawn_and_written(sliding, tmp_path):
    """The PNGs (the deformed bodies with the pair's zones; the pressure along both sides of the pair) and the VTK
    file, whose cells are the elements of both bodies, each with its own displacement."""
    write_deformed_png(tmp_path / "u.png", sliding)
    write_contact_png(tmp_path / "contact.png", sliding)
    assert matplotlib.image.imread(tmp_path / "u.png").shape[0] > 100
    height = matplotlib.image.imread(tmp_path / "contact.png").shape[0]
    assert height == pytest.approx(110 * (0.6 + 2.6 * 2), abs=2)  # two panels: c2 and c1
    sol = ndf.solve(sliding.problem, sliding.mesh, order=1)  # P1: one VTK cell per element
    write_vtk(tmp_path / "u.vtu", sol)
    arrays = read_vtu(tmp_path / "u.vtu")
    mesh = sol.mesh
    regions = [el.mat for el in mesh.Elements(ngs.VOL)]
    assert {"lower", "upper"} <= set(regions)
    cells = arrays["connectivity"].reshape(mesh.ne, 3)
    area = ngs.Integrate(ngs.CF(1), mesh, element_wise=True).NumPy()[:, None]
    mean_u = np.column_stack([ngs.Integrate(sol.u[k], mesh, element_wise=True).NumPy() for k in (0, 1)]) / area
    assert np.allclose(arrays["displacement"][cells].mean(axis=1), mean_u, rtol=1e-10, atol=1e-14)
    upper = np.array([region == "upper" for region in regions])
    assert np.all(arrays["Points"][cells[upper]][..., 1] >= 1 - 1e-12)
    assert np.all(arrays["Points"][cells[~upper]][..., 1] <= 1 + 1e-12)


def test_the_transitions_the_hp_refinement_grades_to_lie_at_the_zones_ends_on_both_sides(tilted_solutions):
    """``transitions`` (the points hp refinement grades its meshes towards) at the pair's points: on both sides of
    the tilted press (y = 1 + LIFT and y = 1), each within the mesh size of an end of the contact, stick or slip
    zones that force_balance finds, and the start of the contact zone among them (measured: 0.47 against 0.48, and
    the stick/slip boundary 0.80), for the pair and for it swapped."""
    h = max(H.values())
    for sol in tilted_solutions:
        points = transitions(sol)
        zones = ndf.force_balance(sol).pairs["c2"]
        ends = np.array([x for zone in (zones.contact, zones.stick, zones.slip) if zone.bounds
                         for x in zone.bounds[::2]])
        for y in (1 + LIFT, 1.0):
            on_side = points[np.abs(points[:, 1] - y) < 1e-9, 0]
            assert len(on_side) >= 2
            assert np.min(np.abs(on_side - zones.contact.start[0])) < h
            assert np.all(np.min(np.abs(on_side[:, None] - ends[None]), axis=1) < h)
