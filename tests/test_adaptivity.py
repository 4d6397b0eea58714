import csv
import dataclasses
import logging
import subprocess
import sys
import time
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.adaptivity import choose_method, minimum_angle
from ngdgfric.levels import out_of_time
from ngdgfric.meshes import refine

ROOT = Path(__file__).resolve().parent.parent


def test_refinement_keeps_labels_and_shape_regularity():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 2)
    angle = minimum_angle(mesh)
    for _ in range(15):  # refine towards the corner (0, 0.05), where Gamma_C meets Gamma_F
        centers = [np.mean([mesh[v].point for v in el.vertices], axis=0) for el in mesh.Elements()]
        marked = np.array([np.hypot(c[0], c[1] - 0.05) < 0.4 for c in centers])
        refine(mesh, marked)
    assert set(mesh.GetBoundaries()) == {"contact", "dirichlet", "traction"}
    assert abs(ngs.Integrate(ngs.CF(1), mesh, definedon=mesh.Boundaries("contact")) - 1) < 1e-12
    assert minimum_angle(mesh) >= angle - 1e-9  # newest vertex bisection: no new angles
    assert mesh.ne > 100


def test_adapt_reduces_eta_and_stops_at_tol(tmp_path):
    p = ndf.example_6_2()
    records = ndf.adapt(p, order=1, hp=False, max_levels=6, csv_path=tmp_path / "levels.csv", progress=None).levels
    assert len(records) == 6
    etas = [r["eta_h"] for r in records]
    assert etas[-1] < etas[0]
    assert all(b["ndof"] > a["ndof"] for a, b in zip(records, records[1:], strict=False))
    # warm starts: u is carried through the refinement, the multiplier through its Gauss values
    assert max(r["iterations"] for r in records[1:]) <= 3
    rows = list(csv.DictReader(open(tmp_path / "levels.csv")))
    assert [int(r["level"]) for r in rows] == list(range(6))
    tol = 0.999 * min(etas[:3])
    first = next(i for i, e in enumerate(etas) if e <= tol)  # the runs are deterministic
    stopped = ndf.adapt(p, order=1, hp=False, max_levels=20, tol=tol, progress=None)
    assert stopped.levels[-1]["eta_h"] <= tol and len(stopped.levels) == first + 1 and stopped.stopped == "tol"


def test_adapt_stops_before_exceeding_max_ndof():
    run = ndf.adapt(ndf.example_6_1(), order=1, hp=False, max_levels=50, max_ndof=2000, progress=None)
    assert run.levels[-1]["ndof"] <= 2000 and run.stopped == "max_ndof"
    assert len(run.levels) < 50


def test_max_ndof_counts_the_conforming_dofs_for_cg():
    run = ndf.adapt(ndf.example_6_2(), method="cg", order=2, hp=False, max_levels=50, max_ndof=3000, progress=None)
    last = run.levels[-1]
    assert last["ndof"] <= 3000 and run.stopped == "max_ndof"
    assert last["elements"] * 12 > 3000  # the DG count of this mesh at p = 2, (p + 1)(p + 2) per element: not the one
    further = ndf.adapt(ndf.example_6_2(), method="cg", order=2, hp=False, max_levels=len(run.levels) + 1,
                        progress=None)
    assert further.levels[-1]["ndof"] > 3000  # the next level would have exceeded the budget


def test_interrupted_run_keeps_finished_levels(tmp_path):
    path = tmp_path / "levels.csv"
    code = ("import ngdgfric as ndf; "
            f"ndf.adapt(ndf.example_6_1(), order=1, hp=False, max_levels=200, max_ndof=10**8, csv_path=r'{path}')")
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=ROOT, stdout=subprocess.DEVNULL)
    try:
        deadline = time.time() + 120
        while time.time() < deadline:
            if path.exists() and len(path.read_text().strip().splitlines()) >= 3:  # header + 2 levels
                break
            time.sleep(0.05)
        proc.kill()
        proc.wait()
    finally:
        if proc.poll() is None:
            proc.kill()
    rows = list(csv.DictReader(open(path)))
    assert len(rows) >= 2
    assert [int(r["level"]) for r in rows[:2]] == [0, 1]
    assert float(rows[1]["eta_h"]) > 0


def test_adapt_returns_the_final_solution_on_its_own_mesh():
    for stop in (dict(max_levels=3), dict(max_ndof=1500), dict(tol=None, max_levels=2)):
        run = ndf.adapt(ndf.example_6_2(), method="sipg", order=1, hp=False, progress=None, **stop)
        last = run.levels[-1]
        # not refined after its solve: the solution lives on the mesh it was solved on
        assert run.solution.ndof == last["ndof"] == run.solution.mesh.ne * 6
        assert run.estimate.eta_h == pytest.approx(last["eta_h"], rel=1e-12)
        assert ndf.estimate(run.solution).eta_h == pytest.approx(last["eta_h"], rel=1e-10)
        assert ndf.kkt_residuals(run.solution)["equilibrium"] < 1e-9
    assert run.stopped == "max_levels"


@pytest.mark.slow
def test_adapt_tol_bounds_the_true_energy_error():
    # eta_h <= tol in energy units: the true error of the returned solution is below tol, and not far below
    from ngdgfric.studies.manufactured import incompressible_contact_manufactured

    problem, u = incompressible_contact_manufactured()
    for tol in (3e-2, 3e-3, 3e-4):  # the first level (p = 4, graded towards the corners) has eta_h = 2.8e-2
        run = ndf.adapt(problem, tol=tol, progress=None)
        error = ndf.energy_norm(run.solution, u)
        assert run.stopped == "tol" and tol / 10 <= error <= tol, (tol, error)


def test_adapt_rejects_bad_budgets():
    for bad in (dict(max_levels=0), dict(max_ndof=-1), dict(variant="none"), dict(max_bytes=0)):
        with pytest.raises(ValueError, match=next(iter(bad))):
            ndf.adapt(ndf.example_6_2(), progress=None, **bad)


def test_adapt_stops_before_a_mesh_above_the_memory_budget(monkeypatch):
    # hp with the default max_ndof = 1e6 reached meshes whose solve check_size refuses (P8: 25 GB)
    from ngdgfric import checks

    problem = ndf.example_6_2()
    first = ndf.adapt(problem, order=2, max_levels=3, progress=None)
    budget = checks.estimated_bytes(first.solution.discretization.orders) * 1.01  # the last level's mesh just fits
    run = ndf.adapt(problem, order=2, max_levels=10, progress=None, max_bytes=budget)
    assert run.stopped == "memory" and len(run.levels) == 3
    assert [r["ndof"] for r in run.levels] == [r["ndof"] for r in first.levels]


@pytest.mark.slow
def test_inexact_levels_solve_the_returned_level_fully():
    """gamma_lin: every level's eta_lin <= gamma_lin eta_h; the returned solution meets the solver's tolerance
    (KKT conditions at round-off) and equals a full solve on its mesh (u; the multiplier is not unique on
    hp meshes, :mod:`ngdgfric.solvers.reduced`)."""
    problem = ndf.example_6_1()
    run = ndf.adapt(problem, max_levels=8, rtol=0, gamma_lin=0.1, progress=None)
    for record in run.levels:
        assert record["eta_lin"] <= 0.1 * record["eta_h"]
    sol = run.solution
    assert sol.state is None and sol.info["converged"]
    full = ndf.solve(problem, sol.mesh, method=run.method, order=sol.discretization.orders)
    a, b = sol.u.vec.FV().NumPy(), full.u.vec.FV().NumPy()
    assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(b))
    kkt = ndf.kkt_residuals(sol)
    assert kkt["lam_excess"] <= 1e-14 and kkt["complementarity"] <= 1e-12
    with pytest.raises(ValueError, match="gamma_lin"):
        ndf.adapt(problem, gamma_lin=1.5, progress=None)


def test_solver_tol_reaches_every_solve_and_finish(monkeypatch):
    """adapt(solver_tol=...) is the tolerance of the solves and of the finishing of inexact levels."""
    seen = []
    from ngdgfric import levels

    for name in ("solve", "finish"):
        original = getattr(levels, name)

        def spy(*args, original=original, name=name, **kwargs):
            seen.append((name, kwargs.get("solver_tol")))
            return original(*args, **kwargs)

        monkeypatch.setattr(levels, name, spy)
    ndf.adapt(ndf.example_6_2(), max_levels=3, gamma_lin=0.1, solver_tol=1e-12, progress=None)
    assert {name for name, _ in seen} == {"solve", "finish"} and {tol for _, tol in seen} == {1e-12}


GUIDE = Path(__file__).resolve().parents[1] / "docs" / "user_guide" / "adaptivity.md"


def guide_loop():
    """The code block under "The paper's loop, by hand" in the user guide's page on adaptivity."""
    section = GUIDE.read_text().split("## The paper's loop, by hand", 1)[1]
    return section.split("```python\n", 1)[1].split("```", 1)[0]


def test_the_hand_written_loop_of_the_guide_runs_and_equals_adapt(capsys):
    # the guide's SOLVE -> ESTIMATE -> MARK -> REFINE loop, as written there, with every Solution kept
    # across the refinements that follow it (it used to crash: "active_dofs size doesn't match FESpace")
    namespace = {}
    exec(compile(guide_loop(), str(GUIDE), "exec"), namespace)
    printed = [line.split() for line in capsys.readouterr().out.splitlines()]
    sol, mesh = namespace["sol"], namespace["mesh"]
    assert len(printed) == 8 and mesh.ne > sol.mesh.ne  # refined after the last solve; sol has its own mesh
    again = ndf.estimate(sol, variant="paper")
    assert again.eta_h == pytest.approx(float(printed[-1][2]), rel=1e-12)
    assert ndf.kkt_residuals(sol)["equilibrium"] < 1e-10
    run = ndf.adapt(ndf.example_6_1(), method="sipg", order=1, hp=False, theta=0.3, variant="paper", max_levels=8,
                    progress=None)
    assert [r["ndof"] for r in run.levels] == [int(row[1]) for row in printed]
    assert [r["eta_h"] for r in run.levels] == pytest.approx([float(row[2]) for row in printed], rel=1e-8)


def test_solutions_kept_by_adapt_stay_valid_after_the_mesh_is_refined():
    kept = []
    ndf.adapt(ndf.example_6_2(), max_levels=4, progress=None, keep=lambda level, sol, est: kept.append((sol, est)))
    for sol, est in kept:
        assert ndf.estimate(sol).eta_h == pytest.approx(est.eta_h, rel=1e-10)
        assert ndf.energy_norm(sol) > 0


def test_adapt_chooses_a_method_that_does_not_lock_and_says_why():
    run = ndf.adapt(dataclasses.replace(ndf.example_6_1(), nu=0.4999), max_levels=1, progress=None)
    assert run.method == "bassi" and "nu reaches 0.4999" in run.method_reason
    assert run.solution.method == "bassi"
    run = ndf.adapt(ndf.example_6_1(), max_levels=1, progress=None)
    assert run.method == "cg" and "nu = 0.4 is moderate" in run.method_reason
    given = ndf.adapt(dataclasses.replace(ndf.example_6_1(), nu=0.4999), method="brezzi", max_levels=1,
                      progress=None)
    assert (given.method, given.method_reason) == ("brezzi", "given")
    # the switch is where cg locks at some degree (ngdgfric.dg.methods.LOCKING, results/locking.md): nu = 0.49
    assert choose_method(dataclasses.replace(ndf.example_6_1(), nu=0.4899), None, 2)[0] == "cg"
    assert choose_method(dataclasses.replace(ndf.example_6_1(), nu=0.49), None, 2)[0] == "bassi"


def test_adapt_stops_before_a_level_that_would_end_after_max_seconds():
    run = ndf.adapt(ndf.example_6_1(), max_seconds=1e-9, progress=None)  # the first level always runs
    assert run.stopped == "max_seconds" and len(run.levels) == 1 and run.solution.state is None
    assert ndf.adapt(ndf.example_6_1(), max_seconds=1e9, max_levels=3, progress=None).stopped == "max_levels"
    with pytest.raises(ValueError, match="max_seconds must be a positive finite number, got -1"):
        ndf.adapt(ndf.example_6_1(), max_seconds=-1)


def test_the_time_limit_predicts_the_next_level_from_the_growth_in_dofs():
    class Sol:
        ndof = 3000

    start = time.perf_counter()
    records = [dict(ndof=1000)]
    # 1 s so far (this level included), this level took 2 s and tripled the DOFs: the next would end at 1 + 6 s
    assert out_of_time(records, Sol, dict(solve=1.5, estimate=0.5), start - 1.0, 6.5)
    assert not out_of_time(records, Sol, dict(solve=1.5, estimate=0.5), start - 1.0, 7.5)
    assert out_of_time([], Sol, dict(solve=1.0), start, 1.5)  # first level: growth 2 assumed, ends near 2 s
    assert not out_of_time(records, Sol, dict(solve=1.0), start, None)


def test_options_that_the_chosen_solver_estimator_or_refinement_would_ignore_are_refused():
    problem = ndf.example_6_2()
    cases = [(dict(solver="uzawa", gamma_lin=0.1), r"gamma_lin=0.1 needs solver='newton'.*solver='uzawa' would ignore"),
             (dict(solver="fixed_point", gamma_lin=0.1), "solver='fixed_point' would ignore it"),
             (dict(estimator="equilibrated", variant="paper"), "estimator='equilibrated' has none and would ignore"),
             (dict(hp=False, max_order=5), "max_order=5 acts in hp refinement only; hp=False would ignore it"),
             (dict(hp=False, layers=2), "layers=2 acts in hp refinement only")]
    for options, message in cases:
        with pytest.raises(ValueError, match=message):
            ndf.adapt(problem, progress=None, **options)


def test_the_old_keyword_weights_still_selects_the_variant_with_a_deprecation_warning():
    paper = ndf.adapt(ndf.example_6_2(), method="sipg", order=1, hp=False, max_levels=1, variant="paper")
    with pytest.warns(DeprecationWarning, match=r"adapt\(weights=...\) is deprecated.*use variant='paper'"):
        old = ndf.adapt(ndf.example_6_2(), method="sipg", order=1, hp=False, max_levels=1, weights="paper")
    assert old.levels[0]["eta_h"] == paper.levels[0]["eta_h"]


def test_progress_goes_to_the_ngdgfric_logger_or_to_a_callable(caplog, capsys):
    options = dict(method="sipg", order=1, hp=False, theta=0.3, max_levels=2)
    ndf.adapt(ndf.example_6_2(), **options)
    assert capsys.readouterr().out == ""  # silent unless logging is configured
    with caplog.at_level(logging.INFO, logger="ngdgfric"):
        ndf.adapt(ndf.example_6_2(), **options)
    logged = [record.getMessage() for record in caplog.records if record.name == "ngdgfric"]
    seen = []
    ndf.adapt(ndf.example_6_2(), progress=seen.append, **options)
    assert len(logged) == len(seen) == 4 and logged[0] == seen[0] == "method sipg: given"
    assert logged[1] == seen[1]
    assert seen[1].startswith("target: eta_h <= rtol |||u_h|||_h with rtol = 0.001, the default")
    assert [line.split(",")[:2] for line in logged] == [line.split(",")[:2] for line in seen]  # times differ
    assert seen[2].startswith("level   0: ") and "eta_h = " in seen[2]


def test_without_tol_or_rtol_adapt_stops_at_the_default_accuracy_and_says_so():
    problem = ndf.example_6_2()
    seen = []
    run = ndf.adapt(problem, progress=seen.append)
    assert ndf.adaptivity.DEFAULT_RTOL == 1e-3
    assert run.stopped == "tol" and "rtol = 0.001, the default" in seen[1]
    norm = ndf.energy_norm(run.solution)
    assert run.estimate.eta_h <= 1e-3 * norm < run.levels[-2]["eta_h"]  # stopped at the first level below, not later
    assert ndf.AdaptOptions().rtol == 1e-3 and ndf.AdaptOptions(tol=1e-2).rtol is None
    assert ndf.AdaptOptions(tol=1e-2, rtol=1e-3).rtol == 1e-3
    # tol alone: no relative target besides it (the default would stop this run at 0.1 % long before tol = 1e-9)
    assert ndf.adapt(problem, tol=1e-9, max_levels=8, progress=None).stopped == "max_levels"
    # rtol = 0: no target, the budgets end the run
    seen = []
    assert ndf.adapt(problem, rtol=0, max_levels=3, progress=seen.append).stopped == "max_levels"
    assert not any(line.startswith("target:") for line in seen)


def test_settings_grouped_or_as_keywords_give_the_same_run():
    problem = ndf.example_6_2()
    keywords = dict(order=1, hp=False, theta=0.3, max_levels=3, max_ndof=5000)
    by_keywords = ndf.adapt(problem, method="sipg", progress=None, **keywords)
    settings = ndf.AdaptOptions(hp=False, theta=0.3, max_levels=3, max_ndof=5000)
    grouped = ndf.adapt(problem, method="sipg", order=1, settings=settings, progress=None)
    assert [r["ndof"] for r in grouped.levels] == [r["ndof"] for r in by_keywords.levels]
    assert [r["eta_h"] for r in grouped.levels] == [r["eta_h"] for r in by_keywords.levels]
    assert grouped.stopped == by_keywords.stopped == "max_levels"


def test_settings_refused_twice_or_of_the_wrong_type_or_out_of_range():
    problem = ndf.example_6_2()
    with pytest.raises(ValueError, match=r"max_levels given as keywords together with settings="):
        ndf.adapt(problem, settings=ndf.AdaptOptions(tol=1e-2), max_levels=3)
    with pytest.raises(ValueError, match=r"rtol, theta given as keywords together with settings="):
        ndf.adapt(problem, None, None, 4, ndf.AdaptOptions(), theta=0.8, rtol=None)  # even at their defaults
    with pytest.raises(ValueError, match=r"settings must be an AdaptOptions or None, got 0.3"):
        ndf.adapt(problem, None, "sipg", 1, 0.3)  # theta where 0.1 took it positionally
    for bad, message in ((dict(theta=1.5), r"theta must be in \(0, 1\], got 1.5"),
                         (dict(hp="yes"), r"hp must be True or False, got 'yes'"),
                         (dict(max_order=0), r"max_order must be an integer in 1..30 .* or None, got 0"),
                         (dict(tol=-1.0), r"tol must be a finite number >= 0, got -1.0"),
                         (dict(rtol=float("inf")), r"rtol must be a finite number >= 0, got inf"),
                         (dict(max_seconds=float("nan")), r"max_seconds must be a positive finite number, got nan"),
                         (dict(hp=False, layers=1), r"layers=1 acts in hp refinement only")):
        with pytest.raises(ValueError, match=message):
            ndf.AdaptOptions(**bad)
        with pytest.raises(ValueError, match=message):
            ndf.adapt(problem, progress=None, **bad)
    with pytest.raises(ValueError, match=r"order must be an integer in 1..30, got 0"):
        ndf.adapt(problem, order=0)


def test_theta_one_without_a_tolerance():
    """theta = 1 and no tolerance: the landing rule kept theta = 1, expected eta_h = 0 of the next level and
    divided by it."""
    problem = ndf.example_6_2()
    run = ndf.adapt(problem, ndf.uniform_mesh(problem, 0.5), order=1, hp=False, theta=1.0, max_levels=3,
                    progress=None)
    assert run.stopped == "max_levels" and len(run.levels) == 3
