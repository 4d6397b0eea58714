"""Solver options: one frozen dataclass per solver; bad options raise a ValueError naming them before assembly."""

import dataclasses

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.solvers.fixed_point import FixedPointOptions
from ngdgfric.solvers.newton import NewtonOptions
from ngdgfric.solvers.uzawa import UzawaOptions


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
    assert FixedPointOptions.from_keywords().inner == NewtonOptions(solver_tol=1e-8)


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
