import ngsolve as ngs
import pytest

import ngdgfric as ndf


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


def test_edge_length_function_is_the_edge_length():
    from ngdgfric.forms import edge_length
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
