"""The public API's docstrings are NumPy style, and their examples run.

numpydoc's own validator (``numpydoc.validate``, the checker of the NumPy/SciPy ecosystem) reads the
docstring of every public function and class: the names of ``ngdgfric.__all__`` and the plotting and
writing functions of ``ngdgfric.output``.  Each must parse as a NumPy docstring with a one-line summary,
document every argument of its signature and no other (Parameters), and, for a function, say what it
returns (Returns or Yields) and describe it.  The Examples sections are run as doctests.
"""

import doctest
import inspect

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
