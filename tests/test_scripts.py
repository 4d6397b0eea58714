"""Every script runs in its --quick form and writes what it promises (into a temporary folder)."""

import importlib

import pytest


def run(name, tmp_path, *args):
    module = importlib.import_module(name)
    return module.main(["--quick", "--out", str(tmp_path), *args])


def test_uniform_convergence(tmp_path):
    results = run("uniform_convergence", tmp_path, "--example", "6.1", "--method", "sipg")
    rows = results["sipg"]
    assert [r["k"] for r in rows] == [1, 2]
    assert rows[0]["paper_error"] == pytest.approx(4.7518e-1)
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
    assert "Findings" in (tmp_path / "table_investigation.md").read_text()
