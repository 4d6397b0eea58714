"""Problem data checked pointwise on the mesh, and the size limit (ngdgfric.checks)."""

import dataclasses

import ngsolve as ngs
import pytest

import ngdgfric as ndf
from ngdgfric.checks import check_data, check_size

x, y = ngs.x, ngs.y


@pytest.mark.parametrize("change, message", [
    # E vanishes only on the side x = 0 (element edges and vertices): Gauss points alone would miss it
    (dict(E=2000 * x), r"E must be finite and > 0 on Omega, got 0.0 at \(0, "),
    (dict(E=ngs.log(x + 1e-300)), "E must be finite and > 0 on Omega"),
    (dict(f=ngs.CF((0, 1 / (y - 0.55)))), "f must be finite on Omega"),  # a pole on an element edge
    (dict(g=(ngs.sqrt(0.5 - x), -190.0)), r"g must be finite on the boundary 'traction', got \(nan, -190.0\)"),
    (dict(c_n=x - 0.25), "c_n must be finite and >= 0 on the boundary 'contact'"),
    # negative only at the end x = 0 of Gamma_C
    (dict(c_tau=450 * x - 1e-9), r"c_tau must be finite and >= 0 on the boundary 'contact', got -1e-09 at \(0, "),
    (dict(g_a=ngs.sqrt(x - 2)), "g_a must be finite on the boundary 'contact', got nan"),
])
def test_bad_data_are_named_with_a_point(change, message):
    problem = dataclasses.replace(ndf.example_6_1(), **change)
    mesh = ndf.uniform_mesh(problem, 0.25)
    with pytest.raises(ValueError, match=message):
        check_data(problem, mesh, 1)
    with pytest.raises(ValueError, match=message.split(",")[0]):
        ndf.solve(problem, mesh)


def test_valid_varying_data_pass():
    # positive, finite data that only touch their bounds where allowed (c_n = 0 at one end)
    problem = dataclasses.replace(ndf.example_6_1(), E=2000 * (1 + x), c_n=x, c_tau=450 * y, g_a=0.05 * x,
                                  f=(ngs.sin(x), 0.0))
    mesh = ndf.netgen_mesh(problem, 0.3)
    for order in (1, 4):
        check_data(problem, mesh, order)


def test_size_limit_counts_dofs_and_memory():
    check_size([1] * 1000, max_ndof=6000)
    with pytest.raises(ValueError, match="6006 DOFs .* is more than max_ndof = 6000"):
        check_size([1] * 1001, max_ndof=6000)
    # without max_ndof: memory; P1 on 2.5e6 elements (15e6 DOFs) is above 8 GB, 1e5 elements is not
    check_size(1, elements=10**5)
    with pytest.raises(ValueError, match="pass max_ndof=15000000"):
        check_size(1, elements=2.5e6)
    check_size(1, max_ndof=20_000_000, elements=2.5e6)  # the user may raise the limit
    check_size(1, elements=2.5e6, max_bytes=1e12)  # or the memory budget (a parameter, default MEMORY_BUDGET)
    with pytest.raises(ValueError, match="more than the 1e-06 GB allowed by max_bytes = 1000"):
        check_size(1, elements=1, max_bytes=1e3)


def test_data_invalid_only_at_a_contact_gauss_point_are_found():
    # c_n < 0 only within 1e-6 of the first Gauss point of the contact rule (P1, h = 1/4): the check's
    # own rules of degree 2p + 2 missed it and the solver failed with "did not converge" (exit 1)
    gauss = 0.25 * (0.5 - 3**0.5 / 6)
    problem = dataclasses.replace(ndf.example_6_1(), c_n=(x - gauss) ** 2 - 1e-12)
    with pytest.raises(ValueError, match="c_n must be finite and >= 0 on the boundary 'contact', got -1e-12"):
        check_data(problem, ndf.uniform_mesh(problem, 0.25), 1)


@pytest.mark.parametrize("change", [dict(g_a=ngs.CF(0.001j)), dict(E=ngs.CF(2000 + 100j)), dict(f=ngs.CF((1j, 0)))])
def test_complex_data_are_refused(change):
    # g_a = 0.001j was solved as g_a = 0 with only numpy's ComplexWarning
    with pytest.raises(ValueError, match="real"):
        dataclasses.replace(ndf.example_6_1(), **change)
