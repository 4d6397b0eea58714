"""Bad solver options: a ValueError naming the option, raised before anything is assembled."""

import pytest

import ngdgfric as ndf


@pytest.mark.parametrize("options, name", [
    (dict(maxit=0), "maxit"), (dict(maxit=2.5), "maxit"), (dict(tol=-1.0), "tol"), (dict(tol=float("nan")), "tol"),
    (dict(solver="uzawa", rho=-1.0), "rho"), (dict(solver="uzawa", rho=0.0), "rho"), (dict(c0=-1), "c0"),
    (dict(linear_solver="mumps"), "linear_solver"), (dict(progress=3), "progress"),
    (dict(solver="uzawa", linear_solver="pardiso"), "linear_solver"), (dict(solver="fixed_point", inner="x"), "inner"),
    (dict(solver="uzawa", kkt_tol=0.0), "kkt_tol"),
])
def test_bad_option_is_named_before_assembly(options, name):
    with pytest.raises(ValueError, match=name):
        ndf.solve(ndf.example_6_1(), mesh=None, **options)  # no mesh needed: the option is checked first


def test_fixed_point_rejects_options_of_the_other_inner_solver():
    p = ndf.example_6_1()
    with pytest.raises(ValueError, match="rho"):
        ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), solver="fixed_point", inner="newton", rho=1.0)
