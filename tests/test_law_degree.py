"""The contact Gauss rule follows the degree of the elements along Gamma_C; with friction adapt gives them one
degree."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact.boundary import contact_elements, normal_tangent
from ngdgfric.meshes import refine, snapshot


def _dense(matrix):
    """An NGSolve sparse matrix as a dense numpy array."""
    values, columns, starts = matrix.CSR()
    dense = np.zeros((matrix.height, matrix.width))
    rows = np.repeat(np.arange(matrix.height), np.diff(np.asarray(starts, dtype=np.int64)))
    np.add.at(dense, (rows, np.asarray(columns, dtype=np.int64)), np.asarray(values))
    return dense


def test_the_rule_is_exact_for_the_degree_of_the_contact_elements():
    """Degree 3 inside, 2 on the elements along Gamma_C: the rule has 3 points per edge (not 4).  With every point
    penetrating (g_a = -1) and no friction the compliance law is the Robin condition c_n (u_n - g_a) on Gamma_C, so the
    contact solution must equal the linear solve with that term integrated by NGSolve's own (exact) rule: measured
    1.7e-13 relative (tested at 1e-12)."""
    problem = dataclasses.replace(ndf.example_6_2(), g_a=-1.0, c_tau=0.0)
    mesh = ndf.uniform_mesh(problem, 0.25)
    orders = np.full(mesh.ne, 3)
    orders[contact_elements(problem, mesh)] = 2
    sol = ndf.solve(problem, mesh, method="sipg", order=orders)
    assert sol.contact.gauss.q == 3
    assert sol.info["penetrating"] == sol.contact.traces.M
    disc = sol.discretization
    u, v = disc.V.TnT()
    n = normal_tangent()[0]
    on_contact = ngs.ds(skeleton=True, definedon=sol.mesh.Boundaries(problem.where("contact")))
    robin = ngs.BilinearForm(disc.V)
    robin += problem.c_n * (u * n) * (v * n) * on_contact
    robin.Assemble()
    gap = ngs.LinearForm(disc.V)
    gap += problem.c_n * problem.g_a * (v * n) * on_contact
    gap.Assemble()
    expected = np.linalg.solve(_dense(disc.A) + _dense(robin.mat), disc.F.FV().NumPy() + gap.vec.FV().NumPy())
    got = sol.u.vec.FV().NumPy()
    assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))


@pytest.fixture(scope="module")
def hp_run():
    """Example 6.1 hp-adaptive (SIPG from p = 2), each level's solution kept."""
    kept = []
    run = ndf.adapt(ndf.example_6_1(), method="sipg", order=2, max_levels=8, rtol=0, progress=None,
                    keep=lambda number, sol, est: kept.append(sol))
    return run, kept


def test_adapt_gives_the_contact_elements_one_degree(hp_run):
    """Every level: one degree along Gamma_C, the rule of that degree, no redundant points, while the degrees
    elsewhere vary (measured p 2..4 at the last level)."""
    run, kept = hp_run
    assert run.levels[-1]["p_max"] > run.levels[-1]["p_min"]
    for sol in kept:
        degrees = np.unique(sol.discretization.orders[contact_elements(sol.problem, sol.mesh)])
        assert degrees.size == 1
        assert sol.contact.gauss.q == degrees[0] + 1
        assert not sol.contact.traces.redundant


def test_newton_needs_few_iterations_per_warm_started_level(hp_run):
    """The issue's target of 8 semismooth Newton iterations per warm-started level (measured at most 4 here; the
    rubber pad to rtol = 1e-5 at most 6: results/newton_levels.md)."""
    run, _ = hp_run
    assert max(level["iterations"] for level in run.levels[1:]) <= 8


def test_a_mesh_refined_before_gives_the_same_warm_starts():
    """adapt on a mesh with a refinement history and on a copy of it without one (the same elements): the warm starts
    are exact on both (NGSolve prolongates a space created on a mesh with a history wrongly, so the loop interpolates
    there instead), so every level changes the same points in the same number of iterations."""
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 0.5)
    refine(mesh, np.arange(mesh.ne) == 0, bisections=2)
    fresh = snapshot(mesh)
    assert (mesh.levels, fresh.levels) == (2, 1)
    assert ndf.adaptivity.initial_mesh(problem, layers=2).levels == 1  # adapt's own first mesh: the fast path
    runs = [ndf.adapt(problem, start, method="sipg", order=2, max_levels=5, progress=None) for start in (mesh, fresh)]
    for key in ("changed_points", "iterations", "ndof"):
        assert [level[key] for level in runs[0].levels] == [level[key] for level in runs[1].levels]
