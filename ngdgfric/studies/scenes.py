r"""Scenes a user writes every day, beyond the paper's two rectangles.

Studied by ``scripts/scenes.py`` (the results page *User scenes*). Each ``Scene`` is a problem, a family of meshes
and what its answer is measured against: an exact solution (``exact``, a CoefficientFunction of :math:`x, y`) or,
where none is known, a reference solution computed by hp-adaptive SIPG far beyond the accuracy studied
(``exact=None``).

The exact solutions of the layered scenes are piecewise linear: a block on :math:`(0, 1)^2` with :math:`\nu = 0`
and :math:`E = E_0` below :math:`y = c`, :math:`E_1` above (or left and right of :math:`x = c`), in uniaxial
stress.  With :math:`L = \int_0^1 ds / E(s)` (a series of springs):

* ``layers_pressure``: fixed at the bottom, a pressure :math:`p` on top,
  :math:`u = (0, -p \int_0^y ds / E)`; :math:`\Gamma_C` (the left side, a gap of 1, no friction) stays open.
* ``layers_indented``: fixed at the bottom and pushed down at the top by a rigid plane that penetrates it by
  :math:`d` (:math:`g_a = -d`: no loads, :math:`f = 0`, :math:`g = 0`), compliance :math:`c_n`, :math:`m_n = 1`,
  friction :math:`c_\tau`: the contact pressure :math:`P` solves :math:`P = c_n (d - P L)`,
  :math:`u = (0, -P \int_0^y ds / E)`; the top sticks (:math:`u_\tau = 0`, :math:`\sigma_\tau = 0`).
* ``columns``: fixed on the left, pulled by :math:`-p` on the right, :math:`E = E_0` left of :math:`x = c`,
  :math:`E_1` right of it: :math:`u = (-p \int_0^x ds / E, 0)`.

Traction data are :math:`\sigma(u) n` of the exact solution (``g = sigma n`` with NGSolve's normal), so one
:math:`g` serves every traction side.  Every consistent method reproduces these solutions to round-off on a mesh
whose edges follow the jump (:math:`c = 1/2` on the meshes :math:`h = 2^{-k}`), and converges like
:math:`h^{1/2}` where the jump cuts elements (:math:`c = 1/3`: ``layers_indented`` with ``c=1/3``).
"""

import dataclasses
import math
from collections.abc import Callable

import ngsolve as ngs

from ..meshes import netgen_mesh, uniform_mesh
from ..output import tex_number
from ..problem import ContactProblem, Polygon
from .manufactured import incompressible_contact_manufactured

__all__ = ["Scene", "layers_pressure", "layers_indented", "columns", "l_shape", "hertz", "incompressible",
           "strip", "wedge", "SCENES", "hertz_solution"]


@dataclasses.dataclass(frozen=True)
class Scene:
    """A user's problem: ``problem``, ``mesh(k)`` the k-th mesh of a refinement family (k = 0, 1, ...,
    each with two to four times the elements of the last), ``exact`` (a CoefficientFunction, or None: measured
    against a reference), ``description`` (one line) and ``levels`` (how many meshes a study uses)."""

    name: str
    description: str
    problem: ContactProblem
    mesh: Callable
    exact: object = None
    levels: int = 4


def _jump(coordinate, c, low, high):
    """E = low below / left of ``coordinate`` = c, high above / right of it."""
    return ngs.IfPos(coordinate - c, high, low)


def _series(coordinate, c, low, high):
    """int_0^coordinate ds / E(s) for the E of :func:`_jump`."""
    return ngs.IfPos(coordinate - c, c / low + (coordinate - c) / high, coordinate / low)


def _uniform(problem, first=2):
    return lambda k: uniform_mesh(problem, 2.0 ** -(first + k))


def layers_pressure(c=0.5, E0=1.0, E1=100.0, p=1.0):
    """The block of the module docstring fixed at the bottom under a pressure p on top (the issue's scene)."""
    n = ngs.specialcf.normal(2)
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="dirichlet", right="traction", top="traction", left="contact")
    problem = ContactProblem(E=_jump(ngs.y, c, E0, E1), nu=0.0, f=(0, 0), g=ngs.CF((0, -p * n[1])), c_n=1.0, m_n=1,
                             g_a=1.0, c_tau=0.0, geometry=geometry, name="layers under pressure")
    exact = ngs.CF((0, -p * _series(ngs.y, c, E0, E1)))
    return Scene("layers-pressure", f"$E = {E0:g}$ / ${E1:g}$ below / above $y = {c:g}$, $\\nu = 0$, pressure on top",
                 problem, _uniform(problem), exact)


def layers_indented(c=0.5, E0=1.0, E1=100.0, c_n=10.0, d=0.01, c_tau=1.0):
    """The block of the module docstring pushed by a rigid plane penetrating its top by d (no loads)."""
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="dirichlet", right="traction", top="contact", left="traction")
    problem = ContactProblem(E=_jump(ngs.y, c, E0, E1), nu=0.0, f=(0, 0), g=(0, 0), c_n=c_n, m_n=1, g_a=-d,
                             c_tau=c_tau, geometry=geometry, name="layers indented")
    pressure = c_n * d / (1 + c_n * (c / E0 + (1 - c) / E1))
    exact = ngs.CF((0, -pressure * _series(ngs.y, c, E0, E1)))
    if math.isclose(c * 1024, round(c * 1024)):
        return Scene("layers-indented", f"$E = {E0:g}$ / ${E1:g}$ below / above $y = {c:g}$, loaded by a "
                     f"penetration $d = {d:g}$ only", problem, _uniform(problem, first=1), exact)
    # h = 2^-1, 2^-3, 2^-5: y = c cuts its row of elements at the same fraction on each (c = 1/3: 2/3), so the
    # error falls steadily, like h^(1/2) (on h = 2^-k the fraction alternates and so does the error)
    return Scene("layers-cut", f"$E = {E0:g}$ / ${E1:g}$ below / above $y = {c:.4g}$, a jump that cuts "
                 f"elements, loaded by a penetration $d = {d:g}$ only", problem,
                 lambda k: uniform_mesh(problem, 2.0 ** -(1 + 2 * k)), exact, levels=3)


def columns(c=0.5, E0=1.0, E1=100.0, p=1.0):
    """Fixed on the left, pulled by a traction -p on the right; E jumps at x = c (the issue's Brezzi case)."""
    n = ngs.specialcf.normal(2)
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="traction", top="traction", left="dirichlet")
    problem = ContactProblem(E=_jump(ngs.x, c, E0, E1), nu=0.0, f=(0, 0), g=ngs.CF((-p * n[0], 0)), c_n=1.0, m_n=1,
                             g_a=1.0, c_tau=0.0, geometry=geometry, name="columns")
    exact = ngs.CF((-p * _series(ngs.x, c, E0, E1), 0))
    return Scene("columns", f"$E = {E0:g}$ / ${E1:g}$ left / right of $x = {c:g}$, $\\nu = 0$, compressed from the "
                 "right", problem, _uniform(problem), exact)


def l_shape(E=1000.0, nu=0.3, c_n=1e4, c_tau=5.0, weight=10.0, pressure=5.0):
    """An L-shaped body hanging from its top (Gamma_D) under its weight, pressed sideways by a pressure on
    the other sides, resting on a compliant foundation with friction (Gamma_C, the bottom): a re-entrant
    corner at (1, 1), contact, stick and slip."""
    n = ngs.specialcf.normal(2)
    geometry = Polygon(((0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)),
                       ("contact", "traction", "traction", "traction", "dirichlet", "traction"))
    problem = ContactProblem(E=E, nu=nu, f=(0, -weight), g=-pressure * n, c_n=c_n, m_n=1, g_a=0.0, c_tau=c_tau,
                             geometry=geometry, name="L-shape")
    return Scene("l-shape", "re-entrant corner (L-shaped body), weight, pressure, friction",
                 problem, lambda k: netgen_mesh(problem, 0.5 * 2.0**-k))


def hertz(E=1.0, nu=0.3, radius=1.0, depth=0.005, c_n=1e3):
    """A block (-1, 1) x (0, 1) clamped on top and indented from below by a rigid cylinder of ``radius``
    pushed up by ``depth``: g_a(x) = -depth + x^2 / (2 radius), no friction, no loads; compared with Hertz
    theory (:func:`hertz_solution`) for the total force it transmits."""
    geometry = Polygon.rectangle(-1, 0, 1, 1, bottom="contact", right="traction", top="dirichlet", left="traction")
    problem = ContactProblem(E=E, nu=nu, f=(0, 0), g=(0, 0), c_n=c_n, m_n=1, g_a=-depth + ngs.x**2 / (2 * radius),
                             c_tau=0.0, geometry=geometry, name="Hertz")
    return Scene("hertz", f"block on a rigid cylinder, $g_a = -{depth:g} + x^2 / {2 * radius:g}$ (Hertz)",
                 problem, lambda k: uniform_mesh(problem, 2.0 ** -(3 + k)))


def hertz_solution(force, E, nu, radius):
    """Hertz's line contact of a rigid cylinder on an elastic half-space in plane strain (Johnson, Contact
    Mechanics, 1985, Section 4.2): half-width a = (4 P R / (pi E*))^(1/2), E* = E / (1 - nu^2), peak
    pressure p0 = 2 P / (pi a), pressure p(x) = p0 (1 - x^2 / a^2)^(1/2).  Returns (a, p0)."""
    modulus = E / (1 - nu**2)
    a = math.sqrt(4 * force * radius / (math.pi * modulus))
    return a, 2 * force / (math.pi * a)


def incompressible(nu=0.4999, E=1000.0):
    """The divergence-free contact solution of
    :func:`ngdgfric.studies.manufactured.incompressible_contact_manufactured` at nu = 0.4999."""
    problem, exact = incompressible_contact_manufactured(E=E, nu=nu)
    return Scene("incompressible", f"nearly incompressible ($\\nu = {nu:g}$), divergence-free exact solution",
                 dataclasses.replace(problem, name="nearly incompressible"), _uniform(problem, first=1), exact)


def strip(E0=1e3, E1=1e5, c_n=1e6, m_n=2.0, c_tau=10.0, m_t=1.0, pressure=100.0):
    """A strip (0, 8) x (0, 1) fixed on the left, E = E0 / E1 on its halves, pressed onto a stiff compliant
    foundation (c_n, m_n) with the penetration-dependent friction bound c_tau (u_n - g_a)_+^{m_t}."""
    n = ngs.specialcf.normal(2)
    geometry = Polygon.rectangle(0, 0, 8, 1, bottom="contact", right="traction", top="traction", left="dirichlet")
    problem = ContactProblem(E=_jump(ngs.x, 4.0, E0, E1), nu=0.3, f=(0, 0), g=-pressure * n, c_n=c_n, m_n=m_n,
                             g_a=0.0, c_tau=c_tau, m_t=m_t, geometry=geometry, name="bimaterial strip")
    return Scene("strip-mt", f"strip $8 \\times 1$, $E = {E0:g}$ / ${E1:g}$, $c_n = {tex_number(c_n)}$, "
                 f"$m_n = {m_n:g}$, $c_\\tau = {c_tau:g}$, $m_t = {m_t:g}$", problem,
                 lambda k: uniform_mesh(problem, 2.0 ** -(1 + k)), levels=3)


def wedge(angle=6.6, E=1000.0, nu=0.3, pressure=10.0):
    """A wedge with a tip angle of ``angle`` degrees on a compliant foundation (Gamma_C, its bottom), fixed at
    its thick end and pressed by a pressure on its top: Netgen meshes with triangles as thin as the tip."""
    n = ngs.specialcf.normal(2)
    top = 2 * math.tan(math.radians(angle))
    geometry = Polygon(((0, 0), (2, 0), (2, top)), ("contact", "dirichlet", "traction"))
    problem = ContactProblem(E=E, nu=nu, f=(0, 0), g=-pressure * n, c_n=1e4, m_n=1, g_a=0.0, c_tau=1.0,
                             geometry=geometry, name="thin wedge")
    return Scene("wedge", f"wedge with a {angle:g} degree tip, Netgen meshes with {angle:g} degree triangles",
                 problem, lambda k: netgen_mesh(problem, 0.25 * 2.0**-k))


SCENES = {scene.__name__: scene for scene in (layers_pressure, layers_indented, columns, l_shape, hertz,
                                               incompressible, strip, wedge)}
"""The scene factories by name; ``layers_indented(c=1/3)`` is the scene with a jump that cuts elements."""
