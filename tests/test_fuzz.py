"""The bad inputs of tests/data/fuzz (format: its README.md): each one is refused with an error naming it.

In this process (marked fuzz): an API case's call raises its ``error`` with a message that contains one
of its ``expect`` words; a CLI case's ``ngdgfric.cli.main(argv)`` returns 2 with exactly one stderr line
``ngdgfric: error: ...`` naming it.  The cases marked ``isolated`` (they could hang, exhaust memory or
crash the process if their check regressed) run in a process of their own, through scripts/fuzz.py's
runner with its timeout and memory cap (marked slow too).  scripts/fuzz.py runs every case that way and
writes results/fuzz.md.
"""

import importlib
from collections import Counter

import pytest

from ngdgfric import DataError
from ngdgfric.cli import main

fuzz = importlib.import_module("fuzz")  # scripts/ is on sys.path (tests/conftest.py)

CASES = {case.id: case for case in fuzz.CASES}
IN_PROCESS = [case.id for case in fuzz.CASES if not case.isolated]
ISOLATED = [case.id for case in fuzz.CASES if case.isolated]
ERRORS = {"ValueError": ValueError, "DataError": DataError, "FileNotFoundError": FileNotFoundError}

pytestmark = pytest.mark.fuzz


def test_the_data_files_hold_every_family_with_unique_ids():
    ids = [case.id for case in fuzz.CASES]
    assert len(set(ids)) == len(ids), [i for i, n in Counter(ids).items() if n > 1]
    assert {case.family for case in fuzz.CASES} == set(fuzz.FAMILIES)
    for case in fuzz.CASES:
        assert case.id.startswith(case.interface + "-") and case.description
        if case.interface == "api":
            assert case.snippet and not case.argv and case.error in ERRORS
        else:
            assert case.argv is not None and not case.snippet and not case.error
        assert case.check in ("", "quiet", "unchanged")


def test_the_data_cover_the_issue_and_every_datum_through_both_interfaces():
    issue = {case.id for case in fuzz.CASES if case.issue}
    for required in ("api-g_a-nan", "cli-toml-E-huge-int", "api-polygon-bowtie", "cli-toml-polygon-bowtie",
                     "api-reference-truncated", "api-uniform-mesh-1e-5", "cli-size-uniform-levels-14",
                     "cli-out-blocked-vtu", "cli-out-adaptive-rerun", "cli-file-non-utf8", "api-solve-other-mesh-6-2"):
        assert required in issue
    for datum in ("E", "nu", "c_n", "m_n", "g_a", "c_tau", "m_t", "f0", "f1", "g0", "g1"):
        for value in ("nan", "inf", "minusinf"):
            assert f"api-{datum}-{value}" in CASES and f"cli-toml-{datum}-{value}" in CASES


@pytest.fixture(scope="module")
def preamble():
    """The names an API case's call sees (scripts/fuzz.py's PREAMBLE), made once."""
    names = {}
    exec(fuzz.PREAMBLE, names)
    return names


def message_names(message, case):
    assert message.strip(), f"{case.id}: empty message"
    assert fuzz.names_datum(message, case.expect), f"{case.id}: {message!r} names none of {case.expect}"


def check_api(case, names):
    names = dict(names)
    exec(case.setup, names)
    with pytest.raises(ERRORS[case.error]) as raised:
        exec(case.snippet, names)
    message_names(str(raised.value), case)


def check_cli(case, folder, capsys):
    for command in case.commands:  # an earlier run (output safety)
        assert main(list(command)) == 0, capsys.readouterr().err
    capsys.readouterr()
    before = fuzz.snapshot(folder)
    code = main(list(case.argv))
    out, err = capsys.readouterr()
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2 and len(lines) == 1 and lines[0].startswith("ngdgfric: error: "), (code, err)
    message_names(lines[0].removeprefix("ngdgfric: error: "), case)
    if case.check == "quiet":
        assert not out.strip(), f"{case.id}: printed {out!r} before the error"
    if case.check == "unchanged":
        assert before and fuzz.snapshot(folder) == before


@pytest.mark.parametrize("case_id", IN_PROCESS)
def test_bad_input_is_refused_naming_it(case_id, preamble, tmp_path, monkeypatch, capsys):
    case = CASES[case_id]
    monkeypatch.chdir(tmp_path)
    fuzz.make_files(tmp_path, case.files)
    if case.interface == "api":
        check_api(case, preamble)
    else:
        check_cli(case, tmp_path, capsys)


@pytest.mark.slow
@pytest.mark.parametrize("case_id", ISOLATED)
def test_bad_input_is_refused_naming_it_in_its_own_process(case_id):
    result = fuzz.run_case(CASES[case_id], timeout=60)
    assert result.verdict == fuzz.NAMED, result.happened
