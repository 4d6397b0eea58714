import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.meshes import refine, triangle_corners


@pytest.mark.parametrize("diagonal", ["sw-ne", "nw-se"])
def test_uniform_mesh_has_squares_of_side_h_and_the_problem_labels(diagonal):
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 8, diagonal=diagonal)
    assert mesh.ne == 2 * 8 * 8
    assert ngs.Integrate(ngs.CF(1), mesh) == pytest.approx(1.0)
    lengths = {name: ngs.Integrate(ngs.CF(1), mesh, definedon=mesh.Boundaries(name))
               for name in ("dirichlet", "traction", "contact")}
    assert lengths == pytest.approx({"dirichlet": 1.0, "traction": 2.0, "contact": 1.0})
    # Gamma_C is the bottom side y = 0.05
    y_mean = ngs.Integrate(ngs.y, mesh, definedon=mesh.Boundaries("contact"))
    assert y_mean == pytest.approx(0.05)


def rectangle(width, height):
    """Example 6.2's data on the rectangle (0, width) x (0, height)."""
    geometry = ndf.Polygon.rectangle(0, 0, width, height, bottom="contact", right="traction", top="dirichlet",
                                     left="traction")
    return dataclasses.replace(ndf.example_6_2(), geometry=geometry)


def test_grid_mesh_is_the_uniform_mesh_where_h_divides_and_nested_cells_where_it_does_not():
    from ngdgfric.meshes import grid_mesh, mesh_arrays
    p = ndf.example_6_1()
    for refinements in (0, 2):
        ours = mesh_arrays(grid_mesh(p, 0.5, refinements))
        uniform = mesh_arrays(ndf.uniform_mesh(p, 0.5 / 2**refinements))
        assert all(np.array_equal(a, b) for a, b in zip(ours, uniform, strict=True))
    p = rectangle(1.3, 0.7)  # 0.5 divides neither side: uniform_mesh refuses it
    with pytest.raises(ValueError, match="does not divide the side length 1.3"):
        ndf.uniform_mesh(p, 0.5)
    coarse, fine = grid_mesh(p, 0.5), grid_mesh(p, 0.5, 1)
    assert (coarse.ne, fine.ne) == (2 * 3 * 2, 2 * 6 * 4)  # ceil(2.6) x ceil(1.4) cells, then each in 2 x 2
    assert ngs.Integrate(ngs.CF(1), fine) == pytest.approx(1.3 * 0.7, rel=1e-14)
    assert set(map(tuple, mesh_arrays(coarse)[0].round(12))) <= set(map(tuple, mesh_arrays(fine)[0].round(12)))
    with pytest.raises(ValueError, match="refinements must be an integer"):
        grid_mesh(p, 0.5, -1)
    # the element limit counts grid_mesh's own cells: 1 x 1 cells refined 10 times on a 1 cm square (was estimated
    # as uniform squares of side 0.5 / 2^10: 2 elements, and 2 million were built)
    with pytest.raises(ValueError, match="would make 2.1e\\+06 elements"):
        grid_mesh(rectangle(0.01, 0.01), 0.5, 10)


@pytest.mark.parametrize("width, height", [(1.3, 0.7), (0.01, 0.01)])
def test_the_default_meshes_fit_rectangles_of_any_size(width, height):
    # adapt's first mesh was uniform h = 1/2 on every rectangle: "h = 0.5 does not divide the side length 1.3",
    # also for a square of 1 cm in metres; the mesh is scaled with the domain as Netgen's is elsewhere
    from ngdgfric.adaptivity import initial_mesh
    p = rectangle(width, height)
    mesh = initial_mesh(p)
    assert ngs.Integrate(ngs.CF(1), mesh) == pytest.approx(width * height, rel=1e-13)
    assert mesh.ne >= 8
    run = ndf.adapt(p, max_levels=2, progress=None)
    assert len(run.levels) == 2 and run.levels[1]["eta_h"] < run.levels[0]["eta_h"]


def test_edge_length_function_is_the_edge_length():
    from ngdgfric.dg.forms import edge_length
    mesh = ndf.uniform_mesh(ndf.example_6_2(), 1 / 4)
    h_e = edge_length(mesh)
    # int_{dT} h_e ds = sum_e |e|^2 = 2 (1/4)^2 + (sqrt(2)/4)^2 on every triangle
    per_element = ngs.Integrate(h_e * ngs.dx(element_boundary=True), mesh, element_wise=True).NumPy()
    assert per_element == pytest.approx(4 / 16)


def test_netgen_mesh_carries_the_labels():
    p = ndf.example_6_2()
    mesh = ndf.netgen_mesh(p, 0.3)
    assert set(mesh.GetBoundaries()) == {"dirichlet", "traction", "contact"}
    assert ngs.Integrate(ngs.CF(1), mesh, definedon=mesh.Boundaries("traction")) == pytest.approx(2.0)


@pytest.mark.parametrize("h", [0.3, -1, 0])
def test_bad_h_raises(h):
    with pytest.raises(ValueError, match="h"):
        ndf.uniform_mesh(ndf.example_6_1(), h)


def test_mesh_without_the_problem_names_is_rejected():
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.5))
    with pytest.raises(ValueError, match="no boundary named"):
        ndf.solve(ndf.example_6_2(), mesh)


def test_mesh_of_another_geometry_with_the_same_names_is_rejected():
    # Example 6.2's unit square has the boundary names of Example 6.1 but not its polygon
    p, other = ndf.example_6_1(), ndf.example_6_2()
    with pytest.raises(ValueError, match="does not fit the problem's polygon"):
        ndf.solve(p, ndf.uniform_mesh(other, 0.25))
    shifted = ndf.Polygon(tuple((x, y + 1e-6) for x, y in p.geometry.vertices), p.geometry.labels)
    with pytest.raises(ValueError, match="does not fit"):
        ndf.check_mesh(p, ndf.netgen_mesh(dataclasses.replace(p, geometry=shifted), 0.5))
    ndf.check_mesh(p, ndf.netgen_mesh(p, 0.3))  # its own meshes fit, also after refinement
    mesh = ndf.uniform_mesh(p, 0.25)
    refine(mesh, [True] * mesh.ne)
    ndf.check_mesh(p, mesh)


@pytest.mark.parametrize("make, size", [(ndf.uniform_mesh, 1e-5), (ndf.netgen_mesh, 1e-9)])
def test_size_is_checked_before_meshing(make, size):
    # uniform h = 1e-5 tried to allocate 74 GiB; Netgen with maxh = 1e-9 grew past 2 GB
    with pytest.raises(ValueError, match="would make about .* elements"):
        make(ndf.example_6_1(), size)
    with pytest.raises(ValueError, match="more than max_elements = 100"):
        make(ndf.example_6_1(), 0.05, max_elements=100)


def test_estimated_elements_against_the_meshers():
    p = ndf.example_6_1()
    assert ndf.meshes.estimated_elements(p, h=1 / 8) == ndf.uniform_mesh(p, 1 / 8).ne
    for maxh in (0.2, 0.1, 0.05):
        assert 1.0 <= ndf.meshes.estimated_elements(p, maxh=maxh) / ndf.netgen_mesh(p, maxh).ne < 1.55


def test_solve_refuses_above_the_size_limit_before_assembling():
    p = ndf.example_6_1()
    with pytest.raises(ValueError, match="more than max_ndof = 1000"):
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 16), max_ndof=1000)
    with pytest.raises(ValueError, match="GB, more than the 8 GB allowed by default"):
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 64), order=20)


@pytest.mark.parametrize("bisections, children", [(1, 2), (2, 4)])
def test_refine_bisects_every_marked_triangle_once_or_twice(bisections, children):
    """All elements marked: every triangle has 2 (one bisection) or 4 (two) children, the area is kept and
    the mesh still fits the problem (Netgen's bisection, :func:`ngdgfric.meshes.refine`)."""
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    ne = mesh.ne
    refine(mesh, [True] * ne, bisections=bisections)
    assert mesh.ne == children * ne
    assert ngs.Integrate(1, mesh) == pytest.approx(1.0, rel=1e-14)
    ndf.check_mesh(problem, mesh)


def test_refine_refuses_bad_arguments():
    mesh = ndf.uniform_mesh(ndf.example_6_2(), 1 / 2)
    with pytest.raises(ValueError, match="bisections must be 1 or 2"):
        refine(mesh, [True] * mesh.ne, bisections=3)
    with pytest.raises(ValueError, match="marked has 3 entries"):
        refine(mesh, [True] * 3)


def test_triangle_corners_are_the_elements_vertices():
    mesh = ndf.netgen_mesh(ndf.example_6_1(), 0.3)
    corners = triangle_corners(mesh)
    for el in mesh.Elements(ngs.VOL):
        expected = [mesh[v].point for v in el.vertices]
        assert corners[el.nr].tolist() == [list(point) for point in expected]


def test_nested_finds_deep_corner_layers_and_refuses_meshes_that_do_not_refine():
    # twelve geometric layers (elements 1e-4 of the coarse ones at the corners) used to be refused: corners moved
    # 0.1 % inwards were found in the neighbouring coarse element
    from ngdgfric.hp import containing
    from ngdgfric.meshes import nested, netgen_mesh, snapshot
    p = ndf.example_6_1()
    coarse = ndf.uniform_mesh(p, 0.5)
    fine = snapshot(coarse)
    for _ in range(12):
        refine(fine, containing(fine, p.geometry.corners), bisections=2)
    assert nested(coarse, fine) and nested(coarse, coarse) and not nested(fine, coarse)
    assert not nested(coarse, netgen_mesh(p, 0.13))
    w = ngs.CF((0.01 * ngs.x * ngs.y, 0.02 * ngs.x - 0.01 * ngs.y**2))  # in P2: exact on both meshes
    on_coarse = ngs.GridFunction(ngs.L2(coarse, order=2) ** 2)
    on_coarse.Set(w)
    sol = ndf.solve(p, fine, order=2)
    assert ndf.energy_norm(sol, on_coarse) == pytest.approx(ndf.energy_norm(sol, w), rel=1e-12)
