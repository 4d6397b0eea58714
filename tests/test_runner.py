"""ngdgfric.studies.runner: cases run in worker processes come back in order and are cached."""

import pytest

from ngdgfric.studies.cases import rho_case
from ngdgfric.studies.runner import case_key, run_cases


def test_case_key_depends_on_the_case_and_the_function_only():
    assert case_key(rho_case, dict(h=0.25, factor=1.0)) == case_key(rho_case, dict(factor=1.0, h=0.25))
    assert case_key(rho_case, dict(h=0.25, factor=1.0)) != case_key(rho_case, dict(h=0.25, factor=2.0))
    assert case_key(rho_case, {}) != case_key(run_cases, {})
    with pytest.raises(ValueError, match="workers"):
        run_cases(rho_case, [], workers=0)


@pytest.mark.slow  # a dask cluster
def test_runner_caches_results_and_uzawa_divergence_names_rho(tmp_path):
    cases = [dict(example="6.1", factor=f, h=0.25, maxit=400) for f in (1.0, 4.0)]
    first = run_cases(rho_case, cases, cache=tmp_path, workers=2, progress=None)
    assert first[0]["status"] == "converged" and "rho" in first[1]["status"]
    assert len(list(tmp_path.glob("*.json"))) == 2
    again = run_cases(rho_case, cases, cache=tmp_path, workers=2, progress=None)  # from the cache: no cluster
    assert again == first
