"""Shared fixtures: a manufactured linear-elasticity problem with no contact."""

import ngsolve as ngs
import pytest

import ngdgfric as ndf
from ngdgfric.forms import strain, stress


def manufactured_elasticity(E=1000.0, nu=0.3):
    """Smooth u with u = 0 on Gamma_D = {x = 1} and sigma(u) n = 0 on Gamma_C = {y = 0}.

    u = y^2 (1 - x) (sin(x + y), cos(2x - y)): every strain component carries y, so sigma = 0
    on y = 0; with c_tau = 0 and a gap g_a = 1 larger than |u_n| the contact terms vanish and
    u solves (1.5)-(1.9) with f = -div sigma(u) and g = sigma(u) n on Gamma_F (left and top).
    Returns (problem, u_exact).
    """
    x, y = ngs.x, ngs.y
    u = ngs.CF((y**2 * (1 - x) * ngs.sin(x + y), y**2 * (1 - x) * ngs.cos(2 * x - y)))
    geometry = ndf.Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="dirichlet",
                                     top="traction", left="traction")
    base = ndf.ContactProblem(E=E, nu=nu, f=(0, 0), g=(0, 0), c_n=1.0, m_n=1, g_a=1.0, c_tau=0.0,
                              geometry=geometry)
    sigma = stress(base, strain_of(u))
    f = -ngs.CF((sigma[0, 0].Diff(x) + sigma[0, 1].Diff(y), sigma[1, 0].Diff(x) + sigma[1, 1].Diff(y)))
    g = sigma * ngs.specialcf.normal(2)
    import dataclasses
    return dataclasses.replace(base, f=f, g=g), u


def strain_of(u):
    """eps(u) of a CoefficientFunction of x, y."""
    x, y = ngs.x, ngs.y
    grad = ngs.CF((u[0].Diff(x), u[0].Diff(y), u[1].Diff(x), u[1].Diff(y)), dims=(2, 2))
    return 0.5 * (grad + grad.trans)


@pytest.fixture(scope="session")
def elasticity():
    return manufactured_elasticity()


__all__ = ["manufactured_elasticity", "strain_of", "strain"]
