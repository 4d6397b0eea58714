"""The package's house rules (issue 30): small modules with one job, short functions, one public API."""

import ast
from pathlib import Path

import pytest

import ngdgfric as ndf

PACKAGE = Path(ndf.__file__).resolve().parent
MODULES = sorted(PACKAGE.rglob("*.py"))
MAX_MODULE_LINES, MAX_FUNCTION_LINES = 400, 60


def documentation_lines(tree):
    """The line numbers of the docstrings in ``tree`` (every string that stands as a statement of its own: the
    docstrings of the module, its classes and functions, and those after an assignment)."""
    return {line for node in ast.walk(tree) if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)
            and isinstance(node.value.value, str) for line in range(node.lineno, node.end_lineno + 1)}


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_modules_and_functions_are_short(path):
    """Lines of code, docstrings not counted: the NumPy-style docstrings of the public API (Parameters, Returns,
    Raises, Examples: ``adapt``'s is 100 lines) document the code; they do not make it longer to read."""
    text = path.read_text()
    tree = ast.parse(text)
    docs = documentation_lines(tree)
    assert len(text.splitlines()) - len(docs) <= MAX_MODULE_LINES
    long = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            span = set(range(node.lineno, node.end_lineno + 1))
            if len(span - docs) > MAX_FUNCTION_LINES:
                long.append(f"{node.name} ({len(span - docs)} lines of code)")
    assert not long


@pytest.mark.parametrize("path", [p for p in MODULES if p.name != "__init__.py"],
                         ids=lambda p: str(p.relative_to(PACKAGE)))
def test_every_module_states_its_job(path):
    assert ast.get_docstring(ast.parse(path.read_text())), "module docstring missing"
