"""Shared fixtures: manufactured solutions (ngdgfric.studies.manufactured)."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))

from ngdgfric.studies.manufactured import contact_manufactured, elasticity_manufactured  # noqa: E402


@pytest.fixture(scope="session")
def elasticity():
    return elasticity_manufactured()


@pytest.fixture(scope="session")
def contact_problem():
    return contact_manufactured()
