"""The residual a posteriori estimator eta_h of Section 4, element by element.

    eta_1^2 = sum_T (h_T/p)^2 ||f + div sigma_h(u_h)||_T^2
    eta_2^2 = sum_{e in E_h^i} (h_e/p) ||[sigma_h(u_h)]||_e^2
    eta_3^2 = sum_{e in E_h^o} eta p^2/h_e ||[u_h]||_e^2
    eta_4^2 = sum_{e in E_h^C} (h_e/p) ||sigma_h,tau(u_h) + c_tau (u_hn - g_a)_+^{m_t} lam_tau||_e^2
    eta_5^2 = sum_{e in E_h^F} (h_e/p) ||sigma_h(u_h) n - g||_e^2
    eta_6^2 = sum_{e in E_h^C} (h_e/p) ||sigma_h,n(u_h) + c_n (u_hn - g_a)_+^{m_n}||_e^2

For p = 1 and m_t = 0 these are exactly the terms of Section 4 (div sigma_h(u_h) = 0 for piecewise
linear u_h, so eta_1 involves f only); for m_t > 0, eta_4 carries the friction bound at u_h, as
the friction force of (1.9) does; for p > 1 they carry the usual hp weights h/p and the element
residual f + div sigma_h(u_h).  With a variable order (hp), p is p_T of the element integrated
over (volume terms and the element's share of edge terms) and eta_3 uses the penalty of the
forms, with p_e = max(p_T+, p_T-).  eta_3 uses the method's edge penalty eta p^2/h_e (for the lifting
methods 2 mu eta p^2/h_e, see :func:`ngdgfric.forms.jump_penalty`).  Edge terms of interior edges are shared
half-half by the two neighbours; boundary edges go to their element.  The element values are
those of ``Integrate(..., element_wise=True)``, computed for all six terms in one assembly
(:func:`element_integrals`).
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .contact import compliance, normal_tangent
from .forms import edge_order, jump_inner, jump_penalty, strain, stress
from .linalg import threads
from .meshes import element_diameters, facet_indicator

__all__ = ["Estimate", "estimate", "div_stress"]


@dataclass
class Estimate:
    """element: eta_T^2 per element (numpy); parts: global eta_1^2 ... eta_6^2; total: eta_h."""

    element: np.ndarray
    parts: dict
    total: float
    element_parts: dict


def div_stress(problem, u):
    """div sigma(u) = 2 mu div eps(u) + lam grad div u, from the Hessian of u (elementwise)."""
    H = u.Operator("hesse")  # H[4 c + 2 a + b] = d_a d_b u_c
    hess = lambda c, a, b: H[4 * c + 2 * a + b]  # noqa: E731
    div_eps = [0.5 * sum(hess(i, j, j) + hess(j, i, j) for j in range(2)) for i in range(2)]
    grad_div = [sum(hess(j, i, j) for j in range(2)) for i in range(2)]
    return ngs.CF(tuple(2 * problem.mu * div_eps[i] + problem.lam * grad_div[i] for i in range(2)))


def element_integrals(mesh, integrals):
    """{name: per-element integrals (numpy)} of scalar integrals {name: cf * measure}, in one assembly.

    The same numbers as ``Integrate(integral, mesh, order=q, element_wise=True)`` for each name
    when the measures carry ``bonus_intorder=q``, from one LinearForm on a product of
    piecewise-constant spaces (basis function 1 on each element, so the quadrature order is the
    bonus), traversing the mesh once for all terms.  Integrands must not use ``Other()`` (a
    LinearForm does not set up the neighbour's integration point).
    """
    names = list(integrals)
    space = ngs.FESpace([ngs.L2(mesh, order=0)] * len(names))
    form = ngs.LinearForm(space)
    for name, v in zip(names, space.TestFunction(), strict=True):
        for integral in integrals[name]:
            form += integral.coef * v * integral.symbol
    with threads(space.ndof * 20):
        form.Assemble()
    values = form.vec.FV().NumPy().reshape(len(names), mesh.ne)
    return {name: values[k].copy() for k, name in enumerate(names)}


def _vector(value):
    return value if isinstance(value, ngs.CoefficientFunction) else ngs.CF(tuple(value))


def estimate(sol):
    """Element indicators and the six terms of eta_h for a Solution (see module docstring)."""
    disc = sol.discretization
    problem, mesh, u, p = sol.problem, sol.mesh, sol.u, disc.p
    n, t = normal_tangent()
    h_e = disc.h_e
    h_T = ngs.GridFunction(ngs.L2(mesh, order=0))
    h_T.vec.FV().NumPy()[:] = element_diameters(mesh)
    sigma_n = stress(problem, strain(u)) * n
    jump_u = u - u.Other()
    penalty = jump_penalty(problem, disc.method, disc.eta, edge_order(p), h_e)
    boundary_penalty = jump_penalty(problem, disc.method, disc.eta, p, h_e)
    # quadrature order 2p + 2 (exact for the polynomial parts; Integrate's default 5 is too low
    # for p >= 3): the LinearForm of element_integrals integrates with the bonus order alone,
    # Integrate with 5 + bonus
    q = 2 * disc.order + 2
    boundary = ngs.dx(element_boundary=True, bonus_intorder=q)
    jump_measure = ngs.dx(element_boundary=True, bonus_intorder=max(q - 5, 0))
    on = {name: facet_indicator(mesh, name) for name in problem.boundary_names()}

    residual = _vector(problem.f) + (div_stress(problem, u) if disc.order > 1 else ngs.CF((0, 0)))
    jump_sigma = sigma_n - stress(problem, strain(u)).Other() * n
    contact = on[problem.contact]
    traction_residual = sigma_n - _vector(problem.g)
    parts = element_integrals(mesh, {
        "eta1": (h_T / p) ** 2 * residual * residual * ngs.dx(bonus_intorder=q),
        "eta3": on[problem.dirichlet] * boundary_penalty * jump_inner(u, u, n) * boundary,
        "eta4": contact * h_e / p * (sigma_n * t + disc.bound(u) * sol.lam_tau) ** 2 * boundary,
        "eta5": on[problem.traction] * h_e / p * ngs.InnerProduct(traction_residual, traction_residual) * boundary,
        "eta6": contact * h_e / p * (sigma_n * n + compliance(problem, u)) ** 2 * boundary,
    })
    # the jump terms need the neighbour (Other()), which only Integrate provides on element boundaries
    # (on boundary edges u - u.Other() evaluates to zero, so these terms cover interior edges only)
    for name, integrand in (("eta2", 0.5 * h_e / p * jump_sigma * jump_sigma),
                            ("eta3", 0.5 * penalty * jump_inner(jump_u, jump_u, n))):
        parts[name] = parts.get(name, 0) + ngs.Integrate(integrand * jump_measure, mesh, element_wise=True).NumPy()
    parts = {name: parts[name] for name in sorted(parts)}
    element = sum(parts.values())
    return Estimate(element=element, parts={k: float(v.sum()) for k, v in parts.items()},
                    total=float(np.sqrt(element.sum())), element_parts=parts)
