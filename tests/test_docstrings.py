"""The public API's docstrings are NumPy style, their examples run, and no docstring keeps a lab notebook.

numpydoc's own validator (``numpydoc.validate``, the checker of the NumPy/SciPy ecosystem) reads the
docstring of every public function and class: the names of ``ngdgfric.__all__`` and the plotting and
writing functions of ``ngdgfric.output``.  Each must parse as a NumPy docstring with a one-line summary,
document every argument of its signature and no other (Parameters), and, for a function, say what it
returns (Returns or Yields) and describe it.  The Examples sections are run as doctests.

Every docstring of every module (module, class, function, and the attribute docstrings after an assignment) states
the contract and the mathematics; the story of what was tried goes to the decisions page of the docs
(docs/decisions.md).  So no docstring has the words of such a story (``HISTORY``).
"""

import ast
import doctest
import inspect
import itertools
import re
from pathlib import Path

import numpydoc.docscrape
import numpydoc.validate
import pytest

import ngdgfric
import ngdgfric.output

# numpydoc's codes (numpydoc.validate.ERROR_MSGS): each is a property every public docstring has
REQUIRED = {
    "GL01": "the summary starts on the line after the opening quotes",  # the NumPy layout: see GL01's text
    "GL02": "the closing quotes on a line of their own",
    "GL03": "no double blank lines",
    "GL05": "no tabs",
    "GL06": "no unknown section",
    "GL07": "sections in the standard order",
    "GL08": "a docstring",
    "SS01": "a summary",
    "SS02": "the summary starts with a capital letter",
    "SS03": "the summary ends with a period",
    "SS06": "the summary fits on one line",
    "PR01": "every parameter documented",
    "PR02": "no parameter that does not exist",
    "PR03": "parameters in the signature's order",
    "PR04": "every parameter has a type",
    "PR07": "every parameter has a description",
    "PR08": "descriptions start with a capital letter",
    "PR09": "descriptions end with a period",
    "PR10": "a space before the colon of ``name : type``",
    "RT01": "a Returns or Yields section",
    "RT03": "the return value described",
    "RT04": "its description starts with a capital letter",
    "RT05": "its description ends with a period",
}
# GL01 asks for the summary on the line after the quotes; the package writes it on the quotes' line (PEP 257),
# which numpydoc accepts as well with GL01 off
REQUIRED.pop("GL01")
# the functions of ngdgfric.output a user calls (the gallery's figures); the rest serve the scripts' tables
OUTPUT = ["plot_deformed", "plot_contact", "plot_zones", "plot_mesh", "plot_estimator", "write_vtk",
          "write_deformed_png", "write_contact_png"]


def public_objects():
    """{qualified name: object} of every public function and class."""
    names = {f"ngdgfric.{name}": getattr(ngdgfric, name) for name in ngdgfric.__all__}
    names.update({f"ngdgfric.output.{name}": getattr(ngdgfric.output, name) for name in OUTPUT
                  if hasattr(ngdgfric.output, name)})
    return {name: obj for name, obj in names.items() if inspect.isclass(obj) or inspect.isfunction(obj)}


PUBLIC = public_objects()
# the entry points a newcomer starts from: each shows itself at work in an Examples section
WITH_EXAMPLES = ["solve", "adapt", "estimate", "example", "uniform_mesh", "load_problem", "kkt_residuals",
                 "force_balance", "equilibrate", "energy_norm", "ContactProblem", "AdaptOptions"]


def test_output_functions_exist():
    missing = [name for name in OUTPUT if not hasattr(ngdgfric.output, name)]
    assert not missing, f"ngdgfric.output lost {missing}"


@pytest.mark.parametrize("name", sorted(PUBLIC))
def test_numpy_docstring(name):
    result = numpydoc.validate.validate(name)
    errors = [f"{code} ({REQUIRED[code]}): {message}" for code, message in result["errors"] if code in REQUIRED]
    assert not errors, f"{name}:\n" + "\n".join(errors)


@pytest.mark.parametrize("name", WITH_EXAMPLES)
def test_entry_points_have_examples(name):
    sections = numpydoc.validate.Validator(numpydoc.validate.get_doc_object(getattr(ngdgfric, name)))
    assert sections.examples, f"ngdgfric.{name} has no Examples section"


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(PUBLIC))
def test_examples_run(name):
    """Every Examples section, run as a doctest (numbers printed rounded; ``...`` for what varies)."""
    obj = PUBLIC[name]
    finder = doctest.DocTestFinder(recurse=False)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in finder.find(obj, name, globs={"ndf": ngdgfric, "ngdgfric": ngdgfric}):
        runner.run(test)
    assert runner.summarize(verbose=False).failed == 0, f"{name}: an example failed (see the output above)"


PACKAGE = Path(ngdgfric.__file__).resolve().parent
# whole words, any case, matched in text whose white space is single spaces (``plain``): "tried" but not "retried"
# or "untried", and not the present passive "is tried", "are tried", "be tried" (what the code does: "the
# refinement is tried on a copy of the mesh")
HISTORY = re.compile(r"\b(?<!\bis )(?<!\bare )(?<!\bbe )tried\b|\bexploratory\b|\breverted\b|\bnot kept\b",
                     re.IGNORECASE)


def plain(text):
    """``text`` with every run of white space (line breaks, indentation) as one space."""
    return " ".join(text.split())


def docstrings(tree):
    """(line, name, text) of every docstring of a module's syntax tree: the module's, each class's and function's
    (also nested ones), and each attribute docstring (a string statement right after an assignment, in any block,
    as Sphinx reads them)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            text = ast.get_docstring(node, clean=False)
            if text is not None:
                line = node.body[0].lineno
                found.append((line, getattr(node, "name", "module docstring"), text))
        for field in ("body", "orelse", "finalbody"):
            block = getattr(node, field, None)
            if not isinstance(block, list):
                continue
            for previous, statement in itertools.pairwise(block):
                if isinstance(previous, (ast.Assign, ast.AnnAssign)) and isinstance(statement, ast.Expr) \
                        and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str):
                    targets = previous.targets if isinstance(previous, ast.Assign) else [previous.target]
                    found.append((statement.lineno, " = ".join(ast.unparse(t) for t in targets), statement.value.value))
    return found


def history_sentences(path):
    """``line name: sentence`` for every sentence of a docstring of ``path`` that has a word of ``HISTORY``."""
    result = []
    for line, name, text in docstrings(ast.parse(path.read_text())):
        for sentence in re.split(r"(?<=[.;]) ", plain(text)):
            if HISTORY.search(sentence):
                result.append(f"{line} {name}: {sentence}")
    return result


def test_the_history_words_are_found_and_only_they():
    tree = ast.parse('''"""Module: exploratory runs, not
    kept."""

X = 1
"""Attribute: since reverted."""


class C:
    """Class: the refinement is
    tried on a copy."""

    def f(self):
        """Function: also tried a larger step; retried and untried are other words."""
''')
    counts = {name: len(HISTORY.findall(plain(text))) for _, name, text in docstrings(tree)}
    assert counts == {"module docstring": 2, "X": 1, "C": 0, "f": 1}


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_docstring_keeps_a_lab_notebook(path):
    """Words of a story of what was tried (``HISTORY``) in no docstring: that story is on the decisions page."""
    found = history_sentences(path)
    assert not found, f"{path.relative_to(PACKAGE)}: move to docs/decisions.md:\n" + "\n".join(found)


@pytest.mark.parametrize("function", [ngdgfric.solve, ngdgfric.adapt])
def test_the_default_penalty_of_every_method_is_told_as_the_method_table_has_it(function):
    """``eta``'s entry in the Parameters of solve and adapt names each method's default penalty as
    ``ndf.METHODS`` holds it: a number times mu for the edge penalties, a pure number for the liftings."""
    text = numpydoc.docscrape.NumpyDocString(inspect.getdoc(function))
    eta = " ".join(next(p.desc for p in text["Parameters"] if p.name == "eta"))
    told = dict(re.findall(r"``(\w+)``\s+:math:`([0-9.]+\\mu|[0-9.]+)`", eta))
    assert set(told) == set(ngdgfric.METHODS), eta
    for name, method in ngdgfric.METHODS.items():
        number, unit = (told[name][:-len("\\mu")], "edge") if told[name].endswith("\\mu") else (told[name], "lift")
        assert (float(number), unit) == (method.default_eta, method.penalty), name
