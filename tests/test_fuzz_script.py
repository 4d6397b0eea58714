"""scripts/fuzz.py, the runner over tests/data/fuzz: its selection, its verdicts, a few cases end to end."""

import importlib
import time
from pathlib import Path

import pytest

fuzz = importlib.import_module("fuzz")  # scripts/ is on sys.path (tests/conftest.py)

pytestmark = pytest.mark.fuzz

# a few cases of the issue (a crash, a hang, silent answers before), through the API and the CLI
WORKING = ["api-g_a-nan", "cli-toml-polygon-bowtie", "api-reference-truncated", "cli-size-uniform-levels-14",
           "cli-arg-order-0", "cli-schema-hole-outside", "api-schema-u_D-expression-inf", "cli-schema-expr-if-chained"]


def test_the_schema_of_problem_files_is_covered_and_is_the_quick_run():
    ids = {case.id for case in fuzz.CASES}
    for kind in ("region-unnamed-of-two", "region-name-space", "region-unknown-key", "hole-outside", "hole-radius-bool",
                 "hole-center-spelling", "arcs-key-word", "arcs-crossing", "arcs-point-nan", "symmetry-number",
                 "symmetry-also-traction", "E-table-unknown-region", "nu-table-0.7", "f-table-short",
                 "g-table-unknown-side", "u_D-nan", "u_D-table-unknown", "u_D-expression-inf", "c_n-table-empty",
                 "g_a-table-nan", "c_tau-table-negative-somewhere", "m_n-table-below-1", "m_t-table-negative",
                 "expr-if-no-comparison", "expr-if-chained", "expr-min-one-argument", "expr-step-two-arguments",
                 "expr-if-branch-inf-on-domain"):
        assert f"cli-schema-{kind}" in ids and f"api-schema-{kind}" in ids, kind
    expressions = [i.removeprefix("cli-schema-expr-") for i in ids if i.startswith("cli-schema-expr-")]
    assert len(expressions) > 20
    for name in expressions:  # each bad use of step, min, max, if also straight into the parser
        assert f"api-schema-parse-{name}" in ids or name.endswith("-on-domain")
    quick = fuzz.selected(fuzz.parse(["--quick"]))
    assert quick and all(fuzz.QUICK in case.id for case in quick)
    assert len(quick) == sum(fuzz.QUICK in case.id for case in fuzz.CASES)
    assert [case.id for case in fuzz.selected(fuzz.parse(["--quick", "--only", "hole-radius-bool"]))] \
        == ["cli-schema-hole-radius-bool", "api-schema-hole-radius-bool"]
    assert len(fuzz.selected(fuzz.parse([]))) == len(fuzz.CASES)


def test_a_family_is_selected_by_its_name():
    pairs = fuzz.selected(fuzz.parse(["--family", "pairs"]))
    assert pairs and {case.family for case in pairs} == {"pairs"}
    assert len(pairs) == sum(case.family == "pairs" for case in fuzz.CASES)
    assert [case.id for case in fuzz.selected(fuzz.parse(["--family", "pairs", "--only", "touching"]))] \
        == ["api-pairs-touching-not-a-pair", "cli-pairs-toml-touching-not-a-pair"]
    assert not fuzz.selected(fuzz.parse(["--family", "data", "--only", "pairs-"]))


def outcome(code, stdout="", stderr=""):
    return fuzz.Outcome(code, stdout, stderr, 0.1)


def test_classify():
    api = fuzz.Case("api-x", "api", "x", snippet="pass", expect=("g_a",))
    cli = fuzz.Case("cli-x", "cli", "x", argv=("solve",), expect=("g_a",))
    assert fuzz.classify(api, outcome(None), 30)[0] == fuzz.HANG
    verdict, happened = fuzz.classify(cli, outcome(-11), 30)
    assert verdict == fuzz.SIGNAL and "SIGSEGV" in happened
    assert fuzz.classify(api, outcome(3, "NAMED-ERROR ValueError: g_a must be finite\n"), 30)[0] == fuzz.NAMED
    assert fuzz.classify(api, outcome(3, "NAMED-ERROR ValueError: must be finite\n"), 30)[0] == fuzz.UNNAMED
    assert fuzz.classify(api, outcome(3, "NAMED-ERROR ValueError: \n"), 30)[0] == fuzz.UNNAMED
    assert fuzz.classify(api, outcome(0, "SILENT\n"), 30)[0] == fuzz.SILENT
    wrong = fuzz.classify(api, outcome(1, "", "Traceback (most recent call last):\nOverflowError: big\n"), 30)
    assert wrong == (fuzz.WRONG_TYPE, "exit 1: OverflowError: big")
    assert fuzz.classify(cli, outcome(0, "wrote out/a.csv\n"), 30)[0] == fuzz.SILENT
    assert fuzz.classify(cli, outcome(1, "", "Traceback (most recent call last):\nKeyError: 1\n"), 30)[0] \
        == fuzz.TRACEBACK
    assert fuzz.classify(cli, outcome(2, "", "ngdgfric: error: contact.g_a: nan\n"), 30)[0] == fuzz.NAMED
    assert fuzz.classify(cli, outcome(2, "", "ngdgfric: error: not finite\n"), 30)[0] == fuzz.UNNAMED
    assert fuzz.classify(cli, outcome(2, "", "warning\nngdgfric: error: g_a\n"), 30)[0] == fuzz.OTHER
    assert fuzz.classify(cli, outcome(1, "", "ngdgfric: error: no convergence\n"), 30)[0] == fuzz.EXIT_1
    assert fuzz.classify(cli, outcome(5), 30)[0] == fuzz.OTHER
    # whole words: "nu" is not named by "number", "E" not by "error"
    assert not fuzz.names_datum("must be a number", ("nu",)) and fuzz.names_datum("material.nu: bad", ("nu",))
    assert not fuzz.names_datum("error", ("E",)) and fuzz.names_datum("E must be > 0", ("E",))
    assert fuzz.names_datum("f[0] must be finite", ("f",))


@pytest.mark.slow
def test_run_end_to_end(tmp_path, capsys):
    code = fuzz.main(["--out", str(tmp_path), "--timeout", "60", "--workers", "2",
                      *[arg for case in WORKING for arg in ("--only", case)]])
    text = (tmp_path / "fuzz.md").read_text()
    assert "python scripts/fuzz.py" in text and "| hangs | 0 |" in text
    for case in WORKING:
        assert f"`{case}`" in text
    assert text.count("| named error |") == len(WORKING), text
    assert code == 0
    assert capsys.readouterr().out.count("named error (") == len(WORKING)  # one progress line per case
    assert not list(tmp_path.glob(".*"))  # the temporary file of the atomic write is gone


@pytest.mark.slow
def test_signal_and_hang_in_real_processes(tmp_path):
    crash = fuzz.Case("api-crash", "api", "x", snippet="import signal\nos.kill(os.getpid(), signal.SIGSEGV)")
    result = fuzz.run_case(crash, timeout=60)
    assert result.verdict == fuzz.SIGNAL and "SIGSEGV" in result.happened
    # the case starts a child and both sleep on: the whole process group is killed at the timeout
    pid_file = tmp_path / "pid"
    snippet = ("import subprocess, time\n"
               "child = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(60)'])\n"
               f"open({str(pid_file)!r}, 'w').write(str(child.pid))\ntime.sleep(60)")
    result = fuzz.run_case(fuzz.Case("api-hang", "api", "x", snippet=snippet), timeout=5)
    assert result.verdict == fuzz.HANG and result.seconds < 15
    status = Path(f"/proc/{pid_file.read_text()}/status")
    for _ in range(50):  # killed (then reaped by init, or a zombie meanwhile)
        if not status.exists() or "zombie" in status.read_text():
            break
        time.sleep(0.1)
    else:
        raise AssertionError("the case's child survived the timeout")
