r"""Curved boundaries: Hertz's line contact on a half-disk, and convergence rates on an annulus.

Hertz (the script ``scripts/hertz.py``, the results page *Hertz's line contact on a curved half-disk*): the
half-disk of radius :math:`R`, centre :math:`(0, R)`, below its diameter, pressed onto the rigid plane :math:`y = 0`
by a prescribed displacement :math:`u_D = (0, -\delta)` of its flat top (``hertz_problem``). :math:`\Gamma_C` is the
lower half circle, with the outward normal :math:`n = (x, y - R) / R`; the normal ray from a point :math:`(x, y)` of
the circle meets the plane after the length

.. math::

    g_a = \frac{y R}{R - y}

(``hertz_gap``), the initial gap of (1.8).  Frictionless (:math:`c_\tau = 0`), :math:`m_n = 1`, a stiff
compliance :math:`c_n`: the Signorini problem is the limit :math:`c_n \to \infty`.  ``hertz_measures`` compares
the discrete contact with Hertz's line contact of a cylinder on a half-space in plane strain (``hertz_solution``
of :mod:`ngdgfric.studies.scenes`) for the force :math:`F` the solution transmits: half-width
:math:`a = (4 F R / (\pi E^*))^{1/2}`, :math:`E^* = E / (1 - \nu^2)`, peak pressure :math:`p_0 = 2 F / (\pi a)`.
``discrete_energy`` is the energy :math:`J_h` that the discrete solution minimises (SIPG and the symmetric lifting
methods, :math:`m_t = 0`), so that :math:`2 (J_h(u_h) - J_h(u_\mathrm{ref}))` measures the squared energy error
against a much finer reference :math:`u_\mathrm{ref}` of the same problem (asymptotically: the penalties of
:math:`J_h` and :math:`J_{h_\mathrm{ref}}` differ on the edges :math:`u_h` jumps across, so the difference is not
a norm on coarse meshes; ``reference_error`` measures :math:`\|u_h - u_\mathrm{ref}\|_h` directly).  ``sides``:
the same problem on an inscribed polygon (straight sides, the same data).

Rates (the script ``scripts/curved_rates.py``): the smooth manufactured solution of ``annulus_problem`` on the
annulus :math:`r_i < r < 1` (:math:`\Gamma_D` the upper half of the outer circle, :math:`\Gamma_F` its lower half,
:math:`\Gamma_C` the inner circle, where :math:`\sigma(u) n = 0` and the gap is too large for contact), and the
same construction on the unit square (``square_problem``); ``uniform_meshes`` refines a Netgen mesh uniformly
(new boundary points on the circles), ``inscribed`` rebuilds such a mesh with straight boundary edges (the domain
becomes the inscribed polygons: no curving).
"""

import dataclasses
import math

import ngsolve as ngs
import numpy as np

from ..contact.forms import compliance, penetration
from ..contact.laws import compliance_energy_values, friction_energy_values
from ..contact.state import contact_state
from ..domain import Domain, Loop
from ..meshes import mesh_arrays, mesh_from_arrays, refine
from ..problem import ContactProblem, Polygon, coefficient, is_number, strain, strain_of, stress
from ..reference import energy_norm_squared_parts
from .scenes import hertz_solution

__all__ = ["half_disk", "hertz_gap", "hertz_problem", "contact_profile", "contact_force", "half_width",
           "hertz_measures", "discrete_energy", "reference_error", "fit_exponential", "fit_algebraic",
           "annulus", "annulus_problem", "square_problem", "manufactured_loads", "uniform_meshes", "inscribed"]


# ---------------------------------------------------------------------------------------------------------------
# Hertz: a half-disk on a rigid plane
# ---------------------------------------------------------------------------------------------------------------


def half_disk(radius=1.0, sides=None):
    """The half-disk of ``radius`` R, centre (0, R), below its diameter: side "contact" the lower half circle
    from (-R, R) through (0, 0) to (R, R), side "dirichlet" the diameter.  ``sides``: None for the exact arc (a
    Domain: curved elements), or an even number of straight sides inscribed in the arc (a Polygon whose
    vertices lie on the circle, (0, 0) one of them)."""
    R = float(radius)
    if sides is None:
        return Domain(regions={"omega": Loop([(-R, R), (R, R)], ("contact", "dirichlet"), arcs={0: (0.0, 0.0)})})
    if sides < 2 or sides % 2:
        raise ValueError(f"sides must be an even number >= 2, got {sides!r}")
    angles = math.pi * (1 + np.arange(sides + 1) / sides)
    vertices = np.column_stack([R * np.cos(angles), R + R * np.sin(angles)])
    vertices[[0, sides // 2, sides]] = [(-R, R), (0.0, 0.0), (R, R)]  # exact where the formulas round
    return Polygon([tuple(v) for v in vertices], ("contact",) * sides + ("dirichlet",))


def hertz_gap(radius=1.0):
    """g_a = y R / (R - y) (module docstring), clipped to R above y = R / 2 (far from any contact), so that it
    stays finite at the ends (+-R, R) of the arc."""
    R = float(radius)
    return ngs.IfPos(ngs.y - R / 2, R, ngs.y * R / (R - ngs.y))


def hertz_problem(delta, c_n, E=1.0, nu=0.3, radius=1.0, sides=None):
    """The half-disk (:func:`half_disk`, ``sides`` straight sides or the exact arc) pushed down by u_D = (0, -delta)
    onto the plane y = 0: no loads, frictionless, m_n = 1, compliance ``c_n``, gap :func:`hertz_gap`."""
    shape = "half-disk" if sides is None else f"half-disk as a {sides}-sided polygon"
    return ContactProblem(E=E, nu=nu, f=(0.0, 0.0), g=(0.0, 0.0), c_n=c_n, m_n=1, g_a=hertz_gap(radius), c_tau=0.0,
                          geometry=half_disk(radius, sides), u_D=(0.0, -float(delta)),
                          name=f"Hertz: {shape}, R = {radius:g}, delta = {delta:g}, c_n = {c_n:g}")


def contact_profile(sol, per_edge=33):
    """x, y, the penetration ``gap`` = u_n - g_a and the ``pressure`` c_n (u_n - g_a)_+^{m_n} of a Solution at
    ``per_edge`` equispaced points (ends included) of every edge of Gamma_C, on the (curved) edges themselves
    (the element mapping), sorted by x (the ends of neighbouring edges appear twice: u_h is discontinuous)."""
    problem, mesh = sol.discretization.problem, sol.mesh
    s = np.linspace(0.0, 1.0, per_edge)
    rule = ngs.IntegrationRule(points=[(float(t),) for t in s], weights=[1.0 / per_edge] * per_edge)
    points = mesh.MapToAllElements({ngs.SEGM: rule}, mesh.Boundaries(problem.where("contact")))

    def values(cf):
        return np.asarray(ngs.BoundaryFromVolumeCF(cf)(points)).ravel()

    x, y = np.asarray(ngs.x(points)).ravel(), np.asarray(ngs.y(points)).ravel()
    order = np.argsort(x, kind="stable")
    return dict(x=x[order], y=y[order], gap=values(penetration(problem, sol.u))[order],
                pressure=values(compliance(problem, sol.u))[order])


def contact_force(sol):
    """(F, F_n): the vertical force sum_q omega_q p_q (-n_y)(x_q) the plane exerts on the body, and the integral
    sum_q omega_q p_q of the contact pressure p = c_n (u_n - g_a)_+^{m_n}, both with the discrete contact rule
    (Gauss points x_q, weights omega_q of the curved edges, ``sol.contact.traces.omega``)."""
    state = contact_state(sol)
    normal = np.asarray(ngs.specialcf.normal(2)(sol.contact.points())).reshape(-1, 2)
    omega = sol.contact.traces.omega
    return float(np.sum(omega * state["pressure"] * -normal[:, 1])), float(np.sum(omega * state["pressure"]))


def half_width(x, gap):
    """(a, x_left, x_right): the ends of the contact zone {gap > 0} along sorted points x, each the zero of the
    straight line through the last point out of contact and the first in contact (x_left) or the last in contact
    and the first out of it (x_right), and a = (x_right - x_left) / 2; NaNs if nothing is in contact.  ValueError
    if the contact reaches an end of the points."""
    x, gap = np.asarray(x, dtype=float), np.asarray(gap, dtype=float)
    inside = np.flatnonzero(gap > 0)
    if inside.size == 0:
        return math.nan, math.nan, math.nan
    if inside[0] == 0 or inside[-1] == len(x) - 1:
        raise ValueError("the contact zone reaches the end of Gamma_C")

    def zero(i, j):
        return x[i] + (x[j] - x[i]) * gap[i] / (gap[i] - gap[j])

    left, right = zero(inside[0] - 1, inside[0]), zero(inside[-1], inside[-1] + 1)
    return 0.5 * (right - left), left, right


def hertz_measures(sol, per_edge=33):
    """The contact of a Solution of ``hertz_problem`` against Hertz for the force it transmits, a dict:
    F (vertical force, :func:`contact_force`), F_n (integral of the pressure), a (half-width where u_n - g_a
    changes sign, :func:`half_width` on :func:`contact_profile`), x_left, x_right, p0 (pressure at x = 0: the mean
    of the two edges meeting there), p_max, x_p_max, the gaps the contact zone holds inside (``holes``, 0 if it
    is one interval), Hertz's a_hertz and p0_hertz for F, the relative differences rel_a, rel_p0, and
    profile = max |p(x) - p_Hertz(x)| / p0_hertz along Gamma_C."""
    problem = sol.discretization.problem
    x0, _, x1, _ = problem.geometry.bounds
    R = 0.5 * float(x1 - x0)
    F, F_n = contact_force(sol)
    a_hertz, p0_hertz = hertz_solution(F, float(problem.E), float(problem.nu), R)
    prof = contact_profile(sol, per_edge)
    x, gap, pressure = prof["x"], prof["gap"], prof["pressure"]
    a, left, right = half_width(x, gap)
    inside = np.flatnonzero(gap > 0)
    at_zero = np.abs(x) <= 1e-12 * R
    p0 = float(np.mean(pressure[at_zero])) if at_zero.any() else float(np.interp(0.0, x, pressure))
    hertz_profile = p0_hertz * np.sqrt(np.clip(1 - (x / a_hertz) ** 2, 0, None))
    return dict(F=F, F_n=F_n, a=a, x_left=left, x_right=right, p0=p0, p_max=float(pressure.max()),
                x_p_max=float(x[np.argmax(pressure)]),
                holes=int(np.count_nonzero(gap[inside[0]:inside[-1]] <= 0)) if inside.size else 0,
                a_hertz=a_hertz, p0_hertz=p0_hertz, rel_a=a / a_hertz - 1, rel_p0=p0 / p0_hertz - 1,
                profile=float(np.max(np.abs(pressure - hertz_profile)) / p0_hertz))


def _constant(u_D):
    """Whether a prescribed displacement is given as a pair of numbers."""
    return isinstance(u_D, (tuple, list)) and all(is_number(c) for c in u_D)


def discrete_energy(sol):
    """J_h(u_h) = 1/2 B_h(u_h, u_h) - F_h(u_h) + C_D + sum_q omega_q [c_n / (m_n + 1) (u_n - g_a)_+^{m_n + 1}
    + c_tau |u_tau|](x_q): the energy whose minimiser over V_h is the discrete solution of (3.1) for a symmetric
    method and m_t = 0 (its derivative is the residual of :func:`ngdgfric.contact.forms.residual`).  C_D = 1/2 B_h(w, w)
    for w = u_D is the constant that makes J_h(u) the energy of the continuous problem at the exact u (the
    penalty on Gamma_D of u_D itself, which grows under refinement); u_D must be constant (then w lies in V_h, has
    no strain, and F_h = B_h(w, .) + loads), and J_h = 1/2 B_h(u_h - w, u_h - w) + (B_h(w, .) - F_h)(u_h) + contact
    is computed so.  For the exact u and u_h, 2 (J_h(u_h) - J(u)) = B_h(u - u_h, u - u_h) + 2 (convex remainder
    of the contact terms) ~ |||u - u_h|||_h^2."""
    disc = sol.discretization
    problem = disc.problem
    if not disc.symmetric or problem.m_t != 0:
        raise ValueError("the discrete problem minimises an energy for symmetric methods and m_t = 0 only")
    if not _constant(problem.u_D):
        raise ValueError("discrete_energy needs a constant u_D (a pair of numbers)")
    A, F = disc.A, disc.F
    w = ngs.GridFunction(disc.V)
    w.Set(coefficient(problem.u_D))
    d, Ad, residual = F.CreateVector(), F.CreateVector(), F.CreateVector()
    d.data = sol.u.vec - w.vec
    Ad.data = A * d
    residual.data = A * w.vec - F
    state, traces = contact_state(sol), sol.contact.traces
    contact = np.sum(traces.omega * (compliance_energy_values(state["gap"], traces.c_n, problem.m_n)
                                     + friction_energy_values(traces.c_tau, state["u_tau"])))
    return 0.5 * ngs.InnerProduct(d, Ad) + ngs.InnerProduct(residual, sol.u.vec) + float(contact)


def _found(mesh, xy, centres):
    """Mapped points of ``mesh`` at xy (k, 2); points the search misses (outside a curved boundary by round-off)
    are moved towards ``centres`` (k, 2) by 1e-9, 1e-7 ... of the distance until found."""
    points = mesh(xy[:, 0], xy[:, 1])
    missing = np.flatnonzero(points["nr"] < 0)
    for step in (1e-9, 1e-7, 1e-5, 1e-3):
        if missing.size == 0:
            break
        moved = xy[missing] + step * (centres[missing] - xy[missing])
        retry = mesh(moved[:, 0], moved[:, 1])
        points[missing] = retry
        missing = missing[retry["nr"] < 0]
    if missing.size:
        raise ValueError(f"{missing.size} points of the solution's mesh lie outside the reference's mesh, e.g. "
                         f"{xy[missing[0]].tolist()}")
    return points


def reference_error(sol, reference, degree=None):
    """|||u_h - u_ref|||_h for a Solution and a reference Solution on another mesh of (nearly) the same domain:

        sum_T int_T C eps(u_h - u_ref) : eps(u_h - u_ref) dx + sum_{e in E_h^o} h_e^-1 ||[u_h]||_e^2,

    the volume part by a Gauss rule of ``degree`` (default 2 p_max + 2) on u_h's (curved) elements, weights
    times |det J| of the element mapping, u_ref evaluated by point search in its mesh; the jump part as for the
    exact solution (continuous, u = u_D on Gamma_D: [u_h - u] = [u_h], u_h - u_D on Gamma_D; u_D constant).
    On an inscribed polygon this is the error against the true solution on the polygon's domain."""
    problem, mesh = sol.discretization.problem, sol.mesh
    degree = 2 * int(sol.discretization.order) + 2 if degree is None else degree
    rule = ngs.IntegrationRule(ngs.TRIG, degree)
    points = mesh.MapToAllElements({ngs.TRIG: rule}, ngs.VOL)
    xy = np.asarray(ngs.CF((ngs.x, ngs.y))(points)).reshape(-1, 2)
    q = len(rule.weights)
    centres = np.repeat(xy.reshape(-1, q, 2).mean(axis=1), q, axis=0)
    foreign = _found(reference.mesh, xy, centres)
    jacobian = np.abs(np.asarray(ngs.Det(ngs.specialcf.JacobianMatrix(2))(points)).ravel())
    weights = np.tile(np.asarray(rule.weights), mesh.ne) * jacobian
    e = (np.asarray(strain(sol.u)(points)) - np.asarray(strain(reference.u)(foreign))).reshape(-1, 4)
    mu, lam = float(problem.mu), float(problem.lam)
    volume = float(np.sum(weights * (lam * (e[:, 0] + e[:, 3]) ** 2 + 2 * mu * np.sum(e**2, axis=1))))
    return math.sqrt(volume + _jumps(sol))


def _jumps(sol):
    """sum_{e in E_h^o} h_e^-1 ||[u_h]||_e^2 with [u_h] = u_h - u_D on Gamma_D (constant u_D): the jump part of
    the energy norm of u_h - w, w = u_D (in V_h, continuous)."""
    problem = sol.discretization.problem
    if not _constant(problem.u_D):
        raise ValueError("reference_error needs a constant u_D (a pair of numbers)")
    w, d = ngs.GridFunction(sol.u.space), ngs.GridFunction(sol.u.space)
    w.Set(coefficient(problem.u_D))
    d.vec.data = sol.u.vec - w.vec  # not into w.vec itself: NGSolve would compute w = u, then w -= w
    return float(energy_norm_squared_parts(problem, sol.mesh, d)[1])


def fit_exponential(ndof, errors):
    """(b, rms): the least-squares line log e = log C - b N^(1/3) (exponential convergence of hp methods in 2D)
    and the root mean square of its residuals in log e."""
    t, e = np.asarray(ndof, dtype=float) ** (1 / 3), np.log(np.asarray(errors, dtype=float))
    coefficients = np.polyfit(t, e, 1)
    return float(-coefficients[0]), float(np.sqrt(np.mean((np.polyval(coefficients, t) - e) ** 2)))


def fit_algebraic(ndof, errors):
    """(s, rms): the least-squares line log e = log C - s log N (algebraic convergence, e ~ N^-s) and the root
    mean square of its residuals in log e."""
    t, e = np.log(np.asarray(ndof, dtype=float)), np.log(np.asarray(errors, dtype=float))
    coefficients = np.polyfit(t, e, 1)
    return float(-coefficients[0]), float(np.sqrt(np.mean((np.polyval(coefficients, t) - e) ** 2)))


# ---------------------------------------------------------------------------------------------------------------
# Rates: a manufactured solution on an annulus (curved) and on a square (straight)
# ---------------------------------------------------------------------------------------------------------------

INNER = 0.5  # the inner radius of the annulus


def annulus(inner=INNER):
    """The annulus inner < r < 1 around the origin: the outer circle's upper half "dirichlet", its lower half
    "traction", the inner circle (a hole) "contact"."""
    c = math.sqrt(0.5)
    outer = Loop([(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)], ("dirichlet", "dirichlet", "traction", "traction"),
                 arcs={0: (c, c), 1: (-c, c), 2: (-c, -c), 3: (c, -c)})
    return Domain(regions={"omega": outer}, holes=[Loop.circle((0.0, 0.0), inner, "contact")])


def _smooth_field():
    """w = (sin(2x + y), cos(x - 2y)) / 4: smooth, no polynomial."""
    x, y = ngs.x, ngs.y
    return ngs.CF((ngs.sin(2 * x + y), ngs.cos(x - 2 * y))) / 4


def manufactured_loads(problem, u, normal):
    """(f, g) = (-div sigma(u), sigma(u) ``normal``) for a smooth CoefficientFunction u (``normal``: a
    2-vector CoefficientFunction of x, y, the outward normal of the exact boundary, so that the data do not
    depend on the mesh's approximation of it)."""
    sigma = stress(problem, strain_of(u))
    x, y = ngs.x, ngs.y
    f = -ngs.CF((sigma[0, 0].Diff(x) + sigma[0, 1].Diff(y), sigma[1, 0].Diff(x) + sigma[1, 1].Diff(y)))
    return f, sigma * normal


def _manufactured(geometry, u, normal, E, nu, name):
    """The problem on ``geometry`` with the exact solution u: f, g of :func:`manufactured_loads`, u_D = u on
    Gamma_D, Gamma_C open (g_a = 1e3, sigma(u) n = 0 there by construction), no friction."""
    base = ContactProblem(E=E, nu=nu, f=(0.0, 0.0), g=(0.0, 0.0), c_n=1.0, m_n=1, g_a=1e3, c_tau=0.0,
                          geometry=geometry, name=name)
    f, g = manufactured_loads(base, u, normal)
    return ContactProblem(E=E, nu=nu, f=f, g=g, c_n=1.0, m_n=1, g_a=1e3, c_tau=0.0, geometry=geometry, u_D=u,
                          name=name)


def annulus_problem(E=1.0, nu=0.3, inner=INNER):
    """(problem, u) on :func:`annulus`: u = (r^2 - r_i^2)^2 w with w of :func:`_smooth_field`.  u and eps(u)
    vanish on the inner circle (Gamma_C: sigma(u) n = 0, the gap g_a = 1e3 keeps it open); u_D = u on the upper
    half of the outer circle, g = sigma(u) n with n = (x, y) / r on its lower half, f = -div sigma(u)."""
    x, y = ngs.x, ngs.y
    r2 = x * x + y * y
    psi = r2 - inner**2
    u = psi * psi * _smooth_field()
    normal = ngs.CF((x, y)) / ngs.sqrt(r2)
    return _manufactured(annulus(inner), u, normal, E, nu, f"annulus {inner:g} < r < 1, smooth u"), u


def square_problem(E=1.0, nu=0.3):
    """(problem, u) on the unit square, the same construction with straight sides: u = y^2 w (w of
    :func:`_smooth_field`), Gamma_C = bottom (u = eps(u) = 0 there), Gamma_D = top (u_D = u), Gamma_F = left and
    right (g = sigma(u) n)."""
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="traction", top="dirichlet", left="traction")
    u = ngs.y * ngs.y * _smooth_field()
    return _manufactured(geometry, u, ngs.specialcf.normal(2), E, nu, "unit square, smooth u"), u


def uniform_meshes(mesh, levels):
    """The meshes of ``levels`` uniform refinements of ``mesh`` (copies; each triangle bisected twice into four
    similar ones, new boundary points on the geometry's curves), ``mesh`` itself first."""
    meshes = [ngs.Mesh(mesh.ngmesh.Copy())]
    for _ in range(levels):
        finer = ngs.Mesh(meshes[-1].ngmesh.Copy())
        refine(finer, np.ones(finer.ne, dtype=bool), bisections=2)
        meshes.append(finer)
    return meshes


def _loops(segments, labels):
    """The closed chains of boundary segments (k, 2) as lists of (vertex numbers, labels of the segments leaving
    them), in the direction of the segments."""
    following = {int(a): (int(b), str(label)) for (a, b), label in zip(segments, labels, strict=True)}
    chains = []
    while following:
        start = min(following)
        chain, names, vertex = [], [], start
        while vertex in following:
            nxt, name = following.pop(vertex)
            chain.append(vertex)
            names.append(name)
            vertex = nxt
        chains.append((chain, names))
    return chains


def _oriented(points, chain, names, counter_clockwise):
    """A chain (vertex numbers, the labels of the sides leaving them) run in the given sense."""
    x, y = points[chain, 0], points[chain, 1]
    if (np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0) == counter_clockwise:
        return list(chain), list(names)
    return chain[::-1], [names[k - 1] for k in range(len(names) - 1, -1, -1)]  # side k ends where it started


def inscribed(problem, mesh):
    """(problem on the straight-sided domain, mesh without curving): the domain whose boundary is the boundary
    edges of ``mesh`` (its vertices lie on the circles: the inscribed polygons), the same data, and the mesh
    rebuilt from its vertices and triangles (no geometry, so it is never curved).  The boundary chain enclosing
    the largest area is the outer boundary, the others are holes."""
    points, triangles, segments, labels = mesh_arrays(mesh)
    chains = _loops(segments, labels)
    extent = [np.ptp(points[chain], axis=0).prod() for chain, _ in chains]
    outer, holes, edges, names = None, [], [], []
    for k, (chain, sides) in enumerate(chains):
        loop = Loop([tuple(points[v]) for v in _oriented(points, chain, sides, True)[0]],
                    _oriented(points, chain, sides, True)[1])
        if k == int(np.argmax(extent)):
            outer = loop
        else:
            holes.append(loop)
        left, left_names = _oriented(points, chain, sides, k == int(np.argmax(extent)))  # the domain on the left
        edges += [(a, b) for a, b in zip(left, np.roll(left, -1), strict=True)]
        names += left_names
    straight = dataclasses.replace(problem, geometry=Domain(regions={"omega": outer}, holes=holes),
                                   name=f"{problem.name} (inscribed polygons)")
    return straight, mesh_from_arrays(straight, points, triangles, np.asarray(edges), np.asarray(names))
