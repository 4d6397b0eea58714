"""README.md, the front door: short, its two commands the ones CI and the paper's reproduction run, its first scene
printing what it shows, its citation and licence real."""

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

import ngdgfric

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")


def blocks(language):
    """The fenced code blocks of ``language`` in README.md, in order."""
    return re.findall(rf"```{language}\n(.*?)```", README, flags=re.S)


def test_the_readme_is_a_front_door_of_at_most_80_lines():
    assert len(README.splitlines()) <= 80
    assert len(README[:README.index("## Two commands")].splitlines()) <= 12  # the commands near the top


def test_its_two_commands_are_the_reproduction_and_the_ci_test_command():
    install_and_reproduce, install_and_test = (block.strip() for block in blocks("bash")[:2])
    assert install_and_reproduce.startswith("python3 -m pip install . && python3 scripts/uniform_convergence.py "
                                            "--example 6.1")
    assert install_and_test.startswith("python3 -m pip install '.[test]' && ")
    test_command = install_and_test.split(" && ", 1)[1]
    ci = (ROOT / ".ci" / "run").read_text()
    assert test_command in ci.splitlines()  # CI runs exactly the README's test command, as a line of its own
    assert (ROOT / "scripts" / "uniform_convergence.py").exists()


@pytest.mark.slow
def test_the_first_scene_prints_what_the_readme_shows(tmp_path):
    """The README's scene run as written, in a fresh process: its output is the text block under it, to the digit."""
    section = README.split("## A first scene", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, flags=re.S).group(1)
    shown = re.search(r"```text\n(.*?)```", section, flags=re.S).group(1)
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout == shown


def test_the_citation_file_names_the_paper_by_its_arxiv_number_and_the_licence_is_mit():
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert citation["cff-version"] == "1.2.0" and citation["title"].startswith("ngdgfric")
    assert citation["license"] == "MIT" and citation["type"] == "software"
    paper = citation["preferred-citation"]
    assert paper["title"] == ("Unified analysis of discontinuous Galerkin methods for frictional contact problem "
                              "with normal compliance")
    assert [a.get("family-names", a.get("name")) for a in paper["authors"]] == ["Porwal", "Tanvi"]
    assert {"type": "other", "value": "arXiv:2104.08266", "description": "The arXiv preprint"} in paper["identifiers"]
    assert "arXiv:2104.08266" in README and "CITATION.cff" in README
    assert (ROOT / "LICENSE").read_text().startswith("MIT License\n")
    assert str(citation["version"]) == ngdgfric.__version__
