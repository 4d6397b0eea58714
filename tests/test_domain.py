"""Domains with regions, holes and circular arcs (ngdgfric/domain.py): exact geometry, Netgen meshes that
follow it, curved elements, and the checks that refuse what is not a domain."""

import math

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.domain import INTERFACE, Arc, Domain, Loop
from ngdgfric.loops import closest_approach, contains
from ngdgfric.meshes import mesh_arrays, mesh_from_arrays, refine

HALF_DISK = Loop([(-1, 1), (1, 1)], ["contact", "dirichlet"], arcs={0: (0.0, 0.0)})


def problem(geometry, **changes):
    data = dict(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=10.0, m_n=1, g_a=0.0, c_tau=0.0, geometry=geometry)
    return ndf.ContactProblem(**{**data, **changes})


def test_arc_through_a_point_has_the_circle_of_the_three_points():
    arc = Arc((-1.0, 1.0), (1.0, 1.0), (0.0, 0.0))
    assert arc.centre == pytest.approx((0.0, 1.0), abs=1e-15) and arc.radius == pytest.approx(1.0)
    assert arc.sweep == pytest.approx(math.pi)  # counter-clockwise around (0, 1), through the bottom
    assert arc.segment_area() == pytest.approx(math.pi / 2)
    other = Arc((1.0, 1.0), (-1.0, 1.0), (0.0, 2.0))  # the same circle, the top half, also counter-clockwise
    assert other.sweep == pytest.approx(math.pi) and other.length == pytest.approx(math.pi)
    clockwise = Arc((1.0, 1.0), (-1.0, 1.0), (0.0, 0.0))
    assert clockwise.sweep == pytest.approx(-math.pi) and clockwise.segment_area() == pytest.approx(-math.pi / 2)
    pieces = arc.pieces()
    assert len(pieces) == 2 and pieces[0][2] == pytest.approx((0.0, 0.0), abs=1e-15)
    assert pieces[0][1] == pytest.approx((-1.0, 0.0), abs=1e-15)  # the tangents' intersection: an exact circle
    assert arc.distance([(0.0, -1.0), (0.0, 2.0), (2.0, 1.0)]) == pytest.approx([1.0, math.sqrt(2), 1.0])


@pytest.mark.parametrize("kwargs, message", [
    (dict(vertices=[(0, 0), (1, 0)], labels=["a", "b"], arcs={0: (0.5, 0.0)}), "on a line"),
    (dict(vertices=[(0, 0), (1, 0)], labels=["a", "b"]), "at least 3 vertices"),
    (dict(vertices=[(0, 0), (1, 0), (0, 1)], labels=["a", "b", "c"], arcs={3: (1, 1)}), "not a side number"),
    (dict(vertices=[(0, 0), (0, 1), (1, 0)], labels=["a", "b", "c"]), "counter-clockwise"),
    (dict(vertices=[(0, 0), (1, 0), (0, 1)], labels=["a", "b"]), "one label per side"),
    (dict(vertices=[(0, 0), (1, 0), (0, 1)], labels=["a", "b", "c"], arcs={0: ("x", 1)}), r"arcs\[0\]"),
    (dict(vertices=[(0, 0), (2, 0), (2, 1), (0, 1)], labels=list("abcd"), arcs={0: (1.0, 1.5)}),
     "crosses or touches itself"),
])
def test_bad_loops_are_refused_with_a_reason(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Loop(**kwargs)


def test_bad_domains_are_refused_with_a_reason():
    square = Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["a"] * 4)
    with pytest.raises(ValueError, match="region 'bad name' must be"):
        Domain({"bad name": square})
    with pytest.raises(ValueError, match="reserved"):
        Domain({"interface": square})
    with pytest.raises(ValueError, match="hole must lie inside a region"):
        Domain({"omega": square}, holes=[Loop.circle((3, 3), 0.1, "hole")])
    with pytest.raises(ValueError, match="side label 'a b'"):
        Domain({"omega": Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["a b"] * 4)})
    with pytest.raises(ValueError, match="at least one region"):
        Domain({})


def test_regions_share_sides_as_interfaces_and_holes_and_inclusions_count_in_the_area():
    left = Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "mid", "top", "wall"])
    right = Loop([(1, 0), (2, 0), (2, 1), (1, 1)], ["bottom", "free", "top", "mid"])
    domain = Domain({"steel": left, "rubber": right}, holes=[Loop.circle((1.5, 0.5), 0.25, "hole")])
    assert domain.area == pytest.approx(2 - math.pi / 16, rel=1e-14)
    assert set(domain.side_names) == {"bottom", "wall", "top", "free", "hole"}
    interfaces = [s for s in domain.segments if s[1] == INTERFACE]
    assert len(interfaces) == 1 and {interfaces[0][2], interfaces[0][3]} == {1, 2}
    inclusion = Domain({"matrix": Loop([(0, 0), (2, 0), (2, 1), (0, 1)], list("abcd")),
                        "fibre": Loop.circle((1.0, 0.5), 0.25, "ignored")})
    assert inclusion.area == pytest.approx(2.0, rel=1e-14) and "ignored" not in inclusion.side_names
    mesh = ndf.netgen_mesh(problem(inclusion, dirichlet="d", traction=["b", "c"], contact="a"), 0.2)
    assert set(mesh.GetMaterials()) == {"matrix", "fibre"}
    fibre = ngs.Integrate(mesh.MaterialCF({"fibre": 1.0}, default=0.0), mesh)
    assert fibre == pytest.approx(math.pi / 16, rel=0.05)  # straight chords: the inscribed polygon


def test_netgen_follows_region_interfaces_and_holes_and_curving_gives_the_exact_area():
    left = Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["contact", "mid", "top", "dirichlet"])
    right = Loop([(1, 0), (2, 0), (2, 1), (1, 1)], ["contact", "top", "top", "mid"])
    domain = Domain({"steel": left, "rubber": right}, holes=[Loop.circle((1.5, 0.5), 0.2, "hole")])
    p = problem(domain, traction=["top", "hole"], E={"steel": 100.0, "rubber": 1.0})
    mesh = ndf.netgen_mesh(p, 0.15)
    assert set(mesh.GetMaterials()) == {"steel", "rubber"}
    centroids = np.asarray(ndf.meshes.triangle_corners(mesh)).mean(axis=1)
    regions = np.array([mesh.GetMaterials()[el.index] for el in mesh.Elements(ngs.VOL)])
    assert np.all((centroids[:, 0] < 1) == (regions == "steel"))  # no element crosses x = 1
    straight = ngs.Integrate(1, mesh)
    mesh.Curve(4)
    assert abs(straight - domain.area) > 1e-3 and abs(ngs.Integrate(1, mesh) - domain.area) < 1e-6
    ndf.meshes.check_mesh(p, mesh)  # chords plus their circular segments give the area exactly


def test_refinement_puts_new_boundary_points_on_the_circle_and_solve_curves_the_mesh():
    p = problem(Domain({"omega": HALF_DISK}), u_D=(0, -0.01), g_a=ngs.y)
    mesh = ndf.netgen_mesh(p, 0.5)
    for _ in range(2):
        refine(mesh, np.ones(mesh.ne, dtype=bool))
    points, _, segments, labels = mesh_arrays(mesh)
    on_arc = points[np.unique(segments[labels == "contact"])]
    assert np.abs(np.hypot(on_arc[:, 0], on_arc[:, 1] - 1) - 1).max() < 1e-14
    sol = ndf.solve(p, mesh, order=3)
    assert ngs.Integrate(1, sol.mesh) == pytest.approx(math.pi / 2, abs=1e-5)  # the solution's own mesh, curved
    assert ngs.Integrate(1, mesh) < math.pi / 2 - 1e-3  # the given mesh is left straight
    assert ndf.kkt_residuals(sol)["equilibrium"] < 1e-12  # contact weights of the curved edges (not chords)


def test_a_curved_domain_needs_a_mesh_that_carries_its_geometry():
    p = problem(Domain({"omega": HALF_DISK}))
    mesh = ndf.netgen_mesh(p, 0.5)
    rebuilt = mesh_from_arrays(p, *mesh_arrays(mesh))
    with pytest.raises(ValueError, match="carries no geometry"):
        ndf.solve(p, rebuilt, order=2)


def test_a_mesh_of_another_domain_is_refused():
    disk = problem(Domain({"omega": HALF_DISK}))
    flatter = problem(Domain({"omega": Loop([(-1, 1), (1, 1)], ["contact", "dirichlet"], arcs={0: (0.0, 0.1)})}))
    with pytest.raises(ValueError, match="does not fit the problem's domain"):
        ndf.meshes.check_mesh(disk, ndf.netgen_mesh(flatter, 0.5))


def square(x0, y0, size, labels="abcd"):
    return Loop([(x0, y0), (x0 + size, y0), (x0 + size, y0 + size), (x0, y0 + size)], list(labels))


@pytest.mark.parametrize("regions, holes, message", [
    ({"a": square(0, 0, 1), "b": square(0.5, 0.5, 1)}, [], "the sides of region 'a' and region 'b' cross"),
    ({"a": square(0, 0, 2)}, [Loop.circle((0.7, 0.7), 0.3, "h"), Loop.circle((1.1, 0.7), 0.3, "h")],
     "the sides of holes.0. and holes.1. cross"),
    ({"a": square(0, 0, 1)}, [Loop([(0.3, 0.4), (0.7, 0.4), (0.5, 0.75)], list("hhh")),
                               Loop([(0.5, 0.28), (0.7, 0.63), (0.3, 0.63)], list("hhh"))],
     "the sides of holes.0. and holes.1. cross"),  # a star: no vertex of either inside the other
    ({"a": square(0, 0, 2)}, [Loop.circle((1, 1), 0.5, "h"), Loop.circle((1, 1), 0.2, "h")],
     r"holes\[1\] lies inside holes\[0\]"),
    ({"a": square(0, 0, 2), "b": Loop.circle((0.8, 1), 0.15, "i")}, [Loop.circle((1, 1), 0.5, "h"),
                                                                    Loop.circle((1.2, 1), 0.1, "j")],
     r"holes\[1\] lies inside holes\[0\]"),  # beside the region in the hole, not in it
    ({"a": square(0, 0, 2), "b": Loop.circle((1.01, 1), 0.5, "i")}, [Loop.circle((1, 1), 0.5, "h")],
     r"the sides of region 'b' and holes\[0\] cross \(two bodies may touch, not overlap\)"),
    ({"a": square(0, 0, 2), "b": Loop.circle((1.2, 1), 0.4, "i")}, [Loop.circle((1, 1), 0.5, "h")],
     r"the sides of region 'b' and holes\[0\] cross \(two bodies may touch, not overlap\)"),
    ({"a": Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["a", "interface", "c", "d"])}, [],
     "labelled 'interface' but no other region shares it"),
])
def test_domains_whose_loops_do_not_fit_together_are_refused(regions, holes, message):
    """Overlapping regions were meshed twice (area 2 instead of 1.75), a partly shared side left a crack
    between two regions, nested or crossing holes reached Netgen."""
    with pytest.raises(ValueError, match=message):
        Domain(regions, holes=holes)


@pytest.mark.parametrize("radius", [0.5, 0.1])
def test_a_region_in_a_hole_is_a_body_of_its_own(radius):
    """A disk in the hole of a square, on the hole's circle or inside it, with a hole of its own: two bodies, the
    disk's sides keep their labels (not interfaces), the hole in the disk belongs to the disk; sides on one curve
    are touching sides (a contact pair), and the area counts the disk."""
    domain = Domain({"a": square(0, 0, 2), "b": Loop.circle((1, 1), radius, "rim")},
                    holes=[Loop.circle((1, 1), 0.5, "bore"), Loop.circle((1, 1), 0.05, "axle")])
    assert domain.bodies == ((0,), (1,)) and domain.side_names == ("a", "b", "c", "d", "rim", "bore", "axle")
    assert {label: (left, right) for _, label, left, right in domain.segments} == {
        "a": (1, 0), "b": (1, 0), "c": (1, 0), "d": (1, 0), "rim": (2, 0), "bore": (0, 1), "axle": (0, 2)}
    assert domain.touching == ({("bore", "rim")} if radius == 0.5 else set())
    assert domain.area == pytest.approx(4 - math.pi * (0.25 - radius**2 + 0.05**2), rel=1e-14)


TOUCHES = r"holes\[0\] touches the boundary of region 'omega' at about \(0, 0\) \(distance 0\)"


@pytest.mark.parametrize("regions, holes, message", [
    ({"omega": square(0, 0, 1)}, [Loop.circle((0.5, 0.25), 0.25, "h")],
     r"holes\[0\] touches the boundary of region 'omega' at about \(0.5, 0\) \(distance 0\): a hole must keep a "
     r"positive distance from the boundary and from the other holes, more than 0.0001 of the domain's size"),
    ({"omega": square(0, 0.05, 1)}, [Loop.circle((0.5, 0.3), 0.25, "h")],  # its lowest point 0.05 - 1e-17
     r"holes\[0\] touches the boundary of region 'omega' at about \(0.5, 0.05\) \(distance 0\)"),
    ({"omega": square(0, 0, 1)}, [Loop.circle((0.5, 0.25001), 0.25, "h")], r"about \(0.5, 1e-05\) \(distance 1e-05\)"),
    ({"omega": square(0, 0, 1)}, [Loop([(0.5, 0), (0.7, 0.3), (0.3, 0.3)], ["h"] * 3)], r"holes\[0\] .* \(0.5, 0\)"),
    ({"omega": square(0, 0.05, 1)}, [Loop([(0.5, 0.15 - 0.1), (0.7, 0.3), (0.3, 0.3)], ["h"] * 3)],
     r"holes\[0\] touches .* \(0.5, 0.05\)"),  # the vertex 0.05 - 7e-18: its sides cross the side by round-off
    ({"omega": square(0, 0, 1)}, [Loop([(0.3, 0), (0.7, 0), (0.5, 0.3)], ["h"] * 3)], r"holes\[0\] touches the bound"),
    ({"omega": square(0, 0, 1)}, [Loop([(0, 0), (0.3, 0.1), (0.1, 0.3)], ["h"] * 3)], TOUCHES),
    ({"omega": square(0, 0, 1)}, [Loop.circle((0.25, 0.5), 0.125, "h"), Loop.circle((0.5, 0.5), 0.125, "h")],
     r"holes\[1\] touches holes\[0\] at about \(0.375, 0.5\) \(distance 0\)"),
    ({"omega": square(0, 0, 1)}, [Loop.circle((0.3, 0.5), 0.2, "h"), Loop.circle((0.7, 0.5), 0.2, "h")],
     r"holes\[1\] touches holes\[0\] at about \(0.5, 0.5\)"),  # 0.3 + 0.2 > 0.7 - 0.2 by round-off
    ({"omega": HALF_DISK}, [Loop.circle((0, 0.3), 0.3, "h")], TOUCHES),
    ({"omega": HALF_DISK}, [Loop.circle((0.42, 0.44), 0.3, "h")], r"about \(0.6, 0.2\)"),  # inside both arcs
    ({"omega": Loop([(0, 0), (2, 0), (0, 2)], list("abc"))}, [Loop.circle((0.6, 0.6), 0.8 / math.sqrt(2), "h")],
     r"holes\[0\] touches the boundary of region 'omega' at about \(1, 1\)"),  # on the hypotenuse, not at a vertex
    ({"omega": HALF_DISK}, [Loop([(0.6, 0.2), (0.6, 0.6), (0.2, 0.6)], ["h"] * 3)], r"about \(0.6, 0.2\) \(distance 0"),
    ({"matrix": square(0, 0, 1), "fibre": Loop.circle((0.5, 0.25), 0.25, "i")}, [],
     r"region 'fibre' touches the boundary of region 'matrix' at about \(0.5, 0\)"),
])
def test_a_hole_that_touches_the_boundary_or_another_hole_is_refused_naming_both_and_the_point(regions, holes, message):
    """Tangent or touching within CLEARANCE of the size (a circle on a side or an arc, a polygon's vertex or side
    on a side, two holes): Netgen failed ("meshing failed") or meshed a pinched domain; round-off that makes the
    curves cross by 1e-17 still reads as touching."""
    with pytest.raises(ValueError, match=message):
        Domain(regions, holes=holes)


@pytest.mark.parametrize("regions, holes", [
    ({"omega": square(0, 0, 1, ["contact", "dirichlet", "traction", "traction"])},
     [Loop.circle((0.5, 0.251), 0.25, "traction")]),
    ({"omega": square(0, 0, 1, ["contact", "dirichlet", "traction", "traction"])},
     [Loop([(0.5, 0.001), (0.7, 0.3), (0.3, 0.3)], ["traction"] * 3),
      Loop.circle((0.5, 0.5), 0.199, "traction"), Loop.circle((0.8, 0.5), 0.1, "traction")]),
    ({"omega": Loop([(-1, 1), (1, 1)], ["contact", "dirichlet"], arcs={0: (0.0, 0.0)})},
     [Loop.circle((0.3 * 0.6, 1 - 0.8 * 0.698), 0.3, "traction")]),  # 2e-3 (1e-3 of the size) inside the arc
])
def test_a_hole_clearly_apart_meshes_and_solves(regions, holes):
    """Holes 1e-3 of the size from a side, an arc (closer than the 1e-3 deviation of the arc's polyline) or
    another hole are accepted, and Netgen meshes them at coarse and fine mesh sizes."""
    domain = Domain(regions, holes=holes)
    p = problem(domain, u_D=(0, -0.01), g_a=-0.01)
    for maxh in (0.5, 0.1):
        mesh = ndf.netgen_mesh(p, maxh * domain.diameter())  # check_mesh: the holes' area left out, to the chords
    sol = ndf.solve(p, mesh, order=2)
    assert ndf.kkt_residuals(sol)["equilibrium"] < 1e-10


def test_how_close_two_loops_come_is_exact_for_arcs():
    """closest_approach against distances worked out by hand; contains exact between an arc and its chord."""
    line = Loop([(0, 0), (1, 0), (1, 1), (0, 1)], list("abcd"))
    distance, point = closest_approach(line, Loop.circle((0.5, 0.26), 0.25, "h"))
    assert distance == pytest.approx(0.01) and point == pytest.approx((0.5, 0.01))
    assert closest_approach(Loop.circle((0, 0), 1, "a"), Loop.circle((2.5, 0), 1, "b"))[0] == pytest.approx(0.5)
    assert closest_approach(Loop.circle((0, 0), 1, "a"), Loop.circle((0.2, 0), 0.5, "b"))[0] == pytest.approx(0.3)
    diagonal = Loop([(0, 0), (2, 0), (0, 2)], list("abc"))  # nearest to the hypotenuse inside its quarter arc
    distance, point = closest_approach(diagonal, Loop.circle((0.6, 0.6), 0.5, "h"))
    assert distance == pytest.approx(0.8 / math.sqrt(2) - 0.5)
    assert point == pytest.approx([0.6 + 0.5 / math.sqrt(2)] * 2)
    distance, point = closest_approach(Loop.circle((0, 0), 0.2, "a"), Loop.circle((0.3, 0.4), 0.2, "b"))
    assert distance == pytest.approx(0.1) and point == pytest.approx((0.12, 0.16))
    half = Loop([(1, 0), (-1, 0)], ["a", "b"], arcs={0: (0, 1)})  # the upper half disk: its arc ends at (+-1, 0)
    assert closest_approach(half, Loop.circle((0, -2), 0.5, "c"))[0] == pytest.approx(1.5)  # from the chord
    assert closest_approach(Loop([(1, 0), (-1, 0)], ["a", "b"], arcs={0: (0, 1), 1: (0, 0.5)}),
                            Loop.circle((0, -2), 0.5, "c"))[0] == pytest.approx(math.hypot(1, 2) - 0.5)  # arc ends
    distance, point = closest_approach(line, Loop.circle((0.5, 0.2), 0.25, "h"))  # crosses the bottom side
    assert distance == 0 and point == pytest.approx((0.35, 0.0))
    assert list(contains(HALF_DISK, [(0, 0.0005), (0, -0.0005), (0.5, 1.5)])) == [True, False, False]


def test_a_circle_of_two_half_arcs_is_one_loop_of_two_sides():
    """The two halves of a circle have the same end points and centre: they are two sides, not one shared."""
    disk = Domain({"omega": Loop([(0, 0.5), (1, 0.5)], ["a", "b"], arcs={0: (0.5, 0.0), 1: (0.5, 1.0)})})
    assert disk.area == pytest.approx(math.pi / 4) and disk.side_names == ("a", "b")
