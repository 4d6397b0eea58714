r"""A guaranteed upper bound of :math:`|\!|\!| u - u_h |\!|\!|_h`: an equilibrated stress and a conforming displacement.

For :math:`m_t = 0` the exact :math:`u` minimises :math:`J(v) = \frac12 a(v, v) - L(v) + j(v)` over
:math:`v = u_D` on :math:`\Gamma_D`, with the convex contact functional of (1.8)-(1.9)

.. math::

    j(v) = \int_{\Gamma_C} \frac{c_n}{m_n + 1} (v_n - g_a)_+^{m_n + 1} + c_\tau |v \cdot t| \, ds.

Take :math:`v = s + \ell` with :math:`s` continuous (``potential``) and :math:`\ell` the lifting of
:math:`u_D - s` into the elements of :math:`\Gamma_D` (:mod:`ngdgfric.dirichlet_lifting`: :math:`v = u_D` on
:math:`\Gamma_D`, :math:`\ell = 0` on every other edge), a contact traction :math:`t` that is admissible pointwise,
:math:`j^*(t) < \infty` (:math:`t_n \ge 0`, :math:`|t \cdot t| \le c_\tau`: ``contact_traction``), and a stress
:math:`\sigma \in H(\operatorname{div})` whose divergence and normal traces meet :math:`-f`, :math:`g` on
:math:`\Gamma_F` and :math:`-t` on :math:`\Gamma_C` in the mean (``equilibrated_stress``).  With :math:`z = u - v`,
the variational inequality of :math:`u` at :math:`v` and Fenchel-Young give, for
:math:`x = C^{1/2} \varepsilon_h(u - u_h)`,
:math:`a = C^{-1/2} (\operatorname{sym} \sigma - C \varepsilon_h(u_h))`,
:math:`b = C^{1/2} \varepsilon_h(s - u_h)`, :math:`L = \|C^{1/2} \varepsilon(\ell)\|`,

.. math::

    |x| \le A + (A^2 + F\!Y - (a, b) + |a| L + \rho (|b| + L))^{1/2},

    A = (|a + b| + L + \rho) / 2, \qquad F\!Y = j(s) + j^*(t) - \langle t, s \rangle_{\Gamma_C} \ge 0,

where :math:`\rho |C^{1/2} \varepsilon(z)|` bounds what :math:`\sigma` leaves:
:math:`(\operatorname{skw} \sigma, \operatorname{skw} \nabla z) + (f + \operatorname{div} \sigma, z)
- (\sigma n - g, z)_{\Gamma_F} - (\sigma n + t, z)_{\Gamma_C}`.  Then
:math:`|\!|\!| u - u_h |\!|\!|_h^2 = |x|^2 + \sum_e h_e^{-1} \|[\![u_h]\!]\|_e^2`, the jump part computed exactly
(``energy_norm_squared_parts`` of :mod:`ngdgfric.reference`).  For :math:`\rho = L = F\!Y = 0` this is at most the
Pythagorean :math:`(|a|^2 + |b|^2)^{1/2}` of Ern & Vohralik (SINUM 2015).  No constant of the method enters: the
bound holds for every method (NIPG too) and every :math:`u_h`.

:math:`t`: :math:`t_n = c_n (u_{hn} - g_a)_+^{m_n}` and :math:`t_\tau = c_\tau P(\lambda_{h\tau})`, the forces of
:math:`u_h` and its multiplier, pointwise (not polynomials); on the edges where the projection onto
:math:`[-1, 1]` would cut off :math:`\lambda_{h\tau}` (``kinked_edges``) :math:`P` is a :math:`C^1` clamp
(``smooth_unit``: a kink is what polynomial normal traces miss most), elsewhere that projection.

:math:`\sigma`: row-wise Raviart-Thomas of degree :math:`p_T` on every element (:math:`p_T + 2` on the elements of
:math:`\Gamma_C`: ``CONTACT_RAISE``) closest to :math:`C \varepsilon_h(u_h)` in the :math:`C^{-1}` norm among the
fields with :math:`\operatorname{div} \sigma = -\Pi f`, the skew part orthogonal to :math:`P_{p_T-1}` element by
element (weak symmetry, Arnold, Falk & Winther), :math:`\sigma n = \Pi g` on :math:`\Gamma_F` and :math:`-\Pi t` on
:math:`\Gamma_C` (:math:`\Pi`: :math:`L^2` projections onto the polynomials of the normal traces, edge by edge, in
the Gauss rule of ``edge_measure``); one global minimisation, hybridised (normal continuity by a facet multiplier)
and statically condensed: a sparse system on the edges only.

:math:`s`: the continuous displacement of degree :math:`p_T + 1` closest to :math:`u_h` in the energy, exact at
the vertices of :math:`\Gamma_D`, with its tangential part removed on the edges where :math:`u_h` sticks (a
tangential :math:`s \cdot t \ne 0` there costs :math:`F\!Y` linearly).

:math:`\rho`: element by element, with the inf-sup constant :math:`\beta_T` of the triangle and
:math:`K_T = ((1 + 2/\beta_T^2) / (2 \mu))^{1/2}`, the sum of

* ``asymmetry`` :math:`\frac12 (2/\beta_T) \|\operatorname{skw} \text{ part of } \sigma\|_T / (2\mu)^{1/2}`:
  :math:`\|\operatorname{rot} z - \text{mean}\|_T \le (2/\beta_T) \|\varepsilon(z)\|_T` (Necas' inequality for
  :math:`\nabla \operatorname{rot} z`, written in :math:`\varepsilon(z)`);
* ``oscillation`` :math:`K_T ((h_T/\pi) \|f + \operatorname{div} \sigma\|_T + C_T \|\sigma n - g\|_{\partial T
  \cap \Gamma_F})` and ``traction`` :math:`K_T C_T \|\sigma n + t\|_{\partial T \cap \Gamma_C}`: the three are
  orthogonal to the rigid motions :math:`r` (the linear functions of the element or edge), so :math:`z` may be
  replaced by :math:`z - r` of mean zero with :math:`\|\nabla (z - r)\|_T \le (1 + 2/\beta_T^2)^{1/2}
  \|\varepsilon(z)\|_T`; then Payne-Weinberger :math:`\|z - r\|_T \le (h_T/\pi) \|\nabla(z - r)\|_T` on convex
  :math:`T`, and on the edges the trace inequality of ``trace_constants``.

:math:`\beta_T \ge \sin(\omega_T/2)` with the Horgan-Payne angle :math:`\omega_T` of the triangle seen from its
incentre, half its smallest angle (Horgan & Payne, ARMA 1983; Costabel & Dauge, ARMA 2015, who show the bound can
fail for some star-shaped domains: for triangles it is the one assumption of the bound we did not prove here).

Guaranteed (``Equilibration.guaranteed``, else ``reason`` says why): :math:`m_t = 0`, straight sides,
:math:`u_D` continuous along :math:`\Gamma_D` (no jump where two sides meet nor inside a side, to ``ADMISSIBLE``
relative to :math:`\max |u_D|`: ``dirichlet_jumps`` of :mod:`ngdgfric.dirichlet_lifting`); any data :math:`f`,
:math:`g`, :math:`u_D`, :math:`g_a`, :math:`c_n`, :math:`c_\tau` otherwise, their integrals taken by Gauss rules
(exact for polynomials, of degree :math:`2 (p + 2) + 24` on the edges, where the traction has kinks).  For
:math:`m_t > 0` the friction bound depends on :math:`u` itself (a quasi-variational inequality, no minimisation): the
same number is computed with the friction bound frozen at :math:`u_h`, an estimate without guarantee.  Symmetry sides
are refused (ValueError).
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .checks import check_solution
from .contact.boundary import boundary_edges, contact_elements, contact_points, normal_tangent
from .contact.forms import compliance, friction_bound
from .contact.laws import compliance_energy, friction_energy, pressure_conjugate, project_unit, smooth_unit
from .dg.discretization import (
    conforming_space,
    dg_space,
    edge_orders,
    most_common_degree,
    polynomial_degrees,
)
from .dg.forms import element_areas
from .dirichlet_lifting import dirichlet_jumps, lifting_energies, set_dirichlet_vertices
from .meshes import boundary_elements, element_diameters, facet_indicator, smallest_angles
from .problem import coefficient, exponents, strain, stress
from .reference import energy_norm_squared_parts
from .threads import threads

__all__ = ["Equilibration", "equilibrate", "potential", "equilibrated_stress", "contact_traction",
           "stick_edges", "kinked_edges", "inf_sup_lower_bounds", "trace_constants", "edge_measure", "edge_integrals",
           "ADMISSIBLE"]

ADMISSIBLE = 1e-10  # relative jump of u_D along Gamma_D still called round-off (dirichlet_jumps)
DATA_BONUS = 6  # extra quadrature degree of the non-polynomial integrands (data, kinks of (.)_+)
EDGE_BONUS = 24  # the same on the edges, for g and the contact traction (kinks where P(lam_tau) or (.)_+ cut off)


PAIRS_REASON = ("contact pairs (two bodies) are not built into it: its stress is equilibrated against the foundation's "
                "contact traction, and a pair would need the pair's traction as patch data on both sides and a "
                "contact term for the relative displacement [u]; the residual estimator (kind='residual', the "
                "default) has the pairs' terms")
"""Why the equilibrated bound refuses a problem with :class:`~ngdgfric.ContactPair` s (``equilibrate``,
``estimate(kind="equilibrated")``, ``adapt(estimator="equilibrated")``)."""


@dataclass
class Equilibration:
    r"""The equilibrated bound of a Solution, its parts and the fields it is made of.

    What :func:`ngdgfric.equilibrate` returns (:mod:`ngdgfric.equilibration` derives the bound).

    Parameters
    ----------
    eta_h : float
        The guaranteed bound of :math:`|\!|\!| u - u_h |\!|\!|_h`.
    eta_T_squared : numpy.ndarray
        Element indicators for marking: the squared parts of ``terms_squared`` element by element.
    terms_squared : dict
        The squared parts: ``"stress"`` :math:`\|\operatorname{sym} \sigma - C \varepsilon(s)\|_{C^{-1}}^2`,
        ``"conformity"`` :math:`|b|^2`, ``"jumps"``, ``"contact"`` :math:`2 F\!Y`, ``"dirichlet"`` :math:`L^2` (the
        lifting of what :math:`s` misses of :math:`u_D`), and ``"asymmetry"``, ``"oscillation"`` (of :math:`f`
        and :math:`g`) and ``"traction"`` (what :math:`\sigma n` misses of :math:`-t`): the three parts of
        :math:`\rho`, squared.
    guaranteed : bool
        Whether every assumption of the bound was met.
    reason : str
        Why the bound is not guaranteed (empty if it is).
    sigma : ngsolve.CoefficientFunction
        The equilibrated stress :math:`\sigma`, a 2x2 CoefficientFunction.
    s : ngsolve.GridFunction
        The conforming displacement :math:`s`.
    """

    eta_h: float
    eta_T_squared: np.ndarray
    terms_squared: dict
    guaranteed: bool
    reason: str
    sigma: object
    s: object


def compliance_inverse(problem, tau):
    """C^-1 tau = (tau - lam / (2 mu + 2 lam) tr(tau) I) / (2 mu) (plane strain)."""
    mu, lam = coefficient(problem.mu), coefficient(problem.lam)
    return (tau - lam / (2 * mu + 2 * lam) * ngs.Trace(tau) * ngs.Id(2)) / (2 * mu)


def _check(problem):
    if problem.sides("symmetry"):
        raise ValueError(f"the equilibrated estimator does not treat symmetry sides yet: {problem.sides('symmetry')}; "
                         "use kind='residual'")


def _with_degrees(space, base, degrees, edges=None):
    """``space`` (built with degree ``base``) with degree ``degrees[T]`` on every element T and, if given,
    ``edges[e]`` on every edge e (hp meshes)."""
    for nr in np.flatnonzero(degrees != base):
        space.SetOrder(ngs.NodeId(ngs.ELEMENT, int(nr)), int(degrees[nr]))
    for nr in np.flatnonzero(edges != base) if edges is not None else ():
        space.SetOrder(ngs.NodeId(ngs.EDGE, int(nr)), int(edges[nr]))
    space.Update()
    return space


def potential(sol):
    """s: the continuous vector polynomials (degree p_T + 1 on every element, edges of the larger degree of their
    elements) closest to u_h in the energy, min ||C^1/2 eps_h(s - u_h)||, with s = u_D interpolated on Gamma_D,
    and the tangential part of s removed on the contact edges where u_h sticks (``stick_edges``: there u . t = 0,
    and a tangential s . t != 0 would cost the contact term c_tau |s . t| - t_tau s . t, linear in s - u instead of
    quadratic).  The degree p_T + 1 lets div s follow div u_h as nu -> 1/2 (decisions page, equilibration).  One
    statically condensed Cholesky solve of the conforming space."""
    disc = sol.discretization
    problem, mesh = disc.problem, sol.mesh
    space = conforming_space(mesh, polynomial_degrees(disc) + POTENTIAL_RAISE)
    dirichlet = mesh.Boundaries(problem.where("dirichlet"))
    fixed = np.asarray(list(space.GetDofs(dirichlet)), dtype=bool)
    free = ngs.BitArray(list(np.asarray(list(space.FreeDofs(True)), dtype=bool) & ~fixed))  # coupling dofs
    s, boundary, correction, stick = (ngs.GridFunction(space) for _ in range(4))
    s.Set(sol.u)
    boundary.Set(coefficient(problem.u_D), ngs.BND, definedon=dirichlet)
    set_dirichlet_vertices(problem, mesh, boundary)  # exact at the vertices: the lifting of u_D - s needs it
    s.vec.FV().NumPy()[fixed] = boundary.vec.FV().NumPy()[fixed]
    w, v = space.TnT()
    form = ngs.BilinearForm(space, symmetric=True, condense=True)
    form += ngs.InnerProduct(stress(problem, strain(w)), strain(v)) * ngs.dx
    load = ngs.LinearForm(space)
    load += ngs.InnerProduct(stress(problem, strain(sol.u) - strain(s)), strain(v)) * ngs.dx
    _condensed_solve(form, load, correction, free)
    s.vec.data += correction.vec
    if problem.sides("contact"):
        _, t = normal_tangent()
        stick.Set(stick_edges(sol) * (s * t) * t, ngs.BND, definedon=mesh.Boundaries(problem.where("contact")))
        stick.vec.FV().NumPy()[fixed] = 0.0
        s.vec.data -= stick.vec
    return s


def _condensed_solve(form, load, solution, free):
    """Assemble and solve ``form`` = ``load`` (statically condensed) into the GridFunction ``solution``: umfpack
    below CHOLESKY_FROM unknowns, sparsecholesky above (both condensed matrices are symmetric and definite, the
    stress's negative definite: a Schur complement of a saddle point; the two agree to 1e-10 on the bound)."""
    form.Assemble()
    load.Assemble()
    factor = form.mat.Inverse(free, inverse="umfpack" if free.NumSet() < CHOLESKY_FROM else "sparsecholesky")
    load.vec.data += form.harmonic_extension_trans * load.vec
    solution.vec.data = factor * load.vec
    solution.vec.data += form.harmonic_extension * solution.vec
    solution.vec.data += form.inner_solve * load.vec


def contact_traction(sol):
    """(t_n, t_tau): the contact traction t = t_n n + t_tau t of u_h, admissible pointwise by construction:
    t_n = c_n (u_n - g_a)_+^{m_n} >= 0 and t_tau = bound smooth_unit(lam_tau) with |t_tau| <= bound
    (CoefficientFunctions on the contact edges; the bound frozen at u_h when m_t > 0).  ``smooth_unit``
    (:mod:`ngdgfric.contact.laws`, a C^1 stand-in for the projection, so that the traction has no kink for the edge
    polynomials of sigma n to miss) only on the edges where the projection onto [-1, 1] would have a kink
    (``kinked_edges``), elsewhere the projection itself.
    sigma n = -t holds in the mean (moments of degree p_T + 2 on every contact edge); what it misses is paid by the
    traction term of the bound."""
    problem, u_h, lam = sol.discretization.problem, sol.u, sol.lam_tau
    kinked = kinked_edges(sol)
    return compliance(problem, u_h), friction_bound(problem, u_h) * (kinked * smooth_unit(lam)
                                                                      + (1 - kinked) * project_unit(lam))


def stick_edges(sol, tol=1e-10):
    """Order-0 facet GridFunction: 1 on the contact edges where u_h sticks (|lam_tau| < 1 - tol at every Gauss
    point), 0 elsewhere."""
    return _edge_indicator(sol, np.all(np.abs(sol.contact.gauss.values(sol.lam_tau)) < 1.0 - tol, axis=1))


def kinked_edges(sol, tol=1e-10, samples=32):
    """Order-0 facet GridFunction: 1 on the contact edges where P(lam_tau) has a kink, |lam_tau| > 1 + tol somewhere
    inside the edge (the multiplier sampled at ``samples`` Gauss points per edge), 0 elsewhere (in particular where
    lam_tau = +-1 throughout: slip)."""
    points = contact_points(sol.discretization.problem, sol.mesh, samples - 1)
    dense = np.asarray(sol.lam_tau(points)).reshape(-1, samples)
    return _edge_indicator(sol, np.any(np.abs(dense) > 1.0 + tol, axis=1))


def _edge_indicator(sol, chosen):
    """Order-0 facet GridFunction, 1 on the contact edges flagged in ``chosen`` (one bool per edge, in the order of
    the contact Gauss points)."""
    disc, mesh = sol.discretization, sol.mesh
    space = ngs.FacetFESpace(mesh, order=0)
    indicator = ngs.GridFunction(space)
    for (element, _), on in zip(boundary_edges(disc.problem, mesh), chosen, strict=True):
        if on:
            indicator.vec.FV().NumPy()[space.GetDofNrs(ngs.NodeId(ngs.EDGE, element.edges[0].nr))] = 1.0
    return indicator


CONTACT_RAISE = 2  # RT degree p_T + 2 on the elements with a contact edge (``equilibrated_stress``)
POTENTIAL_RAISE = 1  # the potential of degree p_T + 1 (``potential``)
CHOLESKY_FROM = 15_000  # unknowns from which sparsecholesky beats umfpack (20x slower at 600, 1.5x faster at 25,000)
SKEW_WEIGHT = 100.0  # weight of ||as sigma||^2 / (2 mu) in the minimisation (``equilibrated_stress``)


def equilibrated_stress(sol, traction, skew_weight=None):
    """(sigma, div sigma): the stress of the module docstring (a 2x2 CoefficientFunction, rows in RT of degree p_T on
    every element, normal traces of the larger degree of the two elements on every edge) for the contact traction
    ``traction`` = (t_n, t_tau) of ``contact_traction``, and its divergence."""
    disc = sol.discretization
    problem, mesh = disc.problem, sol.mesh
    degrees = polynomial_degrees(disc).copy()
    degrees[contact_elements(problem, mesh)] += CONTACT_RAISE
    base, edges = most_common_degree(degrees), edge_orders(mesh, degrees)
    rows = _with_degrees(ngs.HDiv(mesh, order=base, RT=True, discontinuous=True), base, degrees, edges)
    facets = _with_degrees(ngs.FacetFESpace(mesh, order=base, dirichlet=problem.where("dirichlet")), base, degrees,
                           edges)
    skew_space = _with_degrees(ngs.L2(mesh, order=max(base - 1, 0)), max(base - 1, 0), np.maximum(degrees - 1, 0))
    X = ngs.FESpace([rows, rows, dg_space(mesh, degrees, dgjumps=False), skew_space, facets, facets])
    (s1, s2, u, r, l1, l2), (t1, t2, v, q, m1, m2) = X.TnT()
    n, t = normal_tangent()

    def tensor(a, b):
        return ngs.CF((a[0], a[1], b[0], b[1]), dims=(2, 2))

    sigma, tau = tensor(s1, s2), tensor(t1, t2)
    mu_test, mu_trial = ngs.CF((m1, m2)), ngs.CF((l1, l2))
    form = ngs.BilinearForm(X, condense=True)
    weight = (SKEW_WEIGHT if skew_weight is None else skew_weight) / (2 * coefficient(problem.mu))
    form += (ngs.InnerProduct(compliance_inverse(problem, sigma), tau) + weight * (sigma[0, 1] - sigma[1, 0])
             * (tau[0, 1] - tau[1, 0])
             + ngs.CF((ngs.div(s1), ngs.div(s2))) * v + ngs.CF((ngs.div(t1), ngs.div(t2))) * u
             + (sigma[0, 1] - sigma[1, 0]) * q + (tau[0, 1] - tau[1, 0]) * r) * ngs.dx
    form += -((sigma * n) * mu_test + (tau * n) * mu_trial) * ngs.dx(element_boundary=True)
    t_n, t_tau = traction
    load = ngs.LinearForm(X)
    load += ngs.InnerProduct(strain(sol.u), tau) * ngs.dx(bonus_intorder=2)
    load += -coefficient(problem.f).Compile() * v * ngs.dx(bonus_intorder=DATA_BONUS)  # Compile: 20x faster for data
    k = int(polynomial_degrees(disc).max())
    for part, datum in (("traction", -coefficient(problem.g)), ("contact", t_n * n + t_tau * t)):
        on = facet_indicator(mesh, problem.where(part))
        load += (on * datum).Compile() * mu_test * edge_measure(k, on)
    solution = ngs.GridFunction(X)
    _condensed_solve(form, load, solution, X.FreeDofs(True))
    rows = solution.components[0], solution.components[1]
    return tensor(*rows), ngs.CF(tuple(ngs.div(row) for row in rows))


def inf_sup_lower_bounds(mesh):
    """beta_T >= sin(omega_T / 2) per triangle, omega_T = half its smallest angle (the Horgan-Payne angle seen
    from the incentre; module docstring)."""
    return np.sin(smallest_angles(mesh) / 4)


def _element_range(mesh, cf):
    """(smallest, largest) value of a scalar CoefficientFunction per element, at its vertices and the points of a
    Gauss rule of degree DATA_BONUS (exact for data constant on every element, as materials on meshes that follow
    them)."""
    rule = ngs.IntegrationRule(ngs.TRIG, DATA_BONUS)
    points = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)] + [tuple(point)[:2] for point in rule.points]
    values = np.asarray(cf(mesh.MapToAllElements({ngs.TRIG: ngs.IntegrationRule(points, [0.0] * len(points))},
                                                 ngs.VOL))).reshape(mesh.ne, len(points))
    return values.min(axis=1), values.max(axis=1)


def _element_values(mesh, density, degree):
    """Per element: the integral of ``density`` by the Gauss rule exact to ``degree``."""
    rule = {ngs.TRIG: ngs.IntegrationRule(ngs.TRIG, degree)}
    return ngs.Integrate(density.Compile() * ngs.dx(intrules=rule), mesh, element_wise=True).NumPy().copy()


def _contact_gap(problem, s, u_h, traction, k, mesh):
    """Per element FY = j(s) + j*(t) - <t, s> on its contact edges (>= 0 pointwise: t is admissible; the friction
    bound frozen at u_h when m_t > 0)."""
    n, t = normal_tangent()
    t_n, t_tau = traction
    c_n, m, g_a = coefficient(problem.c_n), exponents(problem.m_n), coefficient(problem.g_a)
    m_n = max(m)
    if len(set(m)) > 1:
        raise ValueError(f"the equilibrated estimator needs one m_n on all contact sides, got {sorted(set(m))}")
    conjugate = pressure_conjugate(t_n, g_a, c_n, m_n)
    j_s = compliance_energy(s * n - g_a, c_n, m_n) + friction_energy(friction_bound(problem, u_h), s * t)
    gap = edge_integrals(mesh, problem.where("contact"), j_s + conjugate - t_n * (s * n) - t_tau * (s * t), k)
    return np.maximum(gap, 0.0)


def edge_measure(k, on=None):
    """The element-boundary integral of every edge term of the bound for u_h of degree <= k: one Gauss rule, exact
    to degree 2 (k + CONTACT_RAISE) + EDGE_BONUS, for sigma n = g, -t in the mean (the load of
    ``equilibrated_stress``) and for what it misses, so that the misses are orthogonal to the polynomials in this
    rule even where the data have kinks no rule integrates exactly.  ``on``: a facet indicator; then only on the
    elements with an edge where it is 1 (the others add nothing)."""
    rule = {ngs.SEGM: ngs.IntegrationRule(ngs.SEGM, 2 * (k + CONTACT_RAISE) + EDGE_BONUS)}
    if on is None:
        return ngs.dx(element_boundary=True, intrules=rule)
    return ngs.dx(element_boundary=True, intrules=rule,
                  definedonelements=ngs.BitArray(list(boundary_elements(on.space.mesh, [on]))))


def edge_integrals(mesh, where, density, k):
    """Per element: the integral of ``density`` over its edges on the boundary part ``where`` by the rule of
    ``edge_measure(k)`` (assembled as a linear form of the piecewise constants: NGSolve 6.2.2608's ``Integrate``
    ignores the rule of an element-boundary integral and takes its own order)."""
    space = ngs.L2(mesh, order=0)
    form = ngs.LinearForm(space)
    on = facet_indicator(mesh, where)
    form += (on * density).Compile() * space.TestFunction() * edge_measure(k, on)
    form.Assemble()
    return form.vec.FV().NumPy().copy()


def trace_constants(mesh, where):
    """Per element, C_T with sum_e |(d, w)_e| <= C_T ||d||_{dT cap where} ||grad w||_T over its edges e on the
    boundary part ``where``, for every w of mean zero on T: C_T = h_T (c L_T / |T|)^{1/2}, L_T the length of those
    edges, c = (1/pi)(1/pi + 1) (the trace inequality ||w||_e^2 <= |e| / |T| (||w||_T^2 + h_T ||w||_T ||grad w||_T),
    from div((x - a) w^2) with a the vertex opposite e, and Payne-Weinberger ||w||_T <= h_T / pi ||grad w||_T)."""
    lengths = edge_integrals(mesh, where, ngs.CF(1.0), 1)
    areas = element_areas(mesh).vec.FV().NumPy()
    return element_diameters(mesh) * np.sqrt((1 / np.pi) * (1 / np.pi + 1) * lengths / areas)


def equilibrate(sol):
    r"""The guaranteed upper bound of :math:`|\!|\!| u - u_h |\!|\!|_h` of a Solution, from an equilibrated stress.

    An equilibrated stress :math:`\sigma` and a conforming displacement :math:`s` bound the energy error with no
    unknown constant, for every method (:mod:`ngdgfric.equilibration` derives the bound and lists its
    assumptions).  ``estimate(sol, kind="equilibrated")`` (:func:`ngdgfric.estimate`) returns the same bound as
    an :class:`ngdgfric.Estimate`.

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`), any method.

    Returns
    -------
    Equilibration
        The bound :math:`\eta_h`, its parts, whether it is guaranteed (and why not), :math:`\sigma` and
        :math:`s` (:class:`ngdgfric.Equilibration`).

    Raises
    ------
    ValueError
        The problem has symmetry sides (not treated yet; use the residual estimator).

    See Also
    --------
    ngdgfric.estimate : The residual estimator, or this bound with ``kind="equilibrated"``.

    Notes
    -----
    Guaranteed for :math:`m_t = 0`, straight sides and :math:`u_D` continuous along :math:`\Gamma_D` (a jump where
    two Dirichlet sides meet or inside one is named in ``reason``), whatever the data otherwise (what the spaces miss
    of them is paid by explicit terms; the integrals of data that are not polynomials are taken by Gauss rules); for
    :math:`m_t > 0` the same number, with the friction bound frozen at :math:`u_h`, is an estimate without guarantee
    (``guaranteed`` is False and ``reason`` says why).

    Examples
    --------
    >>> problem = ndf.example_6_1()
    >>> sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
    >>> bound = ndf.equilibrate(sol)
    >>> print(f"{bound.eta_h:.1f}", bound.guaranteed)
    22.3 True
    >>> sorted(bound.terms_squared)
    ['asymmetry', 'conformity', 'contact', 'dirichlet', 'jumps', 'oscillation', 'stress', 'traction']
    """
    check_solution(sol, "sol")
    if sol.problem.pairs:
        raise ValueError(f"the equilibrated bound is refused: {PAIRS_REASON}")
    with threads(sol.ndof):
        return _bound(sol)


def _bound(sol):
    """``equilibrate`` (its body, run under the thread policy of the solve)."""
    disc = sol.discretization
    problem, mesh, u_h, k = disc.problem, sol.mesh, sol.u, int(polynomial_degrees(disc).max())
    _check(problem)
    s = potential(sol)
    traction = contact_traction(sol)
    sigma, divergence = equilibrated_stress(sol, traction)
    symmetric = 0.5 * (sigma + sigma.trans)
    strain_h, strain_s = strain(u_h), strain(s)

    def energy(tau):  # tau : C^-1 tau
        return ngs.InnerProduct(compliance_inverse(problem, tau), tau)

    A, B = symmetric - stress(problem, strain_h), stress(problem, strain_s - strain_h)  # a = C^-1/2 A, b = C^-1/2 B
    order = 2 * (k + CONTACT_RAISE) + 2  # exact for sigma of degree p_T + 3, s of p_T + 1
    parts = {"stress": _element_values(mesh, energy(A - B), order),
             "conformity": _element_values(mesh, energy(B), order)}
    cross = _element_values(mesh, ngs.InnerProduct(A, strain_s - strain_h), order).sum()  # (a, b)
    sum_ab = parts["stress"].sum() + 4 * cross  # |a + b|^2 = |a - b|^2 + 4 (a, b)
    gap = _contact_gap(problem, s, u_h, traction, k, mesh)
    parts["contact"] = 2 * gap
    # [u - u_h] = -[u_h] inside, u_D - u_h on Gamma_D
    _, parts["jumps"] = energy_norm_squared_parts(problem, mesh, u_h, element_wise=True,
                                                  dirichlet_value=coefficient(problem.u_D))
    asymmetry, oscillation, pressure = _rho_parts(problem, mesh, sigma, divergence, traction, k, order)
    parts["asymmetry"], parts["oscillation"], parts["traction"] = asymmetry**2, oscillation**2, pressure**2
    mu, lam = (_element_range(mesh, coefficient(value))[1] for value in (problem.mu, problem.lam))
    parts["dirichlet"] = lifting_energies(problem, mesh, s, mu, lam)  # ||C^1/2 eps(l)||_T^2, l: lifting of u_D - s
    rho = float(np.sqrt(np.sum((asymmetry + oscillation + pressure) ** 2)))
    b, lift = float(np.sqrt(parts["conformity"].sum())), float(np.sqrt(parts["dirichlet"].sum()))
    a = float(np.sqrt(max(parts["stress"].sum() + 2 * cross - parts["conformity"].sum(), 0.0)))
    half = (np.sqrt(max(sum_ab, 0.0)) + lift + rho) / 2
    x = half + np.sqrt(max(half**2 + gap.sum() - cross + a * lift + rho * (b + lift), 0.0))
    eta_h = float(np.sqrt(x**2 + parts["jumps"].sum()))
    reasons = []
    if max(exponents(problem.m_t)) > 0:
        reasons.append("m_t > 0: the friction bound depends on u (estimate with the bound frozen at u_h)")
    if problem.geometry.curved:
        reasons.append("curved sides: the constants and the lifting of u_D hold for straight triangles")
    jumps = dirichlet_jumps(problem, mesh, ADMISSIBLE)
    if jumps:
        size, (x, y), where = jumps[0]
        more = {1: "", 2: "; 1 more jump"}.get(len(jumps), f"; {len(jumps) - 1} more jumps")
        reasons.append(f"u_D jumps by {size:.1e} (relative) at ({x:.6g}, {y:.6g}) {where} (not the trace of an H^1 "
                       f"displacement{more})")
    element = sum(parts.values())
    return Equilibration(eta_h=eta_h, eta_T_squared=element, terms_squared={key: float(value.sum()) for key, value
                                                                           in parts.items()},
                         guaranteed=not reasons, reason="; ".join(reasons), sigma=sigma, s=s)


def _rho_parts(problem, mesh, sigma, divergence, traction, k, order):
    """Per element, the three parts of rho (module docstring): the skew part of sigma, the oscillation of f and g
    (what div sigma + f and sigma n - g miss) and what sigma n + t misses on Gamma_C, each times its constant."""
    beta = inf_sup_lower_bounds(mesh)
    mu, lam = coefficient(problem.mu), coefficient(problem.lam)
    stiff = _element_range(mesh, 2 * ngs.IfPos(lam, mu, mu + lam))[0]  # C's smallest eigenvalue 2 min(mu, mu + lam)
    korn = np.sqrt((1 + 2 / beta**2) / stiff)  # ||grad(z - r)||_T <= korn ||C^1/2 eps(z)||_T
    skew = _element_values(mesh, (sigma[0, 1] - sigma[1, 0]) ** 2, order)
    load_residual = coefficient(problem.f) + divergence
    residual = _element_values(mesh, load_residual * load_residual, order + DATA_BONUS)
    n, t = normal_tangent()
    misses = {part: edge_integrals(mesh, problem.where(part), (sigma * n - prescribed) ** 2, k)
              for part, prescribed in (("traction", coefficient(problem.g)),
                                       ("contact", -(traction[0] * n + traction[1] * t)))}
    asymmetry = 0.5 * (2 / beta) * np.sqrt(skew / stiff)
    oscillation = korn * (element_diameters(mesh) / np.pi * np.sqrt(residual)
                          + trace_constants(mesh, problem.where("traction")) * np.sqrt(misses["traction"]))
    pressure = korn * trace_constants(mesh, problem.where("contact")) * np.sqrt(misses["contact"])
    return asymmetry, oscillation, pressure
