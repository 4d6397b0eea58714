"""The contact package is the one home of the contact laws, and the layers run one way.

- A compliance or friction formula outside ``ngdgfric/contact/`` fails the test: the laws are written once, in
  :mod:`ngdgfric.contact.laws`, and everything else calls them.  The patterns are the shapes the laws were written
  in before they had one home (each pattern is checked against such a line below, so that it can fail).
- Nothing in :mod:`ngdgfric.dg` imports from :mod:`ngdgfric.solvers`, and the contact package imports neither.
"""

import ast
import re
from pathlib import Path

import pytest
from test_house import documentation_lines

import ngdgfric as ndf

PACKAGE = Path(ndf.__file__).resolve().parent
CONTACT = PACKAGE / "contact"

LAW_PATTERNS = {
    "projection onto [-1, 1] (CoefficientFunction)": r"IfPos\(\s*[\w.()\[\]]+\s*-\s*1\s*,\s*1\b",
    "projection onto [-1, 1] (numpy)": r"np\.clip\(.*?(lam|ratio|multiplier).*?,\s*-\s*1(\.0)?\s*,\s*1(\.0)?\s*\)",
    "conjugate of the compliance energy": r"\(\s*m\w*\s*\+\s*1\s*\)\s*/\s*m",
    "inverse of the pressure law": r"\*\*\s*\(\s*-?\s*1\s*/\s*[\w.]*m",
    "pressure c_n (d)_+^m": r"c_n\s*\*\s*(ngs\.)?(IfPos|np\.maximum|\w*positive_power)",
    "friction bound c_tau (d)_+^m": r"c_tau\s*\*\s*(ngs\.)?(IfPos|np\.maximum|\w*positive_power)",
    "compliance energy c_n / (m + 1)": r"c_n\s*/\s*\(\s*m\w*\s*\+\s*1\s*\)",
    "positive power": r"def \w*positive_power",
}

# how the laws were written outside the contact package before (estimator, equilibration, solvers, studies)
FORMER = [
    "    return ngs.IfPos(z - 1, 1, ngs.IfPos(-1 - z, -1, z))",
    "    return np.concatenate([normal, beta * np.clip(lam_tau, -1.0, 1.0)])",
    "    power = np.where(m == 1, fn * fn / (2 * safe), m / (m + 1) * safe ** (-1 / m) * fn ** ((m + 1) / m))",
    "    normal = np.where(problem.compliant, -s.w[:M] + problem.g_a + (s.f[:M] / safe) ** (1 / problem.m_n), 0.0)",
    "        s.N = law.omega * law.c_n * _positive_power(gap, m_n)",
    "        s.N = law.omega * law.c_n * np.maximum(gap, 0.0)",
    "    gauss.set_values(lam_tau, np.clip(start.multiplier(gauss.xy.reshape(-1, 2)), -1, 1).reshape(-1, gauss.q))",
    "    beta = np.where(reduced, omega * c_tau, omega * c_tau * _positive_power(gap, exponent))",
    "    j_s = (c_n / (m_n + 1) * positive_power(s * n - g_a, m_n + 1)",
    "def _positive_power(x, m):",
]


def code_lines(path):
    """(line number, text) of the lines of ``path`` that are code: docstrings and comments left out."""
    text = path.read_text()
    docs = documentation_lines(ast.parse(text))
    return [(k, line) for k, line in enumerate(text.splitlines(), 1)
            if k not in docs and not line.lstrip().startswith("#")]


@pytest.mark.parametrize("line", FORMER)
def test_the_patterns_find_the_laws_as_they_were_written(line):
    assert any(re.search(pattern, line) for pattern in LAW_PATTERNS.values())


def test_no_contact_law_outside_the_contact_package():
    found = [f"{path.relative_to(PACKAGE)}:{k}: {name}: {line.strip()}"
             for path in sorted(PACKAGE.rglob("*.py")) if CONTACT not in path.parents
             for k, line in code_lines(path)
             for name, pattern in LAW_PATTERNS.items() if re.search(pattern, line)]
    assert not found, "\n".join(found)


def imported_modules(path):
    """The absolute names of the ngdgfric modules that ``path`` imports (relative imports resolved)."""
    package = ".".join(["ngdgfric", *path.relative_to(PACKAGE).parent.parts])
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            names.add(module)
            names.update(f"{module}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
    return {name for name in names if name.startswith("ngdgfric")}


@pytest.mark.parametrize("layer, forbidden", [("dg", ("ngdgfric.solvers",)),
                                              ("contact", ("ngdgfric.solvers", "ngdgfric.dg"))])
def test_layers_run_one_way(layer, forbidden):
    wrong = {f"{path.relative_to(PACKAGE)}: {name}" for path in (PACKAGE / layer).rglob("*.py")
             for name in imported_modules(path) if name.startswith(forbidden)}
    assert not wrong


def test_the_import_check_sees_an_import():
    """The resolver itself: ngdgfric/dg/discretization.py imports the contact package's boundary module."""
    assert "ngdgfric.contact.boundary" in imported_modules(PACKAGE / "dg" / "discretization.py")
