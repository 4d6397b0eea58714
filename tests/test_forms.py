import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.adaptivity import minimum_angle
from ngdgfric.dg.forms import dg_terms, edge_length, jump_inner, penalty_length
from ngdgfric.dg.material import EdgeCoefficient
from ngdgfric.meshes import grid_arrays, mesh_from_arrays
from ngdgfric.reference import difference
from ngdgfric.studies import rates
from ngdgfric.studies.cases import coercivity, energy_gram


@pytest.mark.parametrize("method", ["sipg", "nipg"])
@pytest.mark.parametrize("order, levels", [(1, (3, 4, 5)), (2, (2, 3, 4)), (3, (1, 2, 3))])
def test_energy_error_converges_at_rate_p(elasticity, method, order, levels):
    problem, u_exact = elasticity
    errors, l2 = [], []
    for k in levels:
        sol = ndf.solve(problem, ndf.uniform_mesh(problem, 2.0**-k), method=method, order=order)
        errors.append(ndf.energy_norm(sol, u_exact))
        e = difference(sol.u, u_exact)
        l2.append(ngs.Integrate(e * e, sol.mesh) ** 0.5)
    hs = [2.0**-k for k in levels]
    assert rates(errors, hs)[-1] == pytest.approx(order, abs=0.15)
    if method == "sipg":
        assert rates(l2, hs)[-1] == pytest.approx(order + 1, abs=0.15)


def test_sipg_matrix_is_symmetric_and_nipg_is_not():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    for method, symmetric in (("sipg", True), ("nipg", False)):
        A = ndf.Discretization(p, mesh, method=method, order=2).A.ToDense().NumPy()
        asym = np.abs(A - A.T).max() / np.abs(A).max()
        assert (asym < 1e-13) == symmetric, (method, asym)


def test_scalar_jump_product_equals_the_symmetric_tensor_product():
    mesh = ndf.uniform_mesh(ndf.example_6_2(), 1 / 2)
    n = ngs.specialcf.normal(2)
    a = ngs.CF((ngs.x + 2, ngs.x * ngs.y - 1))
    b = ngs.CF((ngs.y**2, 3 - ngs.x))
    tensor = ngs.InnerProduct(ngs.Sym(ngs.OuterProduct(a, n)), ngs.Sym(ngs.OuterProduct(b, n)))
    scalar = jump_inner(a, b, n)
    diff = ngs.Integrate((tensor - scalar) ** 2 * ngs.dx(element_boundary=True), mesh)
    size = ngs.Integrate(tensor**2 * ngs.dx(element_boundary=True), mesh)
    assert diff <= 1e-24 * size


def test_unknown_method_and_bad_order_and_eta_raise():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 2)
    with pytest.raises(ValueError, match="method"):
        ndf.solve(p, mesh, method="ipdg")
    with pytest.raises(ValueError, match="order"):
        ndf.solve(p, mesh, order=0)
    with pytest.raises(ValueError, match="eta"):
        ndf.solve(p, mesh, eta=-1.0)


def thin_mesh(problem, nx, ny):
    """The unit square cut into nx x ny rectangles, each cut by its diagonal: triangles with an angle of
    atan(nx / ny) (2.9 degrees for 2 x 40)."""
    points, triangles, segments, sides = grid_arrays((0.0, 0.0, 1.0, 1.0), nx, ny)
    return mesh_from_arrays(problem, points, triangles, segments, np.asarray(problem.geometry.labels)[sides])


@pytest.mark.slow
@pytest.mark.parametrize("order", [1, 2])
def test_the_default_sipg_penalty_stays_coercive_on_thin_triangles(order):
    # B_h(v, v) / |||v|||_h^2 > 0 for all v in V_h with the default eta = 30 mu on triangles with a 2.9 degree
    # angle, with a constant close to that of right isosceles triangles (0.60 at P1); the same eta over the
    # edge length |e| instead of min(|e|, 2 h_T) leaves B_h indefinite there
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=1.0, m_n=1, g_a=0.0, c_tau=0.0,
                                 geometry=ndf.Polygon.rectangle(0, 0, 1, 1, "contact", "traction", "dirichlet",
                                                                "traction"))
    mesh = thin_mesh(problem, 2, 40)
    assert minimum_angle(mesh) == pytest.approx(np.degrees(np.arctan(1 / 20)))
    disc = ndf.Discretization(problem, mesh, "sipg", order)
    gram = energy_gram(problem, mesh, order)
    assert coercivity(problem, mesh, "sipg", order, disc.eta, gram=gram) > 0.3
    u, v = disc.V.TnT()
    form = ngs.BilinearForm(disc.V)
    length = EdgeCoefficient(edge_length(mesh), edge_length(mesh), "|e|")
    for term in dg_terms(dataclasses.replace(disc.forms, p=order, h_penalty=length), u, v):
        form += term
    form.Assemble()
    A = form.mat.ToDense().NumPy()
    lower = np.linalg.cholesky(gram)
    scaled = np.linalg.solve(lower, np.linalg.solve(lower, 0.5 * (A + A.T)).T)
    assert np.linalg.eigvalsh(0.5 * (scaled + scaled.T))[0] < 0


def test_the_penalty_length_is_the_edge_length_on_the_meshes_of_the_paper():
    # h_e = min(|e|, 2 h_T+, 2 h_T-) equals |e| on both diagonals' structured meshes (legs and diagonals)
    problem = ndf.example_6_1()
    for diagonal in ("sw-ne", "nw-se"):
        mesh = ndf.uniform_mesh(problem, 1 / 4, diagonal=diagonal)
        length = penalty_length(mesh)
        space = ngs.L2(mesh, order=0, dgjumps=True)
        u, v = space.TnT()
        form = ngs.BilinearForm(space)
        form += (length.interior / edge_length(mesh) - 1) ** 2 * u * v * ngs.dx(skeleton=True)
        form += (length.boundary / edge_length(mesh) - 1) ** 2 * u * v * ngs.ds(skeleton=True)
        form.Assemble()
        assert np.abs(np.asarray(form.mat.AsVector())).max() <= 1e-28
