"""The default solver over the data (scripts/robustness_cases.py, issue 12, item 6): every case solved at round-off.

A case passes iff the solve raises nothing, the KKT residuals of Lemma 3.1 are at round-off and, where
Uzawa converges, the two solvers agree; a SolverError is accepted only where plain semismooth Newton from
random starts finds no solution either.  The property test draws cases with hypothesis over the ranges
of the study; the named hard cases (issue 12, the extremes of tests/test_newton.py, the bimaterial strip
of issue 26) are explicit examples; the eight quick cases, without Uzawa, are the smoke version.  The report
(results/solver_robustness.md/.csv, a fixed seed) is written by scripts/solver_robustness.py.
"""

import importlib

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

robustness = importlib.import_module("robustness_cases")  # scripts/ is on sys.path (tests/conftest.py)
UZAWA_SECONDS = robustness.QUICK_UZAWA_SECONDS  # Uzawa's time budget per case (its failing is no failure)


def check(spec, uzawa_seconds=UZAWA_SECONDS):
    """Run the case; assert it passes or has no solution; its row."""
    row = robustness.run_case(spec, uzawa_seconds=uzawa_seconds)
    assert row["passed"] or row["status"] == "no solution found", (spec, row["reasons"], row["message"])
    return row


@pytest.mark.parametrize("spec", robustness.quick_cases(), ids=lambda spec: spec["id"])
def test_quick_case_is_solved_at_round_off(spec):
    row = check(spec, uzawa_seconds=0)  # without Uzawa, whose time budget is coarse (the slow tests run it)
    assert row["passed"] and row["uzawa_status"] == "not run"


@pytest.mark.slow
@pytest.mark.parametrize("spec", robustness.named_cases(), ids=lambda spec: spec["id"])
def test_named_hard_case_is_solved_at_round_off(spec):
    check(spec)


@st.composite
def drawn_cases(draw):
    """A case over the ranges of robustness_cases.draw_case, every value equally likely."""
    return robustness.draw_case("H", draw(st.sampled_from(robustness.METHOD_NAMES)),
                                lambda values, weights=None: draw(st.sampled_from(values)),
                                lambda p: draw(st.booleans()))


@pytest.mark.slow
@settings(max_examples=20, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])
@given(drawn_cases())
def test_drawn_cases_are_solved_at_round_off_or_have_no_solution(spec):
    check(spec)


@pytest.mark.slow
def test_the_script_writes_the_report(tmp_path):
    rows = importlib.import_module("solver_robustness").main(
        ["--quick", "--only", "Q1", "Q3", "--workers", "1", "--out", str(tmp_path)])
    assert [row["id"] for row in rows] == ["Q1", "Q3"] and all(row["passed"] for row in rows)
    assert any(row["uzawa_status"] == "converged" for row in rows)  # and agreed: passed
    assert len((tmp_path / "solver_robustness.csv").read_text().splitlines()) == 1 + len(rows)
    text = (tmp_path / "solver_robustness.md").read_text()
    assert "- cases: 2, passed: 2, failed: 0" in text
