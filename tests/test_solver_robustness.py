"""scripts/solver_robustness.py (issue 12, item 6) in its smoke-sized form: every case at round-off."""

import importlib


def test_solver_robustness_quick(tmp_path):
    rows = importlib.import_module("solver_robustness").main(["--quick", "--out", str(tmp_path)])
    assert len(rows) == 8
    failed = [(r["id"], r["reasons"]) for r in rows if not r["passed"]]
    assert not failed
    agreed = [r for r in rows if r["uzawa_status"] == "converged" and r["uzawa_difference"] <= 1e-7]
    assert agreed
    assert (tmp_path / "solver_robustness.csv").stat().st_size > 0
    assert "Summary" in (tmp_path / "solver_robustness.md").read_text()
