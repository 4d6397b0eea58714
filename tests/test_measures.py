"""ngdgfric.studies.measures: rates, slopes and relative differences recover known exponents exactly."""

import dataclasses
import math

import ngsolve as ngs
import pytest

import ngdgfric as ndf
from ngdgfric.studies import max_rel_diff, rates, slope


@pytest.mark.parametrize("order", [0.5, 1.0, 2.0])
def test_rates_of_a_power_law_are_its_exponent(order):
    hs = [2.0**-k for k in range(1, 6)]
    observed = rates([3.0 * h**order for h in hs], hs)
    assert observed[0] is None
    assert observed[1:] == pytest.approx([order] * 4, rel=1e-12)


def test_slope_of_a_power_law_in_the_dofs():
    dofs = [24, 96, 384, 1536]
    assert slope(dofs, [7.0 * n**-0.5 for n in dofs]) == pytest.approx(-0.5, rel=1e-12)
    assert math.isnan(slope(dofs[:1], [1.0]))


def test_max_rel_diff_of_a_scaled_solution_is_the_scaling():
    problem = ndf.example_6_2()
    sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
    scaled = ngs.GridFunction(sol.u.space)
    scaled.vec.data = 1.001 * sol.u.vec
    assert max_rel_diff(dataclasses.replace(sol, u=scaled), sol) == pytest.approx(1e-3, rel=1e-9)
    assert max_rel_diff(sol, sol) == 0.0
