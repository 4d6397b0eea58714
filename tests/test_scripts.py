"""Every script runs in its --quick form and writes what it promises (into a temporary folder)."""

import importlib

import numpy as np
import pytest


def run(name, tmp_path, *args):
    module = importlib.import_module(name)
    return module.main(["--quick", "--out", str(tmp_path), *args])


def test_uniform_convergence(tmp_path):
    results = run("uniform_convergence", tmp_path, "--example", "6.1", "--method", "sipg")
    rows = results["sipg"]
    assert [r["k"] for r in rows] == [1, 2]
    assert rows[0]["paper_error"] == pytest.approx(4.7518e-1)
    # ours/paper compares the true relative error (against the hp reference) with the paper's number
    assert 0.3 < rows[0]["true_relative"] < 1
    assert rows[0]["ratio"] == pytest.approx(rows[0]["true_relative"] / 4.7518e-1)
    text = (tmp_path / "table_6_1.md").read_text()
    assert "ours/paper" in text and "Regenerate" in text
    assert (tmp_path / "table_6_1.csv").exists()


def test_adaptive(tmp_path):
    rows = run("adaptive", tmp_path, "--example", "6.2", "--method", "sipg")
    assert rows[0]["levels"] == 6
    for name in ("figure_6_3.png", "figure_6_4.png", "adaptive_6_2_sipg.csv", "uniform_6_2_sipg.csv",
                 "adaptivity_6_2.md"):
        assert (tmp_path / name).stat().st_size > 0


def test_table_variants(tmp_path):
    rows = run("table_variants", tmp_path)
    assert {r["example"] for r in rows} == {"6.1", "6.2"}
    assert {"consecutive", "hp reference"} <= {r["comparison"] for r in rows}
    assert "Findings" in (tmp_path / "table_investigation.md").read_text()


def test_bench_solvers(tmp_path):
    rows = run("bench_solvers", tmp_path)
    assert {r["example"] for r in rows} == {"6.1", "6.2"}
    warm = [r for r in rows if "warm" in r]
    assert warm and all(r["warm_difference"] <= 1e-10 for r in warm)  # warm and cold starts: one solution
    assert all(r["cold_its"] <= 10 for r in rows)
    text = (tmp_path / "solver_benchmark.md").read_text()
    assert "contact / linear" in text and (tmp_path / "solver_benchmark.png").exists()


def test_bench_linear_solvers(tmp_path):
    rows = run("bench_linear_solvers", tmp_path)
    assert {r["symmetric"] for r in rows} == {True, False}
    assert any(r["schur"] for r in rows)  # W one way or the other
    assert "What each needs" in (tmp_path / "linear_solvers.md").read_text()


def test_bench_assembly(tmp_path):
    run("bench_assembly", tmp_path)
    text = (tmp_path / "assembly_benchmark.md").read_text()
    assert all(method in text for method in ("sipg", "nipg", "bassi", "brezzi", "ldg"))


def test_reference_and_hp(tmp_path):
    run("reference", tmp_path, "--example", "6.2")
    assert (tmp_path / "reference_6_2.npz").exists() and "estimated error" in (tmp_path / "reference.md").read_text()
    run("hp", tmp_path, "--example", "6.2", "--reference", str(tmp_path))
    for name in ("hp_6_2.csv", "hp_6_2.png", "hp_exponential_6_2.png", "hp_mesh_6_2.png", "hp.md"):
        assert (tmp_path / name).stat().st_size > 0
    assert "times fewer" in (tmp_path / "hp.md").read_text()


def test_stability(tmp_path):
    results = run("stability", tmp_path, "--cache", str(tmp_path / "cache"))
    assert set(results) == {"threshold", "penalty", "locking", "compliance", "friction", "rho"}
    sipg = [r for r in results["threshold"] if r["method"] == "sipg"]
    assert all(1 < r["threshold_2mu_lam"] < 4.0 for r in sipg)  # below ngdgfric.dg.methods.SIPG_THRESHOLD[1]
    assert (tmp_path / "stability.png").exists() and "Uzawa's step rho" in (tmp_path / "stability.md").read_text()


def test_work_precision(tmp_path):
    run("work_precision", tmp_path, "--example", "6.2", "--cache", str(tmp_path / "cache"))
    assert "fastest run" in (tmp_path / "work_precision.md").read_text()
    for name in ("work_precision_6_2.png", "work_precision_6_2_dofs.png", "work_precision_6_2.csv"):
        assert (tmp_path / name).stat().st_size > 0


def test_effectivity(tmp_path):
    rows = run("effectivity", tmp_path, "--workers", "1")
    assert {r["family"] for r in rows} == {"divergence-free", "6.2"}
    assert all(1 < r["effectivity"] < 10 for r in rows)
    assert "max/min" in (tmp_path / "effectivity.md").read_text() and (tmp_path / "effectivity.png").exists()


def test_tolerance(tmp_path):
    rows = run("tolerance", tmp_path)
    assert rows[0]["stopped"] == "tol" and rows[0]["error"] <= rows[0]["tol"]
    assert "true error / t" in (tmp_path / "tolerance.md").read_text()


def test_time_to_accuracy(tmp_path):
    rows, stops = run("time_to_accuracy", tmp_path)
    assert {r["run"] for r in rows} == {"adapt", "baseline P3", "sipg"} and {r["target"] for r in rows} == {0.1, 0.01}
    for row in rows:  # each run at its first level below the target, measured against the hp reference
        assert row["error"] <= row["target"] and row["seconds"] > 0
    (stop,) = stops
    assert stop["stopped"] == "tol" and stop["error"] <= stop["eta_h"] <= 5e-4 and stop["method"] == "cg"
    assert stop["ratio"] == pytest.approx(stop["loop_seconds"] / stop["linear_seconds"])
    for name in ("time_to_accuracy.csv", "time_to_accuracy_stops.csv", "time_to_accuracy.md", "time_to_accuracy.png"):
        assert (tmp_path / name).stat().st_size > 0


def test_scenes(tmp_path):
    # three scenes, two methods, P1, two meshes, coarse references: the exact solution across an aligned jump
    # is reproduced, the cut jump converges, the L-shape is measured against its hp reference, adapt reaches tol
    rows, adapts = run("scenes", tmp_path, "--workers", "1", "--scene", "layers-indented", "layers-cut", "l-shape")
    assert all(r["status"] == "solved" for r in rows) and len(rows) == 3 * 2 * 2
    assert all(r["relative"] <= 1e-10 for r in rows if r["scene"] == "layers-indented")
    cut = [r["error"] for r in rows if r["scene"] == "layers-cut" and r["method"] == "sipg"]
    assert 0.4 < np.log(cut[0] / cut[1]) / np.log(4) < 0.8  # h^(1/2): h = 1/2 -> 1/8
    assert all(r["equilibrium"] <= 10 * max(r["rounding"], 1e-14) for r in rows)
    shape = [a for a in adapts if a["scene"] == "l-shape"][0]
    assert shape["stopped"] == "tol" and shape["error"] <= shape["tol"]
    text = (tmp_path / "scenes.md").read_text()
    assert "12 solves, 0 failures" in text and "| exact |" in text and "Regenerate" in text


def test_hertz(tmp_path):
    results = run("hertz", tmp_path)
    reference = results["reference"]
    assert abs(reference["rel_a"]) < 0.03 and abs(reference["rel_p0"]) < 0.03  # a coarse hp run is Hertzian
    assert [r["vary"] for r in results["sweeps"]] == ["delta", "c_n"]
    assert results["levels"][-1]["error_J"] == 0.0 and results["levels"][0]["error_J"] > 0
    text = (tmp_path / "hertz.md").read_text()
    assert "within 1 % of Hertz" in text and "Regenerate" in text and "Polygon with 16 sides" in text
    for name in ("hertz.csv", "hertz.png"):
        assert (tmp_path / name).stat().st_size > 0


def test_curved_rates(tmp_path):
    table = run("curved_rates", tmp_path)
    assert {r["geometry"] for r in table} == {"annulus, curved", "annulus, straight edges", "square"}
    assert all(r["status"] == "solved" for r in table)
    assert all(abs(r["rate"] - r["p"]) < 0.3 for r in table if r["geometry"] == "annulus, curved")  # three meshes
    text = (tmp_path / "curved.md").read_text()
    assert "where the order goes" in text and "Regenerate" in text
    assert (tmp_path / "curved.csv").stat().st_size > 0
