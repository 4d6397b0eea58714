r"""Hertz's contact of two elastic cylinders: two bodies, a contact pair, load control.

The scene (``two_cylinders``): quarter disks of radii :math:`R_1` (below, centre :math:`(0, -R_1)`) and
:math:`R_2` (above, centre :math:`(0, R_2)`) touching at the origin, plane strain, materials
:math:`E_1, \nu_1` and :math:`E_2, \nu_2`.  The lower body stands on its flat side (u = 0); the upper one has no
Dirichlet side: a uniform pressure on its flat top transmits the force :math:`P/2` (the half of the force
:math:`P` per unit length on the whole cylinders), the symmetry sides :math:`x = 0` hold both bodies
horizontally, and only the contact holds the upper body vertically (:mod:`ngdgfric.solvers.floating`).  The pair
"arc2" (the upper arc) against "arc1": frictionless, :math:`m_n = 1`, the gap from the geometry.

Hertz (Johnson, *Contact Mechanics*, 1985, Section 4.2, two cylinders with parallel axes):

.. math::

    a = \Big(\frac{4 P R}{\pi E^*}\Big)^{1/2}, \qquad p_0 = \frac{2 P}{\pi a}, \qquad
    \frac{1}{R} = \frac{1}{R_1} + \frac{1}{R_2}, \qquad
    \frac{1}{E^*} = \frac{1 - \nu_1^2}{E_1} + \frac{1 - \nu_2^2}{E_2}.

The compliance :math:`c_n` is stiff: its share of the approach, :math:`p_0 / c_n`, is compared in
``measures`` with the elastic approach in the contact zone (``compliance_share``).
"""

import math

import numpy as np

from ..contact.pair_state import pair_state
from ..domain import Domain, Loop
from ..problem import ContactPair, ContactProblem

__all__ = ["two_cylinders", "hertz_cylinders", "pair_profile", "plot_pressure", "measures", "DEFAULTS"]

DEFAULTS = dict(R1=1.0, R2=0.5, E1=1.0, nu1=0.3, E2=2.0, nu2=0.2, a=0.02, c_n=1e5)
"""The scene of ``results/two_cylinders.md``: the radii, the materials, the Hertz half-width a the force is chosen
for (a / R = 0.06 with R the combined radius), the compliance."""


def _combined(R1, R2, E1, nu1, E2, nu2):
    """Hertz's combined radius R and modulus E* of two cylinders (module docstring)."""
    return 1.0 / (1.0 / R1 + 1.0 / R2), 1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2)


def hertz_cylinders(P, R1, R2, E1, nu1, E2, nu2):
    """Hertz's half-width a and peak pressure p0 of two cylinders pressed by the force P per unit length (module
    docstring), and the combined R and E*: a dict."""
    R, E_star = _combined(R1, R2, E1, nu1, E2, nu2)
    a = math.sqrt(4.0 * P * R / (math.pi * E_star))
    return dict(a=a, p0=2.0 * P / (math.pi * a), R=R, E_star=E_star)


def two_cylinders(R1=DEFAULTS["R1"], R2=DEFAULTS["R2"], E1=DEFAULTS["E1"], nu1=DEFAULTS["nu1"], E2=DEFAULTS["E2"],
                  nu2=DEFAULTS["nu2"], a=DEFAULTS["a"], c_n=DEFAULTS["c_n"]):
    """The two quarter cylinders of the module docstring, pressed by the force P that gives Hertz's half-width
    ``a``: (ContactProblem, P)."""
    R, E_star = _combined(R1, R2, E1, nu1, E2, nu2)
    P = a**2 * math.pi * E_star / (4.0 * R)
    c = 1.0 / math.sqrt(2.0)
    upper = Loop([(0.0, 0.0), (R2, R2), (0.0, R2)], ("arc2", "top", "axis2"), arcs={0: (R2 * c, R2 * (1 - c))})
    lower = Loop([(0.0, -R1), (R1, -R1), (0.0, 0.0)], ("bottom", "arc1", "axis1"),
                 arcs={1: (R1 * c, -R1 * (1 - c))})
    problem = ContactProblem(
        E={"lower": E1, "upper": E2}, nu={"lower": nu1, "upper": nu2}, f=(0.0, 0.0), g={"top": (0.0, -P / 2 / R2)},
        c_n=0.0, m_n=1, g_a=0.0, c_tau=0.0, geometry=Domain({"lower": lower, "upper": upper}), dirichlet="bottom",
        symmetry=("axis1", "axis2"), traction="top", contact=(), pairs=[ContactPair("arc2", "arc1", c_n=c_n)],
        name=f"two cylinders: R1 = {R1:g}, R2 = {R2:g}, E {E1:g} / {E2:g}, nu {nu1:g} / {nu2:g}, P = {P:.4g}")
    return problem, P


def pair_profile(sol, index=0):
    """Along pair ``index`` of a Solution, at its points sorted by x: ``x``, ``penetration`` [u] . n - g and
    ``pressure`` (the normal force over the point's weight) of :func:`ngdgfric.pair_state`, a dict of arrays."""
    state = pair_state(sol)[index]
    order = np.argsort(state["x"], kind="stable")
    return {name: state[name][order] for name in ("x", "penetration", "pressure")}


def plot_pressure(ax, sol, P, **scene):
    """Draw the pressure along the pair of a Solution of :func:`two_cylinders` (its points up to 2 a) against
    Hertz's ellipse p0 (1 - x^2 / a^2)^(1/2), both over Hertz's a and p0."""
    values = {**DEFAULTS, **scene}
    hertz = hertz_cylinders(P, values["R1"], values["R2"], values["E1"], values["nu1"], values["E2"], values["nu2"])
    a, p0 = hertz["a"], hertz["p0"]
    profile = pair_profile(sol)
    near = profile["x"] <= 2.0 * a
    x = np.linspace(0.0, 1.0, 200)
    ax.plot(x, np.sqrt(1.0 - x**2), "k-", label="Hertz")
    ax.plot(profile["x"][near] / a, profile["pressure"][near] / p0, ".", ms=3, label="ngdgfric (pair points)")
    ax.set_xlabel("x / a (Hertz)")
    ax.set_ylabel("pressure / p0 (Hertz)")
    ax.legend()


def measures(sol, P, **scene):
    """The contact of a Solution of :func:`two_cylinders` against Hertz: a dict with the half-width ``a`` (where
    the penetration changes sign, the zero of the straight line between the two points around it), the peak
    pressure ``p_max``, the normal resultant ``F`` (the pair's normal forces; P / 2 for the quarter model), Hertz's
    ``a_H`` and ``p0_H`` and the relative differences ``a_error``, ``p_error``; ``compliance_share``: the
    compliance's approach p_max / c_n over the elastic approach of the contact zone, a^2 / (2 R)."""
    values = {**DEFAULTS, **scene}
    hertz = hertz_cylinders(P, values["R1"], values["R2"], values["E1"], values["nu1"], values["E2"], values["nu2"])
    profile = pair_profile(sol)
    x, penetration = profile["x"], profile["penetration"]
    inside = np.flatnonzero(penetration > 0)
    last = inside[-1]
    a = x[last] + (x[last + 1] - x[last]) * penetration[last] / (penetration[last] - penetration[last + 1])
    p_max = float(profile["pressure"].max())
    return dict(a=float(a), p_max=p_max, F=float(np.sum(np.asarray(sol.info["pair_forces"])[0])), a_H=hertz["a"],
                p0_H=hertz["p0"], a_error=float(a) / hertz["a"] - 1.0, p_error=p_max / hertz["p0"] - 1.0,
                compliance_share=p_max / values["c_n"] / (hertz["a"] ** 2 / (2.0 * hertz["R"])))
