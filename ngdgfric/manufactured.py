"""Smooth manufactured solutions: f and g from a chosen u, for convergence and locking studies."""

import dataclasses

import ngsolve as ngs

from .forms import stress
from .problem import ContactProblem, Polygon

__all__ = ["strain_of", "body_force_and_traction", "elasticity_manufactured"]


def _grad(u):
    x, y = ngs.x, ngs.y
    return ngs.CF((u[0].Diff(x), u[0].Diff(y), u[1].Diff(x), u[1].Diff(y)), dims=(2, 2))


def strain_of(u):
    """eps(u) of a CoefficientFunction of x, y."""
    g = _grad(u)
    return 0.5 * (g + g.trans)


def body_force_and_traction(problem, u):
    """f = -div sigma(u) and g = sigma(u) n for a smooth CoefficientFunction u."""
    x, y = ngs.x, ngs.y
    sigma = stress(problem, strain_of(u))
    f = -ngs.CF((sigma[0, 0].Diff(x) + sigma[0, 1].Diff(y), sigma[1, 0].Diff(x) + sigma[1, 1].Diff(y)))
    return f, sigma * ngs.specialcf.normal(2)


def elasticity_manufactured(E=1000.0, nu=0.3):
    """Smooth u with u = 0 on Gamma_D = {x = 1} and sigma(u) n = 0 on Gamma_C = {y = 0}.

    u = y^2 (1 - x) (sin(x + y), cos(2x - y)): every strain component carries y, so sigma = 0
    on y = 0; with c_tau = 0 and a gap g_a = 1 larger than |u_n| the contact terms vanish and
    u solves (1.5)-(1.9) (linear elasticity) with f = -div sigma(u) and g = sigma(u) n on Gamma_F.
    """
    x, y = ngs.x, ngs.y
    u = ngs.CF((y**2 * (1 - x) * ngs.sin(x + y), y**2 * (1 - x) * ngs.cos(2 * x - y)))
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="dirichlet", top="traction",
                                     left="traction")
    base = ContactProblem(E=E, nu=nu, f=(0, 0), g=(0, 0), c_n=1.0, m_n=1, g_a=1.0, c_tau=0.0,
                              geometry=geometry)
    f, g = body_force_and_traction(base, u)
    return dataclasses.replace(base, f=f, g=g), u
