"""solve() and the Solution record: defaults, the warm-start conversion, progress lines, timings."""

import time
import warnings

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.errors import TimeLimitError
from ngdgfric.solution import DEFAULT_SOLVER_TOL, finish
from ngdgfric.studies.scenes import layers_indented, layers_pressure
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
    assert (sol.method, sol.max_order, sol.solver, sol.state) == ("sipg", 1, "uzawa", None)
    assert len(lines) == sol.iterations // 100 and all(line.startswith("uzawa ") for line in lines)
    assert sol.timings["total"] >= max(sol.timings["solve"], sol.timings["assemble"]) > 0
    assert finish(sol) is sol  # nothing to continue


def test_an_hp_solution_names_its_largest_degree_and_keeps_every_elements():
    """Solution.max_order is the largest p_T, Solution.orders the degree per element; the old name order (which
    read as "the" degree) still answers max_order with a DeprecationWarning."""
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    orders = 1 + np.arange(mesh.ne) % 3
    sol = ndf.solve(p, mesh, order=orders)
    assert sol.max_order == 3 and np.array_equal(sol.orders, orders) and sol.orders.dtype == np.int64
    sol.orders[:] = 7  # a copy
    assert np.array_equal(sol.orders, orders)
    with pytest.warns(DeprecationWarning, match="Solution.max_order"):
        assert sol.order == 3


def test_unknown_solver_is_refused_before_assembly():
    with pytest.raises(ValueError, match="solver must be one of"):
        ndf.solve(ndf.example_6_1(), None, solver="gauss-seidel")


@pytest.mark.parametrize("solver", ["newton", "uzawa", "fixed_point"])
def test_a_time_limit_stops_every_solver_with_a_named_error(example, solver):
    p, mesh = example
    start = time.perf_counter()
    with pytest.raises(TimeLimitError, match=r"stopped at its time limit \(max_seconds\) after \d+ iterations"):
        ndf.solve(p, mesh, solver=solver, max_seconds=1e-6)
    assert time.perf_counter() - start < 5
    with pytest.raises(ValueError, match="max_seconds must be a positive finite number"):
        ndf.solve(p, mesh, solver=solver, max_seconds=0)
    assert issubclass(TimeLimitError, ndf.SolverError)


def test_the_time_limit_counts_the_assembly():
    # P3 Bassi et al. with the contact open: assembly takes most of a solve; a limit of half the assembly time was
    # the solver's alone (Uzawa went on and converged in 2x the limit without a word)
    problem = layers_pressure().problem
    mesh = ndf.uniform_mesh(problem, 1 / 16)
    assembly = min(ndf.solve(problem, mesh, method="bassi", order=3, solver="uzawa").timings["assemble"]
                   for _ in range(2))
    with pytest.raises(TimeLimitError, match="Uzawa .* stopped at its time limit"):
        ndf.solve(problem, mesh, method="bassi", order=3, solver="uzawa", max_seconds=0.5 * assembly)


def test_a_body_loaded_by_a_penetration_only_has_kkt_residuals_at_round_off():
    # f = 0 and g = 0: the residual was divided by ||F|| = 0 (1e285) and the solver warned of an overflow
    scene = layers_indented(E1=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sol = ndf.solve(scene.problem, scene.mesh(1), order=2)
        kkt = ndf.kkt_residuals(sol)
    assert kkt["equilibrium"] <= 1e-12 and kkt["complementarity"] <= 1e-14
    assert ndf.energy_norm(sol, scene.exact) <= 1e-10 * ndf.energy_norm(sol)


def test_a_solution_prints_as_one_readable_line():
    problem = ndf.example_6_2()
    sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5), method="nipg", order=2)
    assert repr(sol) == f"Solution('Example 6.2', nipg p = 2, {sol.ndof} DOFs, newton {sol.iterations} iterations)"
