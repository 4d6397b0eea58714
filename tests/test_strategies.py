"""ngdgfric.studies.strategies: every refinement strategy measured against a reference solution."""

import pytest

import ngdgfric as ndf
from ngdgfric.studies import strategy_run


@pytest.fixture(scope="module")
def example_and_reference():
    problem = ndf.example_6_2()
    return problem, ndf.solve(problem, ndf.uniform_mesh(problem, 1 / 16), order=3)


def test_uniform_strategy_stops_at_the_dof_budget(example_and_reference):
    problem, reference = example_and_reference
    records = strategy_run(problem, "uniform", reference=reference, max_ndof=1500)
    assert [r["ndof"] for r in records] == [48, 192, 768]  # h = 2^-1, 2^-2, 2^-3; 2^-4 would have 3072
    assert all(r["seconds"] > 0 for r in records)
    conforming = strategy_run(problem, "uniform", method="cg", reference=reference, max_ndof=1500, progress=None)
    assert [r["ndof"] for r in conforming] == [18, 50, 162, 578]  # 2 (1/h + 1)^2: its own DOFs, not a DG count


@pytest.mark.parametrize("strategy, order", [("uniform", 1), ("h", 1), ("hp", 2)])
def test_errors_fall_and_the_estimator_bounds_them(example_and_reference, strategy, order):
    problem, reference = example_and_reference
    kept = []
    records = strategy_run(problem, strategy, order=order, reference=reference, max_ndof=1500,
                           keep=lambda level, sol, est: kept.append(level))
    errors = [r["error"] for r in records]
    assert all(a > b for a, b in zip(errors, errors[1:], strict=False))
    assert all(1 < r["eta_h"] / r["error"] < 5 for r in records)  # reliable, efficient (energy weights)
    if strategy != "uniform":  # the adaptive loop's cumulative time; keep sees every level
        assert kept == [r["level"] for r in records]
        assert all(a["seconds"] < b["seconds"] for a, b in zip(records, records[1:], strict=False))


def test_hp_reaches_a_smaller_error_than_h_with_the_same_budget(example_and_reference):
    problem, reference = example_and_reference
    h, hp = (strategy_run(problem, s, order=p, reference=reference, max_ndof=1500)[-1] for s, p in (("h", 1),
                                                                                                      ("hp", 2)))
    assert hp["ndof"] <= 1500 and h["ndof"] <= 1500 and hp["error"] < 0.5 * h["error"]
    with pytest.raises(ValueError, match="strategy"):
        strategy_run(problem, "p")


def test_the_old_name_weights_still_selects_the_variant_with_a_warning():
    new = strategy_run(ndf.example_6_1(), "uniform", max_ndof=200, progress=None, variant="paper")
    with pytest.warns(DeprecationWarning, match=r"strategy_run\(weights=...\) is deprecated"):
        old = strategy_run(ndf.example_6_1(), "uniform", max_ndof=200, progress=None, weights="paper")
    assert [r["eta_h"] for r in old] == [r["eta_h"] for r in new]
    energy = strategy_run(ndf.example_6_1(), "uniform", max_ndof=200, progress=None)
    assert energy[0]["eta_h"] != new[0]["eta_h"]
