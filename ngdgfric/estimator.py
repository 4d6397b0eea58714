r"""The residual a posteriori estimator :math:`\eta_h` of Section 4, element by element.

.. math::

    \eta_1^2 &= \sum_T (h_T/p)^2 \|f + \operatorname{div} \sigma_h(u_h)\|_T^2, \\
    \eta_2^2 &= \sum_{e \in \mathcal{E}_h^i} (h_e/p) \|[\![\sigma_h(u_h)]\!]\|_e^2, \\
    \eta_3^2 &= \sum_{e \in \mathcal{E}_h^o} \eta\, p^2/h_e \|[\![u_h]\!]\|_e^2, \\
    \eta_4^2 &= \sum_{e \in \mathcal{E}_h^C} (h_e/p)
        \|\sigma_{h,\tau}(u_h) + c_\tau (u_{hn} - g_a)_+^{m_t} \lambda_\tau\|_e^2, \\
    \eta_5^2 &= \sum_{e \in \mathcal{E}_h^F} (h_e/p) \|\sigma_h(u_h) n - g\|_e^2, \\
    \eta_6^2 &= \sum_{e \in \mathcal{E}_h^C} (h_e/p) \|\sigma_{h,n}(u_h) + c_n (u_{hn} - g_a)_+^{m_n}\|_e^2,

with :math:`[\![u_h]\!] = u_h - u_D` on :math:`\Gamma_D` (a prescribed displacement) and, on symmetry sides, the
jump of the normal part :math:`(u_h \cdot n) n` in :math:`\eta_3` and the tangential traction
:math:`\sigma_h(u_h) n \cdot t` (which must vanish there) in :math:`\eta_5`.  These are the terms of
``estimate(sol, variant="paper")``; the default (``variant="energy"``) divides the residual terms by
:math:`2\mu` and replaces the pressure part of :math:`\sigma_h(u_h)` by a continuous average (below), so that
:math:`\eta_h` estimates :math:`|\!|\!| u - u_h |\!|\!|_h` in its units.

For :math:`p = 1` and :math:`m_t = 0` these are exactly the terms of Section 4
(:math:`\operatorname{div} \sigma_h(u_h) = 0` for piecewise linear :math:`u_h`, so :math:`\eta_1` involves
:math:`f` only); for :math:`m_t > 0`, :math:`\eta_4` carries the friction bound at :math:`u_h`, as the friction
force of (1.9) does; for :math:`p > 1` they carry the usual hp weights :math:`h/p` and the element residual
:math:`f + \operatorname{div} \sigma_h(u_h)`.  With a variable order (hp), :math:`p` is :math:`p_T` of the
element integrated over (volume terms and the element's share of edge terms) and :math:`\eta_3` uses the
penalty of the forms, with :math:`p_e = \max(p_{T^+}, p_{T^-})`.  :math:`\eta_3` uses the method's edge
penalty :math:`\eta\, p^2/h_e` with the forms' :math:`h_e` (``penalty_length`` of :mod:`ngdgfric.dg.forms`;
the others use the edge length :math:`|e|`) (for the lifting methods :math:`2\mu\,\eta\, p^2/h_e`, see
``jump_weight`` of :class:`ngdgfric.Method`).  Edge terms of interior edges are shared half-half by the two
neighbours; boundary edges go to their element.  The element values are those of
``Integrate(..., element_wise=True)``, computed for all six terms in one assembly (``element_integrals``).

``variant="energy"`` (default): an estimate of :math:`|\!|\!| u - u_h |\!|\!|_h` in its own units, robust in
the scale of :math:`E` and, for the methods that do not lock, in :math:`\nu \to 1/2`.  Write the discrete stress
as :math:`\sigma_h = 2\mu\, \varepsilon_h(u_h) + p_h I` with :math:`p_h = \lambda \operatorname{div}_h u_h`, let
:math:`\tilde p_h` be the continuous average of :math:`p_h` (``averaged_pressure``) and
:math:`\tilde\sigma_h = 2\mu\, \varepsilon_h(u_h) + \tilde p_h I`.  For :math:`v \in H^1` vanishing on
:math:`\Gamma_D` the residual splits as

.. math::

    R(v) = l(v) - (\tilde\sigma_h, \varepsilon(v)) - \mathrm{contact}(v) - (p_h - \tilde p_h, \operatorname{div} v),

the first part a residual of :math:`\tilde\sigma_h`, bounded by the usual terms (Clement interpolation,
:math:`\|v - I v\|_T \lesssim h_T / p\, |v|_{1, \omega_T}`, Korn) times
:math:`|v|_1 \lesssim |\!|\!| v |\!|\!| / \sqrt{2\mu}`; the second by

.. math::

    \|p_h - \tilde p_h\| \|\operatorname{div} v\| \le \|p_h - \tilde p_h\| \sqrt{2} \|\varepsilon(v)\|
    \le \|p_h - \tilde p_h\| |\!|\!| v |\!|\!| / \sqrt{\mu}.

Hence every residual term carries the weight :math:`1 / (2\mu)` and no constant depends on :math:`\lambda`, as in
the :math:`\lambda`-robust bounds of Houston, Schoetzau & Wihler (CMAME 195, 2006, the pressure a separate
unknown weighted by :math:`1/\mu`) and Wihler (Math. Comp. 75, 2006); the averaging is the Oswald
interpolation of Karakashian & Pascal (SINUM 41, 2003) applied to the pressure.  Using :math:`\tilde p_h`
instead of :math:`p_h` matters for :math:`\nu \to 1/2`: :math:`h_T \|\nabla p_h\|` and the jumps
:math:`[\![p_h]\!]` of an oscillating discrete pressure are much larger than the pressure's share
:math:`\lambda \|\operatorname{div}(u - u_h)\|^2` of the energy error (:ref:`decisions-estimator`).  Where the
material jumps across edges (``Material.jumps`` of
:mod:`ngdgfric.dg.material`) the pressure jumps with it and is not averaged: the terms use
:math:`\sigma_h(u_h)` itself (still divided by :math:`2\mu`).

Calibrated constant: every element indicator is multiplied by :math:`p_T^{-1/2}`.  The hp weights :math:`h/p`
make residual estimators reliable with a constant independent of :math:`p` but efficient only up to
powers of :math:`p` (Melenk & Wohlmuth, Adv. Comput. Math. 15, 2001), and
:math:`\eta_h / |\!|\!| u - u_h |\!|\!|_h` grew with :math:`p` as :math:`p^{1/2}`: medians 1 : 1.32 : 1.67 :
1.93 for :math:`p = 1, 2, 3, 4` on Example 6.1 (SIPG, uniform and h-adaptive levels, against the hp reference),
the cases the factor was chosen on; the results page *Effectivity* checks it on every other case (the other
example, the five methods, the manufactured solutions at :math:`E = 1 \dots 10^6`, :math:`\nu` up to 0.4999).

The terms (all but :math:`\eta_3` divided by :math:`2\mu`, element-wise average of :math:`\mu` when :math:`E`
varies; where the material varies, :math:`\mu` and :math:`\lambda` are the element-wise fields :math:`C_h` of
:mod:`ngdgfric.dg.material` that the forms use, and :math:`\eta_1` also carries their data oscillation
:math:`\int_T |(C - C_h) \varepsilon_h(u_h)|^2 / (2\mu)` with the true :math:`C` and :math:`\mu` pointwise and no
calibration factor, the stress that :math:`C_h` misses in energy units: zero on a mesh that follows the
material's jumps, the error of the element means where a jump cuts elements):

.. math::

    \eta_1^2 &= \sum_T (h_T/p)^2 \|f + \operatorname{div} \tilde\sigma_h\|_T^2 + \|p_h - \tilde p_h\|_T^2
        \quad \text{(+ the oscillation above)}, \\
    \eta_2^2 &= \sum_{e \in \mathcal{E}_h^i} (h_e/p) \|[\![\tilde\sigma_h n]\!]\|_e^2
        \quad (= [\![2\mu\, \varepsilon_h(u_h) n]\!]: \tilde p_h \text{ is continuous}),

:math:`\eta_4`, :math:`\eta_5`, :math:`\eta_6` with :math:`\tilde\sigma_h n` in place of :math:`\sigma_h(u_h) n`;
:math:`\eta_3` as printed (a penalty: already in energy units).
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .checks import check_solution
from .contact.boundary import contact_elements, normal_tangent
from .contact.forms import contact_residuals
from .contact.pair_residuals import pair_terms
from .dg.forms import SYMMETRY_WEIGHT, edge_order, edge_penalty, jump_inner, normal_part
from .dg.material import MATERIAL_BONUS
from .errors import warn
from .meshes import boundary_elements, element_diameters, facet_indicator
from .problem import PARTS, coefficient, strain, stress
from .threads import limited_blas, threads

__all__ = ["Estimate", "estimate", "residual_parts", "div_stress", "KINDS", "VARIANTS"]


@dataclass
class Estimate:
    r"""The estimator of a solution: element indicators, the terms and :math:`\eta_h`.

    What :func:`ngdgfric.estimate` returns.

    Parameters
    ----------
    eta_T_squared : numpy.ndarray
        :math:`\eta_T^2` per element, in the mesh's element order (for marking, :func:`ngdgfric.dorfler_mark`).
    terms_squared : dict
        The global :math:`\eta_1^2, \dots, \eta_6^2` (keys ``"eta1"`` ... ``"eta6"``); for
        ``kind="equilibrated"`` the equilibrated bound's parts (:class:`ngdgfric.Equilibration`).
    eta_h : float
        :math:`\eta_h = (\sum_T \eta_T^2)^{1/2}` (the guaranteed bound for ``"equilibrated"``,
        :mod:`ngdgfric.equilibration`).
    kind : str, optional
        ``"residual"`` (default) or ``"equilibrated"``.
    guaranteed : bool, optional
        True only for an equilibrated bound whose assumptions were all met.  Default ``False``.
    reason : str, optional
        Why the estimate is not guaranteed.  Default ``"the residual estimator's constants are not known"``.
    """

    eta_T_squared: np.ndarray
    terms_squared: dict
    eta_h: float
    kind: str = "residual"
    guaranteed: bool = False
    reason: str = "the residual estimator's constants are not known"


def div_stress(material, u, pressure=True):
    """div sigma(u) element by element, from the Hessian of u: 2 mu div eps(u) + lam grad div u, plus
    2 eps(u) grad mu + div u grad lam where the material varies (``material``: the
    ``Material`` of the discretisation); ``pressure=False`` gives the deviatoric
    part div(2 mu eps(u))."""
    mu, lam = material.mu, material.lam
    H = u.Operator("hesse")  # H[4 c + 2 a + b] = d_a d_b u_c
    hess = lambda c, a, b: H[4 * c + 2 * a + b]  # noqa: E731
    div_eps = ngs.CF(tuple(0.5 * sum(hess(i, j, j) + hess(j, i, j) for j in range(2)) for i in range(2)))
    result = 2 * mu * div_eps
    if pressure:
        result = result + lam * ngs.CF(tuple(sum(hess(j, i, j) for j in range(2)) for i in range(2)))
    if not material.constant:
        result = result + 2 * strain(u) * ngs.Grad(mu)
        if pressure:
            result = result + ngs.Trace(strain(u)) * ngs.Grad(lam)
    return result


def element_integrals(mesh, integrands, degrees, extra=2):
    """{name: per-element integrals (numpy)} of {name: [(cf, on_boundary[, where]), ...]} (cf over the element, or over
    its boundary where ``on_boundary``; only on the elements ``where`` (boolean per element) if given, zero on the
    others), in one assembly, each element with a Gauss rule of degree 2 p_T + ``extra``
    for its own polynomial degree p_T (``degrees``, one per element): exact for the polynomial parts of
    the squared residuals, and on hp meshes not the largest degree's rule everywhere (on the hp levels of
    Example 6.2, p_T = 4 ... 8: a third of the time, the same values to round-off).

    The same numbers as ``Integrate(cf * dx(bonus_intorder=q), mesh, order=q, element_wise=True)`` per group of
    elements of one degree, from one LinearForm on a product of piecewise-constant spaces (basis function 1 on
    each element, so the quadrature order is the bonus) with one integrator per term and degree
    (``definedonelements``), traversing the mesh once for all terms.  Integrands must not use ``Other()`` (a
    LinearForm does not set up the neighbour's integration point).
    """
    names = list(integrands)
    space = ngs.FESpace([ngs.L2(mesh, order=0)] * len(names))
    form = ngs.LinearForm(space)
    degrees = np.asarray(degrees)
    groups = [(int(p), degrees == p) for p in np.unique(degrees)]
    for name, v in zip(names, space.TestFunction(), strict=True):
        for cf, on_boundary, *where in integrands[name]:
            for p, elements in groups:
                if where:
                    elements = elements & where[0]
                elif len(groups) == 1:
                    elements = None
                if elements is not None and not elements.any():
                    continue
                measure = ngs.dx(element_boundary=on_boundary, bonus_intorder=2 * p + extra,
                                 definedonelements=None if elements is None else ngs.BitArray(list(elements)))
                form += cf * v * measure
    with threads(space.ndof * 20):
        form.Assemble()
    values = form.vec.FV().NumPy().reshape(len(names), mesh.ne)
    return {name: values[k].copy() for k, name in enumerate(names)}


VARIANTS = ("energy", "paper")  # the variants of the residual estimator (``estimate``)
KINDS = ("residual", "equilibrated")  # the estimators of ``estimate``


def discrete_pressure(material, u):
    """p_h = lam div_h u_h = lam tr eps_h(u_h), element by element."""
    return material.lam * ngs.Trace(strain(u))


def averaged_pressure(material, u, order):
    """p~_h: p_h made continuous (NGSolve's ``Set`` into H^1 of degree ``order``: local projections,
    averaged at shared vertices and edges, an Oswald-type average)."""
    pressure = ngs.GridFunction(ngs.H1(u.space.mesh, order=int(order)))
    pressure.Set(discrete_pressure(material, u))
    return pressure


def deprecated_weights(variant, weights, where):
    """``variant``, or the value of the old keyword ``weights`` of ``where`` (``estimate``, :func:`ngdgfric.adapt`)
    with a DeprecationWarning: it selects a variant of the estimator, it weights nothing."""
    if weights is None:
        return variant
    warn(f"{where}(weights=...) is deprecated and will be removed in the next release: use "
         f"variant={weights!r} (it selects the estimator's variant)", DeprecationWarning)
    if variant is not None and variant != weights:
        raise ValueError(f"{where}: variant={variant!r} and its old name weights={weights!r} disagree; give variant "
                         f"only")
    return weights


@limited_blas
def estimate(sol, variant=None, kind="residual", weights=None):
    r"""Element indicators :math:`\eta_T^2` and the six terms of :math:`\eta_h` for a Solution.

    The residual estimator of Section 4, in two variants (:mod:`ngdgfric.estimator` states the terms and the
    weights), or the guaranteed upper bound of an equilibrated stress.

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`).
    variant : str or None, optional
        The variant of the residual estimator: ``"energy"`` (``None``, the default: the estimate of
        :math:`|\!|\!| u - u_h |\!|\!|_h` in its own units described in :mod:`ngdgfric.estimator`) or
        ``"paper"`` (the terms of Section 4 as printed).  Refused with ``kind="equilibrated"``.
    kind : str, optional
        ``"residual"`` (default): the estimator of Section 4 in its ``variant``.  ``"equilibrated"``: instead,
        the guaranteed upper bound of :math:`|\!|\!| u - u_h |\!|\!|_h` from an equilibrated stress
        (:func:`ngdgfric.equilibrate`), which has no variants.
    weights : str or None, optional
        The old name of ``variant`` (DeprecationWarning; it selects a variant, it weights nothing).

    Returns
    -------
    Estimate
        The element indicators, the terms and :math:`\eta_h` (:class:`ngdgfric.Estimate`).

    Raises
    ------
    ValueError
        An unknown ``kind`` or ``variant``, a ``variant`` with ``kind="equilibrated"``, ``weights`` and
        ``variant`` that disagree; for ``kind="equilibrated"``, a problem with symmetry sides.

    See Also
    --------
    ngdgfric.equilibrate : The equilibrated bound with its stress and conforming displacement.
    ngdgfric.dorfler_mark : Marks elements by their indicators.

    Examples
    --------
    >>> problem = ndf.example_6_1()
    >>> sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
    >>> est = ndf.estimate(sol)
    >>> sorted(est.terms_squared)
    ['eta1', 'eta2', 'eta3', 'eta4', 'eta5', 'eta6']
    >>> print(f"{est.eta_h:.2f}", len(est.eta_T_squared) == sol.mesh.ne)
    21.52 True
    >>> bound = ndf.estimate(sol, kind="equilibrated")
    >>> print(f"{bound.eta_h:.1f}", bound.guaranteed)
    22.3 True
    """
    check_solution(sol, "sol")
    variant = deprecated_weights(variant, weights, "estimate")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    if variant not in (None, *VARIANTS):
        raise ValueError(f"variant must be one of {VARIANTS}, got {variant!r}")
    if kind == "equilibrated":
        if variant is not None:
            raise ValueError(f"variant={variant!r} is a variant of the residual estimator; kind='equilibrated' has "
                             f"none and would ignore it")
        from .equilibration import equilibrate

        bound = equilibrate(sol)
        return Estimate(eta_T_squared=bound.eta_T_squared, terms_squared=bound.terms_squared, eta_h=bound.eta_h,
                        kind=kind, guaranteed=bound.guaranteed, reason=bound.reason)
    variant = variant or "energy"
    parts = residual_parts(sol, variant)
    if variant == "energy":
        parts = _in_energy_units(sol, parts)
    element = sum(parts.values())
    return Estimate(eta_T_squared=element, terms_squared={k: float(v.sum()) for k, v in parts.items()},
                    eta_h=float(np.sqrt(element.sum())))


def residual_parts(sol, variant):
    """{"eta1": eta_1^2 per element, ..., "eta6": ...} of Section 4 (numpy arrays), with the stress of ``variant``
    (``_stress_and_volume_term``) and before the energy units' weights (``_in_energy_units``)."""
    disc = sol.discretization
    problem, mesh, u, p = disc.problem, sol.mesh, sol.u, disc.p
    n, t = normal_tangent()
    h_e, h_penalty = disc.h_e, disc.h_penalty
    weight = disc.method.jump_weight(disc.material, disc.penalty)
    on = {part: facet_indicator(mesh, problem.where(part)) for part in PARTS}
    near = {part: boundary_elements(mesh, [on[part]]) for part in PARTS}  # the boundary terms live there only
    sigma, neighbour, volume = _stress_and_volume_term(sol, variant)
    sigma_n = sigma * n
    traction_residual = sigma_n - coefficient(problem.g)
    friction_residual, normal_residual = contact_residuals(problem, sigma_n, u, sol.lam_tau)
    off, normal = u - coefficient(problem.u_D), normal_part(u, n)
    parts = element_integrals(mesh, {
        "eta1": [(volume, False)],
        "eta3": [(edge_penalty(weight.boundary, p, h_penalty.boundary)
                  * (on["dirichlet"] * jump_inner(off, off, n)
                     + SYMMETRY_WEIGHT * on["symmetry"] * jump_inner(normal, normal, n)), True,
                  near["dirichlet"] | near["symmetry"])],
        "eta4": [(on["contact"] * h_e / p * friction_residual**2, True, near["contact"])],
        "eta5": [(h_e / p * (on["traction"] * ngs.InnerProduct(traction_residual, traction_residual)
                             + on["symmetry"] * (sigma_n * t) ** 2), True, near["traction"] | near["symmetry"])],
        "eta6": [(on["contact"] * h_e / p * normal_residual**2, True, near["contact"])],
    }, _degrees(disc))
    # the jump terms need the neighbour (Other()), which only Integrate provides on element boundaries
    # (on boundary edges u - u.Other() evaluates to zero, so these terms cover interior edges only)
    # (the conforming baseline's u_h has no jumps: its eta_3 lives on the supports only); quadrature order 2p + 2
    # (exact for the polynomial parts; Integrate's default 5 is too low for p >= 3) with the largest p
    jump_sigma, jump_u = sigma_n - neighbour * n, u - u.Other()
    jump_measure = ngs.dx(element_boundary=True, bonus_intorder=max(2 * disc.order + 2 - 5, 0))
    jumps = [("eta2", 0.5 * h_e / p * jump_sigma * jump_sigma)]
    if not disc.method.conforming:
        jumps.append(("eta3", 0.5 * edge_penalty(weight.interior, edge_order(p), h_penalty.interior)
                      * jump_inner(jump_u, jump_u, n)))
    for name, integrand in jumps:
        parts[name] = parts.get(name, 0) + ngs.Integrate(integrand * jump_measure, mesh, element_wise=True).NumPy()
    if problem.pairs:
        pair_eta4, pair_eta6 = pair_terms(sol, sigma)
        parts["eta4"], parts["eta6"] = parts["eta4"] + pair_eta4, parts["eta6"] + pair_eta6
    return {name: parts[name] for name in sorted(parts)}


def _in_energy_units(sol, parts):
    """The terms of ``residual_parts`` (variant "energy") in the units of the energy norm: the residual terms
    divided by 2 mu, all calibrated by p_T^(-1/2), and eta_1 with the material's oscillation (module docstring)."""
    disc = sol.discretization
    calibration = 1.0 / np.asarray(disc.orders, dtype=float)  # (p_T^(-1/2))^2, see the module docstring
    residual_weight = calibration * _inverse_stiffness(disc.material, sol.mesh)
    parts = {name: value * (calibration if name == "eta3" else residual_weight) for name, value in parts.items()}
    if not disc.material.constant:
        parts["eta1"] = parts["eta1"] + _material_oscillation(sol, 2 * disc.order + 2 + MATERIAL_BONUS)
    return parts


def _degrees(disc):
    """The degree of every element's integrands for ``element_integrals``: its polynomial degree, the largest
    on elements along Gamma_C (the multiplier has the largest degree on every edge there)."""
    degrees = disc.degrees.copy()
    degrees[contact_elements(disc.problem, disc.mesh)] = disc.order
    return degrees


def _stress_and_volume_term(sol, variant):
    """(sigma, the neighbour's sigma, the integrand of eta_1^2) for the ``variant`` of ``estimate``:
    sigma_h(u_h) for "paper", sigma~_h = 2 mu eps_h(u_h) + p~_h I for "energy" (mu, lam each element's own),
    but sigma_h(u_h) where the material jumps: the pressure lam div u jumps there too, and a continuous
    p~_h would leave ||p_h - p~_h|| = O(1) along the interface (eta_h falling like N^(-1/2), seen on a
    bimaterial strip)."""
    problem, u, disc = sol.discretization.problem, sol.u, sol.discretization
    material = disc.material
    h_T = ngs.GridFunction(ngs.L2(sol.mesh, order=0))
    h_T.vec.FV().NumPy()[:] = element_diameters(sol.mesh)
    zero = ngs.CF((0, 0))
    varying = disc.order > 1 or not material.constant  # div sigma_h(u_h) = 0 for P1 and a constant material
    if variant == "paper" or material.jumps:
        residual = coefficient(problem.f) + (div_stress(material, u) if varying else zero)
        volume = (h_T / disc.p) ** 2 * residual * residual
        sigma = stress(material.own, strain(u))
        return sigma, sigma.Other(), volume
    pressure = averaged_pressure(material, u, disc.order)
    residual = coefficient(problem.f) + (div_stress(material, u, pressure=False) if varying else zero) + \
        ngs.Grad(pressure)
    difference = discrete_pressure(material, u) - pressure
    volume = (h_T / disc.p) ** 2 * residual * residual + difference * difference
    deviatoric = 2 * material.mu * strain(u)
    return deviatoric + pressure * ngs.Id(2), deviatoric.Other() + pressure * ngs.Id(2), volume


def _material_oscillation(sol, order):
    """Per element int_T (C - C_h) eps_h(u_h) : (C - C_h) eps_h(u_h) / (2 mu) dx with the problem's C and
    mu at every point: the stress the forms' element-wise material C_h (:mod:`ngdgfric.dg.material`) misses, in
    energy units (zero where C_h = C, on a mesh that follows the material's jumps).  Gauss degree ``order``."""
    problem, u = sol.discretization.problem, sol.u
    missed = stress(problem, strain(u)) - stress(sol.discretization.material.own, strain(u))
    density = ngs.InnerProduct(missed, missed) / (2 * coefficient(problem.mu))
    return ngs.Integrate(density * ngs.dx(bonus_intorder=max(order - 5, 0)), sol.mesh, element_wise=True).NumPy()


def _inverse_stiffness(material, mesh):
    """1 / (2 mu) per element (mu may vary: its element average)."""
    mu = material.mu
    if not isinstance(mu, ngs.CoefficientFunction):
        return 1.0 / (2.0 * mu)
    area = ngs.Integrate(ngs.CF(1) * ngs.dx, mesh, element_wise=True).NumPy()
    return area / (2.0 * ngs.Integrate(mu * ngs.dx, mesh, element_wise=True).NumPy())
