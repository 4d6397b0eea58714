"""Transfers between spaces: the coefficient copy between L2 orders against NGSolve's Set."""

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.discretization import dg_space
from ngdgfric.transfer import copy_orders


@pytest.mark.parametrize("mesh_kind", ["uniform", "netgen"])
def test_copy_between_orders_equals_the_l2_projection(mesh_kind):
    """Random p_T in 1..6 up into p = 8 (exact), and down into random lower orders (the element-wise L2
    projection, which ``Set`` computes by quadrature of degree 2 p_T + bonus)."""
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4) if mesh_kind == "uniform" else ndf.netgen_mesh(problem, 0.3)
    rng = np.random.default_rng(5)
    low = rng.integers(1, 7, mesh.ne)
    u = ngs.GridFunction(dg_space(mesh, low))
    u.vec.FV().NumPy()[:] = rng.standard_normal(len(u.vec))
    high = ngs.GridFunction(ngs.L2(mesh, order=8) ** 2)
    copy_orders(u, low, high, np.full(mesh.ne, 8))
    expected = ngs.GridFunction(high.space)
    expected.Set(u)
    scale = np.abs(expected.vec.FV().NumPy()).max()
    assert np.abs(high.vec.FV().NumPy() - expected.vec.FV().NumPy()).max() <= 1e-12 * scale
    lower = np.minimum(low, rng.integers(1, 7, mesh.ne))
    down = ngs.GridFunction(dg_space(mesh, lower))
    copy_orders(high, np.full(mesh.ne, 8), down, lower)
    projected = ngs.GridFunction(down.space)
    projected.Set(u, bonus_intorder=8)  # exact quadrature (Set's default rule is exact only for p(source) <= p)
    assert np.abs(down.vec.FV().NumPy() - projected.vec.FV().NumPy()).max() <= 1e-12 * scale


def test_copy_refuses_orders_that_do_not_fit_the_space():
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 2)
    u = ngs.GridFunction(dg_space(mesh, 2))
    v = ngs.GridFunction(dg_space(mesh, 3))
    with pytest.raises(ValueError, match="orders"):
        copy_orders(u, np.full(mesh.ne, 3), v, np.full(mesh.ne, 3))
