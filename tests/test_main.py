"""``python -m ngdgfric`` (ngdgfric/__main__.py): the command line in a fresh interpreter, with its exit code."""

import csv
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def python_m(*args):
    return subprocess.run([sys.executable, "-m", "ngdgfric", *args], capture_output=True, text=True, cwd=ROOT,
                          timeout=120)


def test_module_help():
    done = python_m("--help")
    assert done.returncode == 0
    assert "solve" in done.stdout and "adaptive" in done.stdout


def test_module_exit_code_of_bad_input():
    done = python_m("solve", "6.1", "--order", "0")
    assert done.returncode == 2
    assert done.stderr.startswith("ngdgfric: error: ") and "--order" in done.stderr


@pytest.mark.slow  # an adaptive run in a process
def test_sigterm_during_adaptive_exits_143_and_keeps_the_finished_levels(tmp_path):
    # P1 h-adaptive levels of Example 6.1: fractions of a second each, about 25 s for all of them
    process = subprocess.Popen([sys.executable, "-m", "ngdgfric", "adaptive", "6.1", "--no-hp", "--order", "1",
                                "--levels", "30", "--out", str(tmp_path)], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True, cwd=ROOT)
    levels = tmp_path / "6_1_adaptive_auto_p1.csv"
    try:
        deadline = time.monotonic() + 60
        while not (levels.exists() and len(levels.read_text().splitlines()) >= 2) and time.monotonic() < deadline:
            time.sleep(0.02)
        assert process.poll() is None, "the run ended before it could be terminated"
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 143, err
    assert err.splitlines() == ["ngdgfric: error: terminated (SIGTERM)"]
    with open(levels, newline="") as handle:
        reader = csv.DictReader(handle)
        rows = list(reader)
    assert rows and all(list(row) == reader.fieldnames and all(row.values()) for row in rows)  # every column filled
    assert [int(row["level"]) for row in rows] == list(range(len(rows)))
    assert [path.name for path in tmp_path.iterdir()] == [levels.name]  # no temporary file left
