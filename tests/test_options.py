"""Solver options: one frozen dataclass per solver; bad options raise a ValueError naming them before assembly, and
every option changes what the solver does."""

import dataclasses

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.solvers import pardiso
from ngdgfric.solvers.fixed_point import FixedPointOptions, fixed_point
from ngdgfric.solvers.newton import NewtonOptions, newton
from ngdgfric.solvers.options import SolverOptions
from ngdgfric.solvers.uzawa import UzawaOptions, uzawa


@pytest.mark.parametrize("options, name", [
    (dict(maxit=0), "maxit"), (dict(maxit=2.5), "maxit"), (dict(solver_tol=-1.0), "solver_tol"),
    (dict(solver_tol=float("nan")), "solver_tol"),
    (dict(solver="uzawa", rho=-1.0), "rho"), (dict(solver="uzawa", rho=0.0), "rho"), (dict(c0=-1), "c0"),
    (dict(linear_solver="mumps"), "linear_solver"), (dict(progress=3), "progress"),
    (dict(solver="uzawa", linear_solver="pardiso"), "linear_solver"), (dict(solver="fixed_point", inner="x"), "inner"),
    (dict(solver="uzawa", kkt_tol=0.0), "kkt_tol"), (dict(solver="fixed_point", solver_tol=0.0), "solver_tol"),
    (dict(initial="a solution"), "initial"),
])
def test_bad_option_is_named_before_assembly(options, name):
    with pytest.raises(ValueError, match=name):
        ndf.solve(ndf.example_6_1(), mesh=None, **options)  # no mesh needed: the option is checked first


def test_fixed_point_rejects_options_of_the_other_inner_solver():
    p = ndf.example_6_1()
    with pytest.raises(ValueError, match="rho"):
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), solver="fixed_point", inner="newton", rho=1.0)


@pytest.mark.parametrize("options_class", [NewtonOptions, UzawaOptions, FixedPointOptions])
def test_options_objects_check_their_fields(options_class):
    options = options_class()
    # the documented defaults: KKT residual 1e-13 for Newton, Section 6's 1e-8 for Uzawa and the fixed point
    assert options.solver_tol == {"newton": 1e-13, "uzawa": 1e-8, "fixed_point": 1e-8}[options_class.solver]
    for name, bad in (("maxit", 0), ("solver_tol", -1.0), ("progress", "print")):
        with pytest.raises(ValueError, match=name):
            options_class(**{name: bad})
    with pytest.raises(dataclasses.FrozenInstanceError):
        options.maxit = 3
    assert options_class.from_keywords(maxit=None, progress=None) == options  # None means the default


def test_fixed_point_keywords_build_the_inner_solvers_options():
    options = FixedPointOptions.from_keywords(solver_tol=1e-9, maxit=7, inner="uzawa", rho=0.5, kkt_tol=1e-7)
    assert options.maxit == 7 and options.solver_tol == 1e-9
    assert options.inner == UzawaOptions(solver_tol=1e-9, rho=0.5, kkt_tol=1e-7)  # inner maxit: Uzawa's own
    assert FixedPointOptions.from_keywords().inner is None  # None: Newton with the outer solver_tol
    assert FixedPointOptions.from_keywords().inner_options == NewtonOptions(solver_tol=1e-8)


def test_deprecated_tol_is_solver_tol():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    with pytest.warns(DeprecationWarning, match="solver_tol"):
        old = ndf.solve(p, mesh, solver="uzawa", tol=1e-9)
    new = ndf.solve(p, mesh, solver="uzawa", solver_tol=1e-9)
    assert old.iterations == new.iterations
    old_u, new_u = old.u.vec.FV().NumPy(), new.u.vec.FV().NumPy()
    assert np.max(np.abs(old_u - new_u)) <= 1e-12 * np.max(np.abs(new_u))
    with pytest.raises(ValueError, match="solver_tol only"), pytest.warns(DeprecationWarning):
        ndf.solve(p, mesh, tol=1e-9, solver_tol=1e-9)
    with pytest.raises(ValueError, match="solver_tol"), pytest.warns(DeprecationWarning):
        ndf.solve(p, None, tol=-1.0)  # checked before assembly, under its new name


# ---------------------------------------------------------------------------- every option does something
# For every field of every options class: the value it is changed to, and what that change must do to the solve
# (on a small problem per solver) compared with the defaults.  A new field, or a new options class, without an
# entry here fails test_every_option_has_a_behaviour_test.

@dataclasses.dataclass
class Outcome:
    """What a solve did: its info, or the error it raised, and the progress lines it printed."""

    info: dict | None
    error: Exception | None
    messages: list


def fewer_iterations(default, changed):
    return changed.info["iterations"] < default.info["iterations"]


def more_iterations(default, changed):
    return changed.info["iterations"] > default.info["iterations"]


def stops_at_maxit(default, changed):
    return isinstance(changed.error, ndf.SolverError) and len(changed.error.history) == 2 and default.error is None


def reports_progress(every=1):
    def check(default, changed):
        return not default.messages and len(changed.messages) == changed.info["iterations"] // every > 0
    return check


def stops_at_time_limit(default, changed):
    return isinstance(changed.error, ndf.TimeLimitError) and default.error is None


def other_linear_solver(default, changed):
    if not pardiso.available():  # "auto" is "ngsolve" here, and "pardiso" is refused
        return isinstance(changed.error, ValueError) and "pip install mkl" in str(changed.error)
    return (default.info["linear_solver"], changed.info["linear_solver"]) == ("pardiso", "ngsolve")


def full_space(default, changed):
    if not pardiso.available():  # refused: the full space needs PARDISO
        return isinstance(changed.error, ValueError) and "PARDISO" in str(changed.error)
    return (default.info["linear_solver"], changed.info["linear_solver"]) == ("pardiso", "pardiso (full space)")


def stops_early_with_a_state(default, changed):
    return changed.info["iterations"] == 0 and changed.info["state"] is not None and default.info["state"] is None


def uses_its_rho(default, changed):
    return changed.info["rho"] == 0.005 != default.info["rho"] and changed.info["iterations"] != default.info[
        "iterations"]


def looser_inner_solves(default, changed):
    return sum(changed.info["inner_iterations"]) < sum(default.info["inner_iterations"])


COMMON = dict(maxit=(2, stops_at_maxit), max_seconds=(1e-9, stops_at_time_limit))
EFFECTS = {
    NewtonOptions: dict(COMMON, solver_tol=(1e-3, fewer_iterations), progress=("record", reports_progress()),
                        linear_solver=("ngsolve" if pardiso.available() else "pardiso", other_linear_solver),
                        energy_tol=(1e3, stops_early_with_a_state), formulation=("full-space", full_space)),
    UzawaOptions: dict(COMMON, solver_tol=(1e-4, fewer_iterations), progress=("record", reports_progress(100)),
                       rho=(0.005, uses_its_rho), kkt_tol=(1e-8, more_iterations)),
    FixedPointOptions: dict(COMMON, solver_tol=(1e-3, fewer_iterations), progress=("record", reports_progress()),
                            inner=(NewtonOptions(solver_tol=1e-3), looser_inner_solves)),
}
SOLVE = {NewtonOptions: newton, UzawaOptions: uzawa, FixedPointOptions: fixed_point}
CLASSES = SolverOptions.__subclasses__()


@pytest.fixture(scope="module")
def small_problems():
    """Example 6.1 at h = 1/4: with m_n = 2 for Newton (so that solver_tol matters: P1 with m_n = 1 is solved
    exactly in 4 steps), as is for Uzawa (276 iterations), with m_t = 1 for the fixed point."""
    def disc(**changes):
        problem = dataclasses.replace(ndf.example_6_1(), **changes)
        discretization = ndf.Discretization(problem, ndf.uniform_mesh(problem, 1 / 4))
        return discretization, ndf.Contact(discretization)
    return {NewtonOptions: disc(m_n=2.0), UzawaOptions: disc(), FixedPointOptions: disc(m_t=1.0)}


def run(options_class, disc, **changes):
    messages = []
    changes = {name: messages.append if value == "record" else value for name, value in changes.items()}
    try:
        return Outcome(SOLVE[options_class](*disc, options_class(**changes))[2], None, messages)
    except (ndf.SolverError, ValueError) as error:
        return Outcome(None, error, messages)


def test_every_option_has_a_behaviour_test():
    assert set(CLASSES) == set(EFFECTS) == set(SOLVE)
    for options_class in CLASSES:
        assert sorted(EFFECTS[options_class]) == sorted(field.name for field in dataclasses.fields(options_class))


@pytest.mark.parametrize("options_class, name", [(options_class, field.name) for options_class in CLASSES
                                                 for field in dataclasses.fields(options_class)])
def test_changing_an_option_changes_the_solve(small_problems, options_class, name):
    value, effect = EFFECTS[options_class][name]
    disc = small_problems[options_class]
    default, changed = run(options_class, disc), run(options_class, disc, **{name: value})
    assert default.error is None
    assert effect(default, changed), (name, value, default, changed)


def test_the_inner_options_of_the_fixed_point_are_used_as_given(small_problems):
    """Issue 30: the inner solver_tol was overwritten by the outer one; now every inner option counts (its
    progress, its max_seconds), and inner=None means Newton with the outer solver_tol."""
    (disc, contact), lines = small_problems[FixedPointOptions], []
    fixed_point(disc, contact, FixedPointOptions(inner=NewtonOptions(solver_tol=1e-12, progress=lines.append)))
    assert lines and all(line.startswith("newton ") for line in lines)
    with pytest.raises(ndf.TimeLimitError, match="semismooth Newton"):
        fixed_point(disc, contact, FixedPointOptions(inner=NewtonOptions(max_seconds=1e-9)))
    assert FixedPointOptions(solver_tol=1e-11).inner_options == NewtonOptions(solver_tol=1e-11)
    assert FixedPointOptions(inner=UzawaOptions(rho=0.5)).inner_options == UzawaOptions(rho=0.5)
    with pytest.raises(ValueError, match="inner must be None, NewtonOptions or UzawaOptions"):
        FixedPointOptions(inner="newton")
