"""ngdgfric.dg.methods: the five DG methods and the conforming baseline as data rows, each the form it names, eta's
unit, coercive defaults."""

import csv
import dataclasses
import warnings
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.adaptivity import choose_method
from ngdgfric.dg.methods import METHODS, LockingWarning, PenaltyWarning, check_penalty, get_method

RESULTS = Path(__file__).resolve().parent.parent / "results"


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


@pytest.mark.filterwarnings("ignore::ngdgfric.LockingWarning")  # coercivity, also for methods that lock there
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


@pytest.mark.filterwarnings("ignore::ngdgfric.LockingWarning")  # SIPG P1 locks there; coercive all the same
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


# ---- locking (issue 38): where a method locks, the warning and adapt's choice --------------------------------------

def _nearly_incompressible(nu):
    problem = dataclasses.replace(ndf.example_6_1(), nu=nu)
    return problem, ndf.uniform_mesh(problem, 1 / 4)


def test_cg_p1_warns_where_it_locks_and_names_what_to_use_instead():
    """The user's case: cg P1 at nu = 0.4999 (error 9.8 times its value at nu = 0.3, results/locking.md)."""
    problem, mesh = _nearly_incompressible(0.4999)
    with pytest.warns(LockingWarning, match="cg with elements of degree 1 locks at nu = 0.4999") as caught:
        sol = ndf.solve(problem, mesh, method="cg", order=1)
    message = str(caught[0].message)
    assert "to 2.34 times its value at nu = 0.3 at nu = 0.49 and to 11.3 times at nu = 0.49999" in message
    assert "Use method='bassi', 'brezzi' or 'nipg' (they do not lock up to nu = 0.49999), or order >= 4." in message
    assert caught[0].filename == __file__  # the user's line (errors.warn), not the package's
    assert sol.method == "cg"


@pytest.mark.parametrize("name, order", [("cg", 3), ("sipg", 1), ("sipg", 2), ("ldg", 4)])
def test_every_method_and_order_that_locks_warns(name, order):
    problem, mesh = _nearly_incompressible(0.4999)
    with pytest.warns(LockingWarning, match=f"{name} with elements of degree {order} locks"):
        ndf.Discretization(problem, mesh, name, order=order)


def test_no_locking_warning_where_the_method_does_not_lock():
    """Bassi, Brezzi, NIPG at nu = 0.4999 (any p), cg and SIPG at p = 4, every method at the paper's nu = 0.3; and
    just below the measured thresholds (cg: 0.49, SIPG: 0.497, LDG P2: 0.4997)."""
    quiet = [(name, p, 0.4999) for name in ("bassi", "brezzi", "nipg") for p in (1, 2)]
    quiet += [("cg", 4, 0.49999), ("sipg", 4, 0.49999), ("cg", 1, 0.4899), ("sipg", 3, 0.4969), ("ldg", 2, 0.4996)]
    quiet += [(name, p, 0.3) for name in METHODS for p in (1, 2)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", LockingWarning)
        for name, order, nu in quiet:
            problem, mesh = _nearly_incompressible(nu)
            ndf.Discretization(problem, mesh, name, order=order)


def test_the_locking_warning_sees_the_largest_nu_and_the_lowest_order():
    """nu = 0.4999 on the right half only (a jump along mesh lines); hp orders 1 and 4: the warning is about P1."""
    problem = dataclasses.replace(ndf.example_6_1(), nu=ngs.IfPos(ngs.x - 0.5, 0.4999, 0.3))
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    orders = np.where(np.arange(mesh.ne) % 2 == 0, 1, 4).astype(np.int64)
    with pytest.warns(LockingWarning, match="degree 1 locks at nu = 0.4999"):
        ndf.Discretization(problem, mesh, "cg", order=orders)
    with warnings.catch_warnings():
        warnings.simplefilter("error", LockingWarning)
        ndf.Discretization(problem, mesh, "cg", order=np.full(mesh.ne, 4, dtype=np.int64))
        ndf.Discretization(dataclasses.replace(problem, nu=ngs.IfPos(ngs.x - 0.5, 0.48, 0.3)), mesh, "cg", order=1)


def test_the_locking_warning_is_silenced_by_the_warning_filters():
    problem, mesh = _nearly_incompressible(0.4999)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", LockingWarning)
        ndf.Discretization(problem, mesh, "cg")
    assert not [w for w in caught if issubclass(w.category, LockingWarning)]


@pytest.mark.parametrize("order", [1, 2, 3, 4, 6])
def test_adapt_never_chooses_a_method_that_locks(order):
    """choose_method and the warning read one table (LOCKING): over nu = 0 ... 0.49999 adapt's choice never locks
    at its first degree, and it is cg exactly below cg's lowest threshold (nu = 0.49)."""
    for nu in (0.0, 0.3, 0.45, 0.4899, 0.49, 0.495, 0.4999, 0.49999):
        name, _ = choose_method(dataclasses.replace(ndf.example_6_1(), nu=nu), None, order)
        assert not get_method(name).locks(nu, order), (nu, name)
        assert (name == "cg") == (nu < 0.49), (nu, name)


def test_adapt_with_its_defaults_does_not_warn_near_incompressibility():
    problem = dataclasses.replace(ndf.example_6_1(), nu=0.4999)
    with warnings.catch_warnings():
        warnings.simplefilter("error", LockingWarning)
        run = ndf.adapt(problem, max_levels=1, progress=None)
    assert run.method == "bassi"
    with pytest.warns(LockingWarning, match="cg with elements of degree 1"):
        ndf.adapt(problem, method="cg", order=1, hp=False, max_levels=1, progress=None)


def read_rows(path):
    """The rows of a results CSV, numbers as floats (method names and statuses as text)."""
    def value(text):
        try:
            return float(text)
        except ValueError:
            return text

    with open(path, newline="") as handle:
        return [{key: value(text) for key, text in row.items()} for row in csv.DictReader(handle)]


def test_the_locking_table_is_the_measured_one():
    """LOCKING holds what scripts/locking.py measured (results/locking.csv): each threshold, and the growths there
    and at nu = 0.49999 to their three digits."""
    import locking

    rows = read_rows(RESULTS / "locking.csv")
    largest = max(r["nu"] for r in rows)
    for name, method in METHODS.items():
        for order in (1, 2, 3, 4):
            nu = locking.threshold(rows, name, order)
            entry = method.locking_at(order)
            assert (entry is None) == (nu is None), (name, order)
            if entry is not None:
                assert entry.nu == nu
                assert entry.growth == pytest.approx(locking.growth(rows, name, order, nu)[0], rel=5e-3)
                assert entry.worst == pytest.approx(locking.growth(rows, name, order, largest)[0], rel=5e-3)
