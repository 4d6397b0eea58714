"""solve() and the Solution record: defaults, the warm-start conversion, progress lines, timings."""

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.solution import DEFAULT_SOLVER_TOL, finish
from ngdgfric.transfer import WarmStart


@pytest.fixture(scope="module")
def example():
    p = ndf.example_6_1()
    return p, ndf.uniform_mesh(p, 1 / 8)


def test_default_tolerances_are_met(example):
    p, mesh = example
    newton = ndf.solve(p, mesh)
    assert newton.info["converged"] and newton.info["residual"] <= DEFAULT_SOLVER_TOL["newton"]
    uzawa = ndf.solve(p, mesh, solver="uzawa")
    assert uzawa.history[-1] <= DEFAULT_SOLVER_TOL["uzawa"] < uzawa.history[-2]
    assert np.abs(newton.u.vec.FV().NumPy() - uzawa.u.vec.FV().NumPy()).max() \
        <= 1e-5 * np.abs(newton.u.vec.FV().NumPy()).max()


def test_a_solution_and_its_warm_start_start_the_same_solve(example):
    p, mesh = example
    coarse = ndf.solve(p, ndf.uniform_mesh(p, 1 / 4))
    from_solution = ndf.solve(p, mesh, initial=coarse)
    from_warm_start = ndf.solve(p, mesh, initial=WarmStart.from_solution(coarse))
    assert np.array_equal(from_solution.u.vec.FV().NumPy(), from_warm_start.u.vec.FV().NumPy())
    assert from_solution.iterations == from_warm_start.iterations


def test_record_and_progress_lines(example):
    p, mesh = example
    lines = []
    sol = ndf.solve(p, mesh, solver="uzawa", progress=lines.append)
    assert sol.ndof == sol.discretization.V.ndof == sol.u.space.ndof
    assert (sol.method, sol.order, sol.solver, sol.state) == ("sipg", 1, "uzawa", None)
    assert len(lines) == sol.iterations // 100 and all(line.startswith("uzawa ") for line in lines)
    assert sol.timings["total"] >= max(sol.timings["solve"], sol.timings["assemble"]) > 0
    assert finish(sol) is sol  # nothing to continue


def test_unknown_solver_is_refused_before_assembly():
    with pytest.raises(ValueError, match="solver must be one of"):
        ndf.solve(ndf.example_6_1(), None, solver="gauss-seidel")
