import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.forms import jump_inner
from ngdgfric.reference import difference
from ngdgfric.studies import rates


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
