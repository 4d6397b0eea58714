"""The polygon checks (ngdgfric.geometry) through Polygon, and the polygon's area far from the origin."""

import dataclasses

import ngsolve as ngs
import pytest

import ngdgfric as ndf

NAN, INF = float("nan"), float("inf")


LABELS = ("contact", "dirichlet", "traction", "traction")
SQUARE = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))


@pytest.mark.parametrize("vertices, message", [
    (((0, 0), (1, 0), (1, 0), (0, 1)), r"vertices\[1\] .* and vertices\[2\] .* coincide"),  # crashed Netgen
    (((0, 0), (1, 0), (1, 1), (1 - 1e-9, 1)), "coincide"),  # made Netgen fail
    (((0, 0), (NAN, 0), (1, 1), (0, 1)), r"vertices\[1\] = \(nan, 0.0\): coordinates must be finite"),
    (((0, 0), (INF, 0), (1, 1), (0, 1)), "coordinates must be finite"),
    (((0, 0), (1, 0), (0, 1), (1, 1)), "sides 1 and 3 of the polygon cross"),  # Netgen looped for minutes
    (((0, 0), (2, 0), (1, 0), (1, 1)), "lies on side 0"),  # a spike back along a side
    (((0, 0), (1, 0), (0.5, 0.5 + 1e-9), (1, 1)), "lies on side|cross"),
    (((0, 0), (1, 0), "ab", (0, 1)), r"vertices\[2\] must be a pair of numbers"),
    (((0, 0), (0, 1), (1, 1), (1, 0)), "counter-clockwise"),
    (((0, 0), (1, 0)), "at least 3 vertices"),
])
def test_bad_polygons_raise_naming_the_defect(vertices, message):
    with pytest.raises(ValueError, match=message):
        ndf.Polygon(vertices, LABELS[:len(vertices)] + ("traction",) * (len(vertices) - 4))


def test_polygon_checks_accept_straight_angles_and_small_but_resolved_features():
    ndf.Polygon(((0, 0), (0.5, 0), (1, 0), (1, 1), (0, 1)), ("contact", "contact", "dirichlet", "traction",
                                                              "traction"))
    ndf.Polygon(((0, 0), (1, 0), (1, 1), (1 - 1e-5, 1), (0, 1)), LABELS + ("traction",))


@pytest.mark.parametrize("shift", [1e5, 1e6])
def test_polygons_far_from_the_origin(shift):
    # the shoelace formula on absolute coordinates lost the area (1.15 vs 1.150000572 at 1e5) and
    # called a unit square at (1e8, 1e8) clockwise
    pentagon = [(0, 0), (1, 0), (1.3, 0.6), (0.5, 1.1), (-0.2, 0.7)]
    polygon = ndf.Polygon([(x + shift, y + shift) for x, y in pentagon], LABELS + ("traction",))
    exact = 0.5 * sum(pentagon[k - 1][0] * pentagon[k][1] - pentagon[k][0] * pentagon[k - 1][1] for k in range(5))
    rounding = 1e-16 * shift  # the vertices' own rounding
    assert polygon.signed_area == pytest.approx(exact, rel=1e-9 + 10 * rounding)
    problem = dataclasses.replace(ndf.example_6_1(), geometry=polygon)
    mesh = ndf.netgen_mesh(problem, 0.3)
    assert ngs.Integrate(ngs.CF(1), mesh) == pytest.approx(exact, rel=1e-9 + 10 * rounding)

    with pytest.raises(ValueError, match="shift its coordinates towards the origin"):
        ndf.Polygon([(x + 1e7, y + 1e7) for x, y in pentagon], LABELS + ("traction",))
