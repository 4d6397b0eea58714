"""The newest surface under odd input, where the right end is an answer, not a refusal (issue 48; the refusals are
the cases of tests/data/fuzz/surface.toml): a finite norm where a function is undefined off the sides it enters, the
same-problem check that compares roles, not the order of names, a numpy number taken as a number, adapt's refusals
before its first solve, a LockingWarning for a Poisson ratio largest at a vertex, the key ``target`` of the levels.
"""

import dataclasses
import math
import warnings

import numpy as np
import pytest
from ngsolve import CF, log, x, y

import ngdgfric as ndf
import ngdgfric.levels


@pytest.fixture(scope="module")
def example():
    problem = ndf.example_6_1()
    return problem, ndf.solve(problem, ndf.uniform_mesh(problem, 0.25))


def test_a_function_undefined_on_a_side_where_it_does_not_enter_has_a_finite_norm(example):
    """x log x is NaN on x = 0 (0 log 0), a traction side of Example 6.1: the jumps are taken on Gamma_D (x = 1) only,
    so the norm is that of the same function written so that it is 0 there, x log(x + 1e-300), to the last digit
    (measured: 70.46831594036146 both; it was NaN)."""
    _, sol = example
    value = ndf.energy_norm(sol, CF((x * log(x), 0)))
    assert math.isfinite(value)
    assert value == ndf.energy_norm(sol, CF((x * log(x + 1e-300), 0)))


@pytest.fixture(scope="module")
def rectangle():
    """A rectangle with sides a (contact), b (Dirichlet), c and d (traction), and its solution at h = 1/4."""
    problem = dataclasses.replace(ndf.example_6_1(), geometry=ndf.Polygon.rectangle(0, 0, 1, 1, "a", "b", "c", "d"),
                                  contact="a", dirichlet="b", traction=("c", "d"), g=(0.0, -100.0))
    return problem, ndf.solve(problem, ndf.uniform_mesh(problem, 0.25))


def test_the_same_problem_written_another_way_is_the_same_problem(rectangle):
    """The traction sides listed in another order, and a traction that differs from it only off its sides, are the
    same problem: the error against its solution is the error against itself (the check compared the sides' names in
    order and the traction at the elements' centroids, and refused both)."""
    problem, sol = rectangle
    itself = ndf.energy_error(sol, sol)
    for other in (dataclasses.replace(problem, traction=("d", "c")),
                  dataclasses.replace(problem, g=(0.0, -100.0 + x * (1 - y) * (1 - x)))):  # zero on c (y=1), d (x=0)
        assert ndf.energy_error(sol, ndf.solve(other, sol.mesh)) == pytest.approx(itself, rel=1e-12)


def test_a_side_with_another_role_is_another_problem(rectangle):
    """Dirichlet on b and c against Dirichlet on b: the names in the same order, the roles not (it returned 21.25)."""
    problem, sol = rectangle
    other = dataclasses.replace(problem, dirichlet=("b", "c"), traction="d")
    with pytest.raises(ValueError, match="side 'c' is a dirichlet side there, a traction side for u_h"):
        ndf.energy_error(sol, ndf.solve(other, sol.mesh))


def test_a_numpy_number_is_a_number():
    """AdaptOptions takes numpy's numbers as Python's (stored as Python's), and adapt runs alike."""
    given = ndf.AdaptOptions(theta=np.float32(0.5), max_levels=np.int64(2), tol=np.float64(1e-3), hp=np.True_)
    assert given == ndf.AdaptOptions(theta=0.5, max_levels=2, tol=1e-3)
    assert type(given.theta) is float and type(given.max_levels) is int and type(given.hp) is bool
    problem = ndf.example_6_1()
    runs = [ndf.adapt(problem, method="sipg", order=1, hp=False, theta=theta, max_levels=2, progress=None)
            for theta in (np.float32(0.5), 0.5)]
    assert [r["ndof"] for r in runs[0].levels] == [r["ndof"] for r in runs[1].levels]
    assert [r["eta_h"] for r in runs[0].levels] == [r["eta_h"] for r in runs[1].levels]


@pytest.mark.parametrize("keywords, named", [(dict(max_ndof=10), "max_ndof = 10 is below the first level's 1378"),
                                             (dict(keep=5), "keep must be callable"),
                                             (dict(max_order=10**6), "max_order must be an integer in 1..30"),
                                             (dict(order=31, hp=False), "order must be an integer in 1..30")])
def test_adapt_refuses_before_its_first_solve(keywords, named, monkeypatch):
    def no_solve(*args, **kwargs):
        raise AssertionError("adapt solved before refusing")

    monkeypatch.setattr(ngdgfric.levels, "solve", no_solve)
    with pytest.raises(ValueError, match=named):
        ndf.adapt(ndf.example_6_1(), progress=None, **keywords)


def test_a_poisson_ratio_largest_at_a_vertex_warns_of_locking():
    """nu = 0.3 + 0.19995 x on Example 6.1 reaches 0.49995 at the vertices on x = 1, 0.49702 at the largest of the
    Gauss points of degree 10 that it was sampled at (h = 1/2): LDG P1 locks at 0.49995, not at 0.49702 (the
    results page 'locking'), so it did not warn."""
    problem = dataclasses.replace(ndf.example_6_1(), nu=0.3 + 0.19995 * x)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ndf.Discretization(problem, ndf.uniform_mesh(problem, 0.5), "ldg", 1)
    locking = [str(w.message) for w in caught if issubclass(w.category, ndf.LockingWarning)]
    assert len(locking) == 1 and "nu = 0.49995" in locking[0]


def test_the_target_of_a_level_is_the_eta_h_to_reach():
    """The key ``target`` (documented in Adaptation.levels): the default 1e-3 |||u_h|||_h without tol or rtol, tol
    with it, 0 with rtol = 0 (no target)."""
    problem = ndf.example_6_1()
    runs = [ndf.adapt(problem, method="sipg", order=1, hp=False, max_levels=1, progress=None, **tol)
            for tol in ({}, dict(tol=1e-3), dict(rtol=0))]
    assert runs[0].levels[0]["target"] == pytest.approx(1e-3 * ndf.energy_norm(runs[0].solution), rel=1e-12)
    assert runs[1].levels[0]["target"] == 1e-3 and runs[2].levels[0]["target"] == 0.0
    assert set(runs[0].levels[0]) == {*ndf.adaptivity.FIELDS, "target"}
    assert "``target``" in ndf.Adaptation.__doc__
