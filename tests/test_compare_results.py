"""scripts/compare_results.py: its quick run agrees with the committed results, and its comparison finds a
difference of 1e-6 in an error, a changed iteration count or a changed printed number (scripts/ is on sys.path:
tests/conftest.py)."""

import copy

import compare_results as cr
import pytest
from common import RESULTS, read_csv


def committed(name):
    return read_csv(RESULTS / name, text=cr.TEXT)


@pytest.mark.slow
def test_quick_run_agrees(capsys):
    assert cr.main(["--quick"]) == 0
    out = capsys.readouterr().out
    assert "all agree" in out
    assert "skipped (timing): seconds, uzawa_seconds" in out  # the timing columns are named


def test_identical_rows_agree():
    rows = committed("table_6_2.csv")
    result = cr.compare_rows("table_6_2.csv", rows, copy.deepcopy(rows), cr.TABLE)
    assert result.ok() and result.rows == result.committed == len(rows) and result.worst == 0.0


@pytest.mark.parametrize("column", ["true_relative", "energy", "l2"])
def test_a_relative_change_of_1e_6_in_an_error_is_a_difference(column):
    rows = committed("table_6_2.csv")
    perturbed = copy.deepcopy(rows)
    perturbed[7][column] *= 1 + 1e-6
    result = cr.compare_rows("table_6_2.csv", rows, perturbed, cr.TABLE)
    assert not result.ok()
    assert result.worst == pytest.approx(1e-6, rel=1e-3)
    assert [f.split(":")[0] for f in result.failures] == [f"method=nipg k=3 {column}"]


def test_iterations_and_dofs_must_be_equal_timing_is_skipped():
    rows = committed("adaptive_6_1_sipg.csv")
    changed = copy.deepcopy(rows)
    changed[4]["iterations"] += 1  # one Newton step more: its last step is decided at round-off (listed)
    changed[5]["iterations"] += 2
    changed[6]["ndof"] += 2
    changed[7]["solve_seconds"] *= 10  # timing: not compared
    changed[8]["eta_lin"] = 1e-14  # round-off, against the floor eta_h (about 100 here)
    result = cr.compare_rows("adaptive_6_1_sipg.csv", rows, changed, cr.ADAPTIVE)
    assert sorted(f.split(":")[0] for f in result.failures) == ["level=5 iterations", "level=6 ndof"]
    assert [k.split(":")[0] for k in result.known] == ["level=4 iterations"]
    assert "solve_seconds" in result.skipped


def test_one_newton_step_more_or_less_is_listed_not_counted():
    rows = committed("table_6_1.csv")
    changed = copy.deepcopy(rows)
    bassi = next(r for r in changed if r["method"] == "bassi" and r["k"] == 3)
    bassi["iterations"] = 5  # the committed 6: one step less, at round-off (listed)
    assert cr.compare_rows("table_6_1.csv", rows, changed, cr.TABLE).known
    bassi["iterations"] = 8  # two steps more: a difference
    assert not cr.compare_rows("table_6_1.csv", rows, changed, cr.TABLE).ok()


def test_a_row_not_in_the_committed_file_is_a_difference():
    rows = committed("uniform_6_2_sipg.csv")
    extra = dict(rows[-1], h=rows[-1]["h"] / 2)
    assert not cr.compare_rows("uniform_6_2_sipg.csv", rows, rows + [extra], cr.UNIFORM).ok()


def test_markdown_to_printed_precision():
    page = (RESULTS / "scenes.md").read_text()
    line = next(x for x in page.splitlines() if x.startswith("| sipg | 1 | 5.62e-13"))
    # timing and round-off (below 1e-8) change, the rest as printed: the same
    same = page.replace(line, line.replace("| 1.21 |", "| 9.99 |").replace("5.62e-13", "7.1e-13"))
    assert cr.compare_markdown("scenes.md", page, same).ok()
    newton = page.replace(line, line.replace("| exact | - | 0 |", "| exact | - | 1 |"))  # one step: round-off
    assert cr.compare_markdown("scenes.md", page, newton).ok()
    newton = page.replace(line, line.replace("| exact | - | 0 |", "| exact | - | 2 |"))
    assert not cr.compare_markdown("scenes.md", page, newton).ok()
    failures = page.replace(line, line.rsplit("| 0 |", 1)[0] + "| 1 |")  # the failures column: a count
    assert failures != page and not cr.compare_markdown("scenes.md", page, failures).ok()


def test_stale_sections_are_listed_counted_only_when_strict():
    page = (RESULTS / "scenes.md").read_text()
    adapt_row = next(x for x in page.splitlines() if x.startswith("| layers-indented | cg |"))
    result = cr.compare_markdown("scenes.md", page, page.replace(adapt_row, adapt_row.replace("| 162 |", "| 164 |")))
    assert result.stale and result.ok() and not result.ok(strict=True)


def test_stale_rows_are_listed_the_others_compared():
    rows = committed("scenes_adapt.csv")
    changed = copy.deepcopy(rows)
    for row in changed:
        row["ndof"] += 2
    result = cr.compare_rows("scenes_adapt.csv", rows, changed, cr.SCENES_ADAPT)
    stale = sorted(f.split(":")[0] for f in result.stale)
    assert stale == sorted(f"scene={name} ndof" for name in cr.STALE["scenes_adapt.csv"])
    assert len(result.failures) == len(rows) - len(stale) and not result.ok()
