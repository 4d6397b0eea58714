"""``python -m ngdgfric`` (ngdgfric/__main__.py): the command line in a fresh interpreter, with its exit code."""

import subprocess
import sys
from pathlib import Path

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
