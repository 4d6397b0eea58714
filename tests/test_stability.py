"""Coercivity thresholds (measured by scripts/stability.py) protect the user; study cases run."""

import dataclasses
import warnings

import pytest

import ngdgfric as ndf
from ngdgfric.forms import SIPG_THRESHOLD, PenaltyWarning, coercivity_threshold, get_method
from ngdgfric.studies.cases import coercivity, penalty_threshold, rho_case
from ngdgfric.studies.runner import run_cases


@pytest.mark.parametrize("order", [1, 2, 3])
def test_sipg_threshold_table_separates_coercive_from_not(order):
    for problem in (ndf.example_6_1(), ndf.example_6_2()):
        mesh = ndf.uniform_mesh(problem, 1 / 4)
        threshold = coercivity_threshold(problem, get_method("sipg"), order)
        assert coercivity(problem, mesh, "sipg", order, threshold) > 0
        assert coercivity(problem, mesh, "sipg", order, 0.5 * threshold) < 0


def test_sipg_far_below_threshold_warns_or_raises_and_default_does_not():
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    with pytest.warns(PenaltyWarning, match="coercivity threshold"):
        ndf.Discretization(problem, mesh, "sipg", eta=problem.mu)
    with pytest.raises(ValueError, match="coercivity threshold"):
        ndf.Discretization(problem, mesh, "sipg", eta=problem.mu, penalty_check="raise")
    with warnings.catch_warnings():
        warnings.simplefilter("error", PenaltyWarning)
        assert ndf.Discretization(problem, mesh, "sipg").eta == pytest.approx(30 * problem.mu)
        nearly_incompressible = dataclasses.replace(problem, nu=0.49)
        disc = ndf.Discretization(nearly_incompressible, mesh, "sipg")
        assert disc.eta == pytest.approx(1.5 * SIPG_THRESHOLD[1] * (2 * disc.problem.mu + disc.problem.lam))
        assert coercivity(nearly_incompressible, mesh, "sipg", 1, disc.eta) > 0


def test_methods_without_threshold_are_coercive_for_small_eta():
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    for method in ("nipg", "brezzi", "ldg"):
        assert penalty_threshold(problem, mesh, method, 1) == 1e-2


def test_runner_caches_results_and_uzawa_divergence_names_rho(tmp_path):
    cases = [dict(example="6.1", factor=f, h=0.25, maxit=400) for f in (1.0, 4.0)]
    first = run_cases(rho_case, cases, cache=tmp_path, workers=2, progress=None)
    assert first[0]["status"] == "converged" and "rho" in first[1]["status"]
    assert len(list(tmp_path.glob("*.json"))) == 2
    again = run_cases(rho_case, cases, cache=tmp_path, workers=2, progress=None)  # from the cache: no cluster
    assert again == first
