"""ngdgfric.dg.methods: the five DG methods and the conforming baseline as data rows, eta's unit, defaults above the
coercivity thresholds."""

import dataclasses
import warnings

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.dg.methods import METHODS, PenaltyWarning, check_penalty, get_method


def test_method_table_shows_one_construction():
    rows = {name: (m.symmetry, m.penalty, m.global_lift, m.conforming) for name, m in ndf.METHODS.items()}
    assert rows == {"sipg": (1, "edge", False, False), "nipg": (-1, "edge", False, False),
                    "bassi": (1, "lift", False, False), "brezzi": (1, "lift", True, False),
                    "ldg": (1, "edge", True, False), "cg": (1, "edge", False, True)}
    assert get_method("LDG").name == "ldg"
    with pytest.raises(ValueError, match="ipdg"):
        get_method("ipdg")


@pytest.mark.parametrize("name", sorted(METHODS))
def test_eta_is_a_stress_for_edge_penalties_and_a_number_for_liftings(name):
    """Scaling E by 1000 scales the default eta by 1000 for the edge penalties (eta p^2/h_e [u]:[v] must
    scale like the stress) and leaves the liftings' dimensionless eta alone; Section 6's 30 mu is kept."""
    method, problem = get_method(name), ndf.example_6_1()
    scaled = dataclasses.replace(problem, E=1000 * problem.E)
    ratio = method.default(scaled, 1) / method.default(problem, 1)
    assert ratio == pytest.approx(1000.0 if method.penalty == "edge" else 1.0, rel=1e-14)
    if method.penalty == "edge":
        assert method.default(problem, 1) == 30 * problem.mu


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.49, 0.4999])
@pytest.mark.parametrize("order", [1, 2, 5])
def test_defaults_pass_their_own_coercivity_check(nu, order):
    problem = dataclasses.replace(ndf.example_6_2(), nu=nu)
    for method in METHODS.values():
        threshold = method.threshold(problem, order)
        eta = method.default(problem, order)
        check_penalty(problem, method, eta, order, "raise")
        if threshold is not None:
            assert eta > threshold


def test_default_sipg_matrix_is_positive_definite_near_incompressibility():
    """nu = 0.4999: 30 mu is far below the threshold; the raised default gives an SPD B_h."""
    problem = dataclasses.replace(ndf.example_6_2(), nu=0.4999)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PenaltyWarning)
        disc = ndf.Discretization(problem, ndf.uniform_mesh(problem, 1 / 4), "sipg")
    assert disc.eta == 1.5 * get_method("sipg").threshold(problem, 1) > 30 * problem.mu
    A = np.array(disc.A.ToDense())
    assert np.linalg.eigvalsh(0.5 * (A + A.T)).min() > 0


def test_check_penalty_actions():
    problem, method = ndf.example_6_1(), get_method("bassi")
    with pytest.warns(PenaltyWarning, match="threshold 3"):
        check_penalty(problem, method, 3.0, 1)
    with pytest.raises(ValueError, match="threshold 3"):
        check_penalty(problem, method, 2.0, 1, "raise")
    check_penalty(problem, method, 2.0, 1, "ignore")
    check_penalty(problem, get_method("brezzi"), 1e-9, 1, "raise")  # any eta > 0
    with pytest.raises(ValueError, match="penalty_check"):
        check_penalty(problem, method, 6.0, 1, "loud")
