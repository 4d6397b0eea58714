"""ngdgfric.examples: the problems of Section 6, loaded from the shipped files, carry the printed data."""

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.examples import EXAMPLES, example

# Section 6 as printed: (E, nu, c_n, m_n, g_a, c_tau, Omega's corners, g as a function of (x, y))
PRINTED = {
    "6.1": (2000, 0.4, 1, 1, 0.05, 450, ((0, 0.05), (1, 1.05)), lambda x, y: (200 * (5 - y), -190)),
    "6.2": (2500, 0.2, 1, 1, 0.0, 250, ((0, 0), (1, 1)), lambda x, y: (880, 0)),
}
SIDES = {"6.1": ("contact", "dirichlet", "traction", "traction"),
         "6.2": ("contact", "traction", "dirichlet", "traction")}


@pytest.mark.parametrize("name", sorted(PRINTED))
def test_examples_carry_the_data_printed_in_section_6(name):
    E, nu, c_n, m_n, g_a, c_tau, (low, high), g = PRINTED[name]
    problem = example(name)
    assert (problem.E, problem.nu, problem.c_n, problem.m_n, problem.g_a, problem.c_tau, problem.m_t) \
        == (E, nu, c_n, m_n, g_a, c_tau, 0)
    assert problem.geometry.bounds == (*low, *high)
    assert problem.geometry.labels == SIDES[name]  # bottom, right, top, left
    assert problem.f == (0.0, 0.0)
    mesh = ndf.uniform_mesh(problem, 0.25)
    gx, gy = (ngs.CF(c) if not isinstance(c, ngs.CoefficientFunction) else c for c in problem.g)
    for x, y in ((0.0, low[1] + 0.3), (0.5, high[1]), (1.0, low[1] + 0.7)):
        point = mesh(x, y)
        assert (gx(point), gy(point)) == pytest.approx(g(x, y), rel=1e-15)
    assert problem.mu == pytest.approx(E / (2 * (1 + nu)), rel=1e-15)


def test_registry_and_unknown_names():
    assert sorted(EXAMPLES) == ["6.1", "6.2"]
    with pytest.raises(ValueError, match=r"6\.1.*6\.2.*got '6\.3'"):
        example("6.3")
    assert np.isclose(ndf.example_6_1().geometry.signed_area, 1.0)
