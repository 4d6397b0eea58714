"""ngdgfric.dg.methods: the five DG methods and the conforming baseline as data rows, each the form it names, eta's
unit, coercive defaults."""

import dataclasses
import warnings

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.dg.methods import METHODS, PenaltyWarning, check_penalty, get_method


@pytest.fixture(scope="module")
def matrices():
    """name -> the dense matrix B_h of each method (default eta, P1) on Example 6.2, h = 1/4."""
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    return {name: np.array(ndf.Discretization(problem, mesh, name).A.ToDense()) for name in METHODS}


@pytest.mark.parametrize("name", sorted(METHODS))
def test_each_row_of_the_table_is_the_form_it_names(name, matrices):
    """The row's symmetry sign gives a symmetric B_h (+1) or one whose consistency terms are antisymmetric (-1,
    NIPG); a conforming method has continuous unknowns: fewer than the DG methods' own unknowns per element."""
    method, A = get_method(name), matrices[name]
    asymmetry = np.abs(A - A.T).max() / np.abs(A).max()
    assert (asymmetry < 1e-12) == (method.symmetry == 1), asymmetry
    assert (A.shape[0] < matrices["sipg"].shape[0]) == method.conforming


def test_method_names_are_case_insensitive_and_unknown_ones_are_named():
    assert get_method("LDG") is METHODS["ldg"]
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
@pytest.mark.parametrize("order", [1, 2])
def test_the_default_penalty_is_coercive(nu, order):
    """Every method's default eta gives a positive definite B_h (the symmetric part of its linear part),
    also where the material nearly locks and the default is raised above 30 mu."""
    problem = dataclasses.replace(ndf.example_6_2(), nu=nu)
    mesh = ndf.uniform_mesh(problem, 1 / 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PenaltyWarning)
        for name in METHODS:
            A = np.array(ndf.Discretization(problem, mesh, name, order=order).A.ToDense())
            eigenvalues = np.linalg.eigvalsh(0.5 * (A + A.T))
            assert eigenvalues[0] > 1e-10 * eigenvalues[-1], (name, eigenvalues[0], eigenvalues[-1])


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
