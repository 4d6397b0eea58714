"""The full-space contact solver (ngdgfric.solvers.fullspace) against the condensed one: the same discrete problem
solved another way, so the solutions must agree to the solvers' round-off."""

import dataclasses

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.solvers import fullspace
from ngdgfric.solvers.newton import NewtonOptions, newton

pytestmark = pytest.mark.skipif(not ndf.solvers.pardiso.available(), reason="needs MKL PARDISO")


def both(problem, mesh, method, order, **options):
    condensed = ndf.solve(problem, mesh, method=method, order=order, formulation="condensed", **options)
    full = ndf.solve(problem, mesh, method=method, order=order, formulation="full-space", **options)
    return condensed, full


def agreement(condensed, full):
    """(relative energy difference of u, largest difference of lam_tau)."""
    energy = ndf.energy_norm(condensed, full.u) / ndf.energy_norm(condensed)
    lam = np.max(np.abs(condensed.lam_tau.vec.FV().NumPy() - full.lam_tau.vec.FV().NumPy()))
    return energy, lam


@pytest.mark.parametrize("name", ["6.1", "6.2"])
@pytest.mark.parametrize("method, order, h", [("sipg", 1, 1 / 8), ("sipg", 3, 1 / 8), ("cg", 4, 1 / 16),
                                              ("bassi", 2, 1 / 16), ("ldg", 2, 1 / 8), ("brezzi", 2, 1 / 8)])
def test_full_space_and_condensed_solutions_agree(name, method, order, h):
    """Measured (2026-11-27): energy differences 5e-14 ... 2.6e-12 of |||u_h|||, lam_tau 4.2e-10 at most (cg P4 on
    6.1, sticking points); tested at 1e-11 and 1e-8.  6.1 at P3 cycled with r = 1 / d_q before R_FACTOR."""
    problem = ndf.example(name)
    condensed, full = both(problem, ndf.uniform_mesh(problem, h), method, order)
    energy, lam = agreement(condensed, full)
    assert energy <= 1e-11
    assert lam <= 1e-8
    assert full.info["linear_solver"] == "pardiso (full space)"
    assert (full.info["penetrating"], full.info["stick"]) == (condensed.info["penetrating"], condensed.info["stick"])
    assert all(value <= 1e-10 for value in ndf.kkt_residuals(full).values())


def test_hp_level_with_redundant_points_agrees():
    """An hp level of adapt (p = 4 ... 6) with every other element on Gamma_C one degree lower (adapt gives them one
    degree, so that its Gauss points are not redundant): elements of p_T < p on Gamma_C, dependent rows of B, the
    sticking rows regularised by STICK_REGULARIZATION.  Measured on Example 6.2 (tol 3e-3): energy difference
    1.7e-11, KKT residuals as the condensed solver's (2.3e-11 and 2.2e-11), and one multiplier (difference 0: both
    end with the least-norm forces of ngdgfric.solvers.selection; before it they differed)."""
    problem = ndf.example_6_2()
    sol = ndf.adapt(problem, method="sipg", tol=3e-3, progress=None).solution
    orders = sol.discretization.orders.copy()
    orders[ndf.contact.boundary.contact_elements(problem, sol.mesh)[::2]] -= 1
    condensed, full = both(problem, sol.mesh, "sipg", orders)
    assert condensed.contact.traces.redundant
    energy, lam = agreement(condensed, full)
    assert energy <= 5e-11
    assert lam <= 1e-10
    assert ndf.kkt_residuals(full)["equilibrium"] <= 1e-10


@pytest.mark.parametrize("change", [dict(c_n=1e8), dict(m_n=2.0, c_n=1e6), dict(g_a=-1e-3, g=(0.0, 0.0)),
                                    dict(c_tau=0.0)])
def test_stiff_nonlinear_and_penetration_only_laws_agree(change):
    """Stiff compliance (C = 1 / N' tiny), m_n = 2 (N' changes every step), a body loaded by penetration only,
    no friction."""
    problem = dataclasses.replace(ndf.example_6_2(), **change)
    condensed, full = both(problem, ndf.uniform_mesh(problem, 1 / 8), "sipg", 2)
    energy, lam = agreement(condensed, full)
    assert energy <= 1e-9
    assert full.info["converged"]


def test_warm_start_reaches_the_same_solution_in_fewer_iterations():
    problem = ndf.example_6_1()
    coarse = ndf.solve(problem, ndf.uniform_mesh(problem, 1 / 8), method="sipg", order=2, formulation="full-space")
    mesh = ndf.uniform_mesh(problem, 1 / 16)
    cold = ndf.solve(problem, mesh, method="sipg", order=2, formulation="full-space")
    warm = ndf.solve(problem, mesh, method="sipg", order=2, formulation="full-space", initial=coarse)
    assert ndf.energy_norm(cold, warm.u) <= 1e-11 * ndf.energy_norm(cold)
    assert warm.iterations < cold.iterations


def test_auto_takes_the_full_space_from_the_threshold():
    """A long side with FULL_SPACE_POINTS points (conforming P1: one point per edge) goes to the full space, a short
    one stays condensed."""
    problem = dataclasses.replace(ndf.example_6_2(), geometry=ndf.Polygon(
        ((0, 0), (8, 0), (8, 1 / 8), (0, 1 / 8)), ("contact", "traction", "dirichlet", "traction")),
        g=(0.0, 0.0), u_D=(0.002, -0.001), c_n=1e4, c_tau=25.0)
    long = ndf.solve(problem, ndf.meshes.grid_mesh(problem, 8 / fullspace.FULL_SPACE_POINTS), method="cg", order=1)
    assert long.info["contact_points"] == fullspace.FULL_SPACE_POINTS
    assert long.info["linear_solver"] == "pardiso (full space)"
    short = ndf.solve(problem, ndf.meshes.grid_mesh(problem, 1 / 8), method="cg", order=1)
    assert short.info["linear_solver"] == "pardiso"
    condensed = ndf.solve(problem, long.mesh, method="cg", order=1, formulation="condensed")
    assert ndf.energy_norm(condensed, long.u) <= 1e-11 * ndf.energy_norm(condensed)


@pytest.mark.parametrize("case, words", [
    (dict(method="nipg"), "symmetric"),
    (dict(problem=dict(m_t=1.0)), "m_t = 0"),
    (dict(energy_tol=1e-3), "energy_tol"),
    (dict(linear_solver="ngsolve"), "PARDISO"),
])
def test_full_space_where_it_does_not_apply_is_refused(case, words):
    problem = dataclasses.replace(ndf.example_6_2(), **case.get("problem", {}))
    options = {key: value for key, value in case.items() if key not in ("method", "problem")}
    with pytest.raises(ValueError, match=words):
        ndf.solve(problem, ndf.uniform_mesh(problem, 1 / 4), method=case.get("method", "sipg"), order=1,
                  formulation="full-space", **options)


def test_no_convergence_within_maxit_raises_with_the_residuals():
    problem = ndf.example_6_1()
    disc = ndf.Discretization(problem, ndf.uniform_mesh(problem, 1 / 8), method="sipg", order=3)
    contact = ndf.Contact(disc)
    with pytest.raises(ndf.SolverError, match="no convergence in 2 iterations"):
        newton(disc, contact, NewtonOptions(formulation="full-space", maxit=2))


def test_progress_reports_each_iteration():
    lines = []
    problem = ndf.example_6_2()
    ndf.solve(problem, ndf.uniform_mesh(problem, 1 / 4), method="sipg", order=1, formulation="full-space",
              progress=lines.append)
    assert lines and all(line.startswith("full-space newton") for line in lines)


def test_auto_falls_back_to_the_condensed_solver_when_the_full_space_fails(monkeypatch):
    """"auto" above the threshold: a failed full-space iteration is taken over by the condensed solver, and says so."""
    monkeypatch.setattr(ndf.solvers.newton, "FULL_SPACE_POINTS", 1)
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 8)
    reference = ndf.solve(problem, mesh, method="sipg", order=3, formulation="condensed")
    sol = ndf.solve(problem, mesh, method="sipg", order=3, maxit=100)
    assert sol.info["linear_solver"] == "pardiso (full space)" and "fallback" not in sol.info

    def failing(*args, **kwargs):
        raise ndf.SolverError("no convergence (forced)", solver="newton")

    monkeypatch.setattr(fullspace.FullSpaceState, "run", failing)
    sol = ndf.solve(problem, mesh, method="sipg", order=3)
    assert sol.info["linear_solver"] == "pardiso" and "forced" in sol.info["fallback"]
    assert ndf.energy_norm(reference, sol.u) <= 1e-12 * ndf.energy_norm(reference)
    with pytest.raises(ndf.SolverError, match="forced"):
        ndf.solve(problem, mesh, method="sipg", order=3, formulation="full-space")
