"""ngdgfric.studies.cases: the energy Gram matrix is |||.|||_h, coercivity thresholds protect the user
(measured by scripts/stability.py), the study cases measure what they say."""

import dataclasses
import math
import warnings

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.dg.methods import PenaltyWarning, get_method
from ngdgfric.reference import energy_norm_squared_parts
from ngdgfric.studies.cases import (
    coercivity,
    compliance_case,
    energy_gram,
    locking_case,
    penalty_threshold,
    penalty_value,
)


@pytest.mark.parametrize("order", [1, 3])
def test_energy_gram_gives_the_energy_norm_of_random_functions(order):
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    gram = energy_gram(problem, mesh, order)
    w = ngs.GridFunction(ndf.Discretization(problem, mesh, order=order).V)
    rng = np.random.default_rng(order)
    for _ in range(3):
        x = rng.standard_normal(w.space.ndof)
        w.vec.FV().NumPy()[:] = x
        assert x @ gram @ x == pytest.approx(sum(energy_norm_squared_parts(problem, mesh, w)), rel=1e-10)


@pytest.mark.slow
@pytest.mark.parametrize("order", [1, 2, 3])
def test_sipg_threshold_table_separates_coercive_from_not(order):
    for problem in (ndf.example_6_1(), ndf.example_6_2()):
        mesh = ndf.uniform_mesh(problem, 1 / 4)
        threshold = get_method("sipg").threshold(problem, order)
        gram = energy_gram(problem, mesh, order)
        assert coercivity(problem, mesh, "sipg", order, threshold, gram) > 0
        assert coercivity(problem, mesh, "sipg", order, 0.5 * threshold, gram) < 0


def test_sipg_far_below_threshold_warns_or_raises_and_default_does_not():
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    with pytest.warns(PenaltyWarning, match="coercivity threshold"):
        ndf.Discretization(problem, mesh, "sipg", eta=problem.mu)
    with pytest.raises(ValueError, match="coercivity threshold"):
        ndf.Discretization(problem, mesh, "sipg", eta=problem.mu, penalty_check="raise")
    with warnings.catch_warnings():
        warnings.simplefilter("error", PenaltyWarning)
        for material in (problem, dataclasses.replace(problem, nu=0.49)):  # 30 mu, raised where it is too low
            disc = ndf.Discretization(material, mesh, "sipg")
            assert coercivity(material, mesh, "sipg", 1, disc.eta) > 0


@pytest.mark.slow
def test_methods_without_threshold_are_coercive_for_small_eta():
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    for method in ("nipg", "brezzi", "ldg"):
        assert penalty_threshold(problem, mesh, method, 1) == 1e-2
    # Bassi et al.: below the sufficient eta > 3 of the theory, above 0; eta is dimensionless (no mu)
    assert 1e-2 < penalty_threshold(problem, mesh, "bassi", 1) < 3
    assert penalty_value(problem, "bassi", 2.0) == 2.0 and penalty_value(problem, "sipg", 2.0) == 2 * problem.mu


@pytest.mark.parametrize("order", [1, 2])
def test_locking_case_error_converges_at_rate_p_for_a_compressible_material(order):
    errors = [locking_case(dict(method="sipg", order=order, nu=0.3, h=h))["relative_error"] for h in (1 / 4, 1 / 8)]
    assert math.log2(errors[0] / errors[1]) == pytest.approx(order, abs=0.1)


def test_compliance_case_condition_number_is_the_same_whether_the_solve_converged_or_not():
    solved = compliance_case(dict(example="6.1", c_n=1e4, solver="newton", h=0.25))
    failed = compliance_case(dict(example="6.1", c_n=1e4, solver="uzawa", h=0.25, maxit=3))
    assert solved["status"] == "converged" and failed["status"].startswith("failed")
    assert failed["condition"] == pytest.approx(solved["condition"], rel=1e-12)
    assert solved["lam_excess"] == 0 and solved["complementarity"] <= 1e-12 and "iterations" not in failed
