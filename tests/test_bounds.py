"""The table of the data and their bounds (ngdgfric.bounds): one source for ContactProblem and check_data."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.bounds import DATA
from ngdgfric.checks import BOUNDARY, VOLUME, check_data


@pytest.mark.parametrize("name", [name for name, datum in DATA.items() if datum.low is not None])
def test_a_number_and_a_function_below_the_lower_bound_are_refused_alike(name):
    datum = DATA[name]
    below = datum.low - 1.0 if not datum.low_open else float(datum.low)
    problem = ndf.example_6_1()
    with pytest.raises(ValueError, match=f"{name} must be"):
        dataclasses.replace(problem, **{name: below})
    if datum.kind == "scalar":  # the same bound pointwise on a mesh
        varying = dataclasses.replace(problem, **{name: below + 0 * ngs.x})
        with pytest.raises(ValueError, match=f"{name} must be finite and {'>' if datum.low_open else '>='}"):
            check_data(varying, ndf.uniform_mesh(problem, 0.5), 1)


def test_the_pointwise_checks_cover_every_datum_that_may_be_a_function():
    pointwise = set(VOLUME) | {name for data in BOUNDARY.values() for name in data}
    assert pointwise == {name for name, datum in DATA.items() if datum.kind != "number"}
    assert DATA["nu"].requirement() == "finite and > -1 and < 0.5"
    assert list(DATA["nu"].bad(np.array([-1.0, 0.0, 0.49, 0.5]))) == [True, False, False, True]
