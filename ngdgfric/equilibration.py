r"""A guaranteed upper bound of :math:`|\!|\!| u - u_h |\!|\!|_h`: an equilibrated stress and a conforming displacement.

For :math:`m_t = 0` the exact :math:`u` minimises :math:`J(v) = \frac12 a(v, v) - L(v) + j(v)` over
:math:`v = u_D` on :math:`\Gamma_D`, with the convex contact functional of (1.8)-(1.9)

.. math::

    j(v) = \int_{\Gamma_C} \frac{c_n}{m_n + 1} (v_n - g_a)_+^{m_n + 1} + c_\tau |v \cdot t| \, ds.

Take any :math:`s \in H^1` with :math:`s = u_D` on :math:`\Gamma_D` (``potential``: :math:`u_h` averaged into the
continuous space of the same degree) and any :math:`\sigma \in H(\operatorname{div})` with
:math:`\operatorname{div} \sigma + f = 0`, :math:`\sigma n = g` on :math:`\Gamma_F` and a contact traction
:math:`t = -\sigma n` that is admissible, :math:`j^*(t) < \infty`: :math:`t_n \ge 0` and
:math:`|t \cdot t| \le c_\tau` pointwise (``equilibrated_stress``).  With :math:`z = u - s`, the variational
inequality of :math:`u` at :math:`v = s` and Fenchel-Young give, for
:math:`x = C^{1/2} \varepsilon_h(u - u_h)`,
:math:`a = C^{-1/2} (\operatorname{sym} \sigma - C \varepsilon_h(u_h))`,
:math:`b = C^{1/2} \varepsilon_h(s - u_h)`,

.. math::

    |x|^2 \le (a + b, x) - (a, b) + F\!Y + \rho |x - b|, \qquad
    F\!Y = j(s) + j^*(t) - \langle t, s \rangle_{\Gamma_C} \ge 0,

where :math:`\rho |C^{1/2} \varepsilon(z)|` bounds what the skew part of :math:`\sigma` and the load oscillation
leave, :math:`(\operatorname{skw} \sigma, \operatorname{skw} \nabla z) + (f + \operatorname{div} \sigma, z)`.
Solved for :math:`|x|` (with :math:`|x - b| \le |x| + |b|`):

.. math::

    |x| \le A + (A^2 + F\!Y - (a, b) + \rho |b|)^{1/2}, \qquad A = (|a + b| + \rho) / 2,

and :math:`|\!|\!| u - u_h |\!|\!|_h^2 = |x|^2 + \sum_e h_e^{-1} \|[\![u_h]\!]\|_e^2`, the jump part computed
exactly (``energy_norm_squared_parts`` of :mod:`ngdgfric.reference`).  For :math:`\rho = 0` and
:math:`F\!Y = 0` this is at most the Pythagorean :math:`(|a|^2 + |b|^2)^{1/2}` of Ern & Vohralik (SINUM 2015).
No constant of the method enters, so the bound holds for every method (NIPG too) and every :math:`u_h`.

:math:`\sigma`: row-wise Raviart-Thomas :math:`RT_p` (normal traces :math:`P_p`, div in :math:`P_p`) closest to
:math:`C \varepsilon_h(u_h)` in the :math:`C^{-1}` norm among the fields with
:math:`\operatorname{div} \sigma = -\Pi_p f`, the skew part orthogonal to :math:`P_{p-1}` element by element
(weak symmetry, Arnold, Falk & Winther), :math:`\sigma n = \Pi_p g` on :math:`\Gamma_F` and :math:`-t` on
:math:`\Gamma_C`; one global minimisation, hybridised (normal continuity by a facet multiplier) and statically
condensed: a sparse system on the edges only.
:math:`t`: the compliance and friction forces of :math:`u_h` at the contact Gauss points, interpolated by a
polynomial of the multiplier's degree on every edge and made admissible by clipping its Bernstein coefficients
(a polynomial with coefficients in :math:`[lo, hi]` stays in :math:`[lo, hi]` on the edge).

:math:`\rho`: element by element
:math:`\frac12 \|\operatorname{skw} \text{ part}\| |\operatorname{rot} z - \text{mean}|` plus the oscillation
:math:`\|f - \Pi_p f\| \|z - r\|` (:math:`r` a rigid motion), bounded with the inf-sup constant
:math:`\beta_T` of the triangle:
:math:`\|\operatorname{rot} z - \text{mean}\|_T \le (2/\beta_T) \|\varepsilon(z)\|_T` (Necas' inequality for
:math:`\nabla \operatorname{rot} z`, written in :math:`\varepsilon(z)`), and
:math:`\|z - r\|_T \le (h_T/\pi) (1 + 2/\beta_T^2)^{1/2} \|\varepsilon(z)\|_T` (Payne-Weinberger on convex
:math:`T`).  :math:`\beta_T \ge \sin(\omega_T/2)` with the Horgan-Payne angle :math:`\omega_T` of the triangle
seen from its incentre, half its smallest angle (Horgan & Payne, ARMA 1983; Costabel & Dauge, ARMA 2015, who
show the bound can fail for some star-shaped domains: for triangles it is the one assumption of the bound we
did not prove here).

Guaranteed: :math:`m_t = 0`, straight sides, :math:`u_D`, :math:`g` and :math:`f` reproduced exactly by the
spaces (checked numerically: ``Equilibration.guaranteed`` is False, with the reason, when :math:`t` is not
admissible, when :math:`\sigma n` misses :math:`g` or :math:`u_D` is not met by :math:`s`).  For
:math:`m_t > 0` the friction bound depends on :math:`u` itself (a quasi-variational inequality, no
minimisation): the same number is computed with the friction bound frozen at :math:`u_h`, an estimate without
guarantee.  Symmetry sides are refused (ValueError).
"""

import math
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .contact import compliance, evaluate_on_contact, friction_bound, normal_tangent, positive_power
from .dg.forms import element_areas
from .meshes import element_diameters, facet_indicator, smallest_angles
from .problem import coefficient, exponents, strain, stress
from .reference import energy_norm_squared_parts

__all__ = ["Equilibration", "equilibrate", "potential", "equilibrated_stress", "contact_traction",
           "inf_sup_lower_bounds", "ADMISSIBLE"]

ADMISSIBLE = 1e-10  # relative violation of t's admissibility, of sigma n = g or s = u_D still called round-off
BONUS = 6  # extra quadrature degree of the non-polynomial contact integrands (kinks of (.)_+)


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
        ``"conformity"`` :math:`|b|^2`, ``"jumps"``, ``"contact"`` :math:`2 F\!Y`, ``"asymmetry"`` and
        ``"oscillation"`` (the two parts of :math:`\rho`, squared).
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


def potential(sol):
    """s: u_h averaged into continuous vector polynomials of its largest degree (NGSolve's Set: element-wise
    projections, averaged at shared DOFs), s = u_D interpolated on Gamma_D."""
    disc = sol.discretization
    problem, mesh = disc.problem, sol.mesh
    space = ngs.VectorH1(mesh, order=int(disc.order), dirichlet=problem.where("dirichlet"))
    s, boundary = ngs.GridFunction(space), ngs.GridFunction(space)
    s.Set(sol.u)
    boundary.Set(coefficient(problem.u_D), ngs.BND, definedon=mesh.Boundaries(problem.where("dirichlet")))
    fixed = ~np.asarray(list(space.FreeDofs()), dtype=bool)
    s.vec.FV().NumPy()[fixed] = boundary.vec.FV().NumPy()[fixed]
    return s


def _bernstein(degree, t):
    """Values of the Bernstein polynomials B_0..B_degree at parameters t, shape (len(t), degree + 1)."""
    t = np.asarray(t)[:, None]
    k = np.arange(degree + 1)[None]
    return np.array([math.comb(degree, j) for j in range(degree + 1)])[None] * t**k * (1 - t) ** (degree - k)


def contact_traction(sol):
    """(t_n, t_tau): multiplier-space GridFunctions with t = t_n n + t_tau t admissible on every contact edge:
    the forces c_n (u_n - g_a)_+^{m_n} and bound x lam_tau of u_h at the Gauss points, interpolated in the
    multiplier's degree, their Bernstein coefficients clipped to [0, oo) and [-bound, bound] (bound: its
    smallest Gauss value on the edge)."""
    disc = sol.discretization
    gauss = disc.gauss
    points = gauss.points
    shape = gauss.xy.shape[:2]
    size = shape[0] * shape[1]
    pressure = np.broadcast_to(evaluate_on_contact(compliance(disc.problem, sol.u), points), size)
    bound = np.broadcast_to(evaluate_on_contact(friction_bound(disc.problem, sol.u), points), size)
    lam = np.clip(gauss.values(sol.lam_tau), -1.0, 1.0)
    a, d = gauss.ends[:, 0], gauss.ends[:, 1] - gauss.ends[:, 0]
    nodes = np.einsum("eqk,ek->eq", gauss.xy - a[:, None], d) / np.sum(d * d, axis=1)[:, None]
    basis = np.stack([_bernstein(gauss.q - 1, row) for row in nodes])  # (edges, q, q)
    bound = bound.reshape(shape).min(axis=1, keepdims=True)

    def clipped(values, lo, hi):
        coefficients = np.linalg.solve(basis, values[..., None])[..., 0]
        return np.einsum("eqj,ej->eq", basis, np.clip(coefficients, lo, hi))

    t_n, t_tau = ngs.GridFunction(disc.Q), ngs.GridFunction(disc.Q)
    gauss.set_values(t_n, clipped(pressure.reshape(shape), 0.0, np.inf))
    gauss.set_values(t_tau, clipped(bound * lam, -bound, bound))
    return t_n, t_tau


SKEW_WEIGHT = 100.0  # weight of ||as sigma||^2 / (2 mu) in the minimisation (``equilibrated_stress``)


def equilibrated_stress(sol, traction, skew_weight=None):
    """(sigma, div sigma): the stress of the module docstring (a 2x2 CoefficientFunction, rows in RT_p) for the
    contact traction ``traction`` = (t_n, t_tau) of ``contact_traction``, and its divergence."""
    disc = sol.discretization
    problem, mesh, k = disc.problem, sol.mesh, int(disc.order)
    rows = ngs.HDiv(mesh, order=k, RT=True, discontinuous=True)
    facets = ngs.FacetFESpace(mesh, order=k, dirichlet=problem.where("dirichlet"))
    X = ngs.FESpace([rows, rows, ngs.VectorL2(mesh, order=k), ngs.L2(mesh, order=k - 1), facets, facets])
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
    load += -coefficient(problem.f) * v * ngs.dx(bonus_intorder=BONUS)
    load += -coefficient(problem.g) * mu_test * ngs.ds(problem.where("traction"), bonus_intorder=k + BONUS)
    load += facet_indicator(mesh, problem.where("contact")) * (t_n * n + t_tau * t) * mu_test * \
        ngs.dx(element_boundary=True, bonus_intorder=k + 2)
    form.Assemble()
    load.Assemble()
    inverse = form.mat.Inverse(X.FreeDofs(True), inverse="umfpack")
    solution = ngs.GridFunction(X)
    load.vec.data += form.harmonic_extension_trans * load.vec
    solution.vec.data = inverse * load.vec
    solution.vec.data += form.harmonic_extension * solution.vec
    solution.vec.data += form.inner_solve * load.vec
    rows = solution.components[0], solution.components[1]
    return tensor(*rows), ngs.CF(tuple(ngs.div(row) for row in rows))


def inf_sup_lower_bounds(mesh):
    """beta_T >= sin(omega_T / 2) per triangle, omega_T = half its smallest angle (the Horgan-Payne angle seen
    from the incentre; module docstring)."""
    return np.sin(smallest_angles(mesh) / 4)


def _element_values(mesh, density, order):
    return ngs.Integrate(density * ngs.dx(bonus_intorder=order), mesh, element_wise=True).NumPy().copy()


def _contact_gap(problem, s, traction, k, mesh):
    """Per element FY = j(s) + j*(t) - <t, s> on its contact edges, and the measures of t's inadmissibility
    (int (-t_n)_+ and int (|t_tau| - bound)_+, relative to int |t|)."""
    n, t = normal_tangent()
    t_n, t_tau = traction
    c_n, m, g_a = coefficient(problem.c_n), exponents(problem.m_n), coefficient(problem.g_a)
    m_n = max(m)
    if len(set(m)) > 1:
        raise ValueError(f"the equilibrated estimator needs one m_n on all contact sides, got {sorted(set(m))}")
    bound = friction_bound(problem, s)
    safe = ngs.IfPos(c_n, c_n, 1.0)
    conjugate = ngs.IfPos(c_n, t_n * g_a + m_n / (m_n + 1) * safe ** (-1 / m_n)
                          * ngs.IfPos(t_n, t_n, 0.0) ** ((m_n + 1) / m_n), 0.0)
    j_s = c_n / (m_n + 1) * positive_power(s * n - g_a, m_n + 1) + bound * ngs.sqrt((s * t) ** 2)
    on = facet_indicator(mesh, problem.where("contact"))
    measure = ngs.dx(element_boundary=True, bonus_intorder=2 * k + BONUS)
    gap = ngs.Integrate(on * (j_s + conjugate - t_n * (s * n) - t_tau * (s * t)) * measure, mesh,
                        element_wise=True).NumPy().copy()
    size = ngs.Integrate(on * (ngs.sqrt(t_n * t_n + t_tau * t_tau)) * measure, mesh)
    violation = ngs.sqrt(t_tau * t_tau) - bound
    excess = ngs.Integrate(on * (ngs.IfPos(-t_n, -t_n, 0.0) + ngs.IfPos(violation, violation, 0.0)) * measure, mesh)
    return np.maximum(gap, 0.0), excess / max(size, 1e-300)


def _misfits(problem, mesh, sigma, s, k):
    """Relative misfits of the data the spaces must reproduce: ||sigma n - g|| on Gamma_F over ||g|| + ||sigma n||,
    ||s - u_D|| on Gamma_D over ||u_D|| + ||s||, each scale at least the field's L2 norm on the domain over the
    square root of its diameter (a scale that exists when g = 0 or u_D = 0: no 0 / 0)."""
    n = ngs.specialcf.normal(2)
    g, u_D = coefficient(problem.g), coefficient(problem.u_D)
    measure = ngs.dx(element_boundary=True, bonus_intorder=k + BONUS)
    on_f, on_d = (facet_indicator(mesh, problem.where(part)) for part in ("traction", "dirichlet"))

    def norm(density, on):
        return ngs.Integrate(on * density * measure, mesh) ** 0.5

    def domain_scale(field):
        return (ngs.Integrate(ngs.InnerProduct(field, field), mesh) / problem.geometry.diameter()) ** 0.5

    miss_g, scale_g = norm((sigma * n - g) ** 2, on_f), norm(g * g + (sigma * n) ** 2, on_f)
    miss_u, scale_u = norm((s - u_D) ** 2, on_d), norm(u_D * u_D + s * s, on_d)
    scale_g, scale_u = max(scale_g, domain_scale(sigma), 1e-300), max(scale_u, domain_scale(s), 1e-300)
    return miss_g / scale_g, miss_u / scale_u


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
    Guaranteed for :math:`m_t = 0`, straight sides and data that the spaces reproduce exactly; for
    :math:`m_t > 0` the same number, with the friction bound frozen at :math:`u_h`, is an estimate without
    guarantee (``guaranteed`` is False and ``reason`` says why).

    Examples
    --------
    >>> problem = ndf.example_6_1()
    >>> sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
    >>> bound = ndf.equilibrate(sol)
    >>> print(f"{bound.eta_h:.1f}", bound.guaranteed)
    29.5 True
    >>> sorted(bound.terms_squared)
    ['asymmetry', 'conformity', 'contact', 'jumps', 'oscillation', 'stress']
    """
    disc = sol.discretization
    problem, mesh, u_h, k = disc.problem, sol.mesh, sol.u, int(disc.order)
    _check(problem)
    s = potential(sol)
    traction = contact_traction(sol)
    sigma, divergence = equilibrated_stress(sol, traction)
    mu = coefficient(problem.mu)
    symmetric = 0.5 * (sigma + sigma.trans)
    strain_h, strain_s = strain(u_h), strain(s)

    def energy(tau):  # tau : C^-1 tau
        return ngs.InnerProduct(compliance_inverse(problem, tau), tau)

    A, B = symmetric - stress(problem, strain_h), stress(problem, strain_s - strain_h)  # a = C^-1/2 A, b = C^-1/2 B
    order = 2 * k + 2
    parts = {"stress": _element_values(mesh, energy(A - B), order),
             "conformity": _element_values(mesh, energy(B), order)}
    sum_ab = _element_values(mesh, energy(A + B), order).sum()
    cross = _element_values(mesh, ngs.InnerProduct(A, strain_s - strain_h), order).sum()
    gap, excess = _contact_gap(problem, s, traction, k, mesh)
    parts["contact"] = 2 * gap
    # [u - u_h] = -[u_h] inside, u_D - u_h on Gamma_D
    _, parts["jumps"] = energy_norm_squared_parts(problem, mesh, u_h, element_wise=True,
                                                  dirichlet_value=coefficient(problem.u_D))
    beta = inf_sup_lower_bounds(mesh)
    stiff = _element_values(mesh, 2 * mu, order) / element_areas(mesh).vec.FV().NumPy()  # 2 mu, element mean
    skew = _element_values(mesh, (sigma[0, 1] - sigma[1, 0]) ** 2, order)
    load_residual = coefficient(problem.f) + divergence
    residual = _element_values(mesh, load_residual * load_residual, order + BONUS)
    asymmetry = 0.5 * (2 / beta) * np.sqrt(skew / stiff)
    oscillation = element_diameters(mesh) / np.pi * np.sqrt(1 + 2 / beta**2) * np.sqrt(residual / stiff)
    parts["asymmetry"], parts["oscillation"] = asymmetry**2, oscillation**2
    rho = float(np.sqrt(np.sum((asymmetry + oscillation) ** 2)))
    b = float(np.sqrt(parts["conformity"].sum()))
    half = (np.sqrt(max(sum_ab, 0.0)) + rho) / 2
    x = half + np.sqrt(max(half**2 + gap.sum() - cross + rho * b, 0.0))
    eta_h = float(np.sqrt(x**2 + parts["jumps"].sum()))
    reasons = []
    if max(exponents(problem.m_t)) > 0:
        reasons.append("m_t > 0: the friction bound depends on u (estimate with the bound frozen at u_h)")
    if excess > ADMISSIBLE:
        reasons.append(f"the contact traction is not admissible (relative violation {excess:.1e})")
    miss_g, miss_u = _misfits(problem, mesh, sigma, s, k)
    if miss_g > ADMISSIBLE:
        reasons.append(f"sigma n misses g on Gamma_F by {miss_g:.1e} (g is not a polynomial of degree <= {k})")
    if miss_u > ADMISSIBLE:
        reasons.append(f"s misses u_D on Gamma_D by {miss_u:.1e} (u_D is not a polynomial of degree <= {k})")
    element = sum(parts.values())
    return Equilibration(eta_h=eta_h, eta_T_squared=element, terms_squared={key: float(value.sum()) for key, value
                                                                           in parts.items()},
                         guaranteed=not reasons, reason="; ".join(reasons), sigma=sigma, s=s)
