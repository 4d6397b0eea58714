"""ngdgfric.studies.uniform: consecutive differences on uniform meshes converge at the optimal rate."""

import pytest

from ngdgfric.studies import uniform_study


@pytest.mark.parametrize("order, levels", [(1, (2, 3, 4)), (2, (1, 2, 3))])
def test_consecutive_differences_converge_at_rate_p(elasticity, order, levels):
    problem, _ = elasticity
    said = []
    rows, solutions = uniform_study(problem, "sipg", order, levels, progress=said.append)
    assert [row["k"] for row in rows] == list(levels[:-1]) and len(solutions) == len(said) == len(levels)
    assert rows[0]["rate"] is None and rows[-1]["rate"] == pytest.approx(order, abs=0.1)


def test_the_finest_mesh_is_checked_before_the_first_solve(elasticity):
    problem, _ = elasticity
    said = []
    with pytest.raises(ValueError, match="max_ndof"):
        uniform_study(problem, levels=(1, 2, 9), max_ndof=10**5, progress=said.append)
    assert said == []
