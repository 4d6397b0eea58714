"""SolverError: what a failing solver hands back."""

import pytest

import ngdgfric as ndf
from ngdgfric.errors import SolverError


def test_solver_error_carries_a_copy_of_the_history_and_the_solver():
    history = (1.0, 0.5)
    error = SolverError("no convergence", history=history, solver="newton")
    assert isinstance(error, RuntimeError) and str(error) == "no convergence"
    assert error.history == [1.0, 0.5] and error.solver == "newton"
    assert SolverError("x").history == [] and SolverError("x").solver == ""


@pytest.mark.parametrize("solver, maxit", [("newton", 1), ("uzawa", 5)])
def test_each_solver_reports_one_history_entry_per_iteration(solver, maxit):
    p = ndf.example_6_1()
    with pytest.raises(SolverError, match="solver_tol") as err:
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), solver=solver, maxit=maxit)
    assert len(err.value.history) == maxit and err.value.solver == solver
