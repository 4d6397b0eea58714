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
half-half by the two neighbours; boundary edges go to their element.  Everything is computed
with ``Integrate(..., element_wise=True)``.
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .contact import compliance, normal_tangent
from .forms import edge_order, jump_inner, jump_penalty, strain, stress
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
    boundary = ngs.dx(element_boundary=True)
    on = {name: facet_indicator(mesh, name) for name in problem.boundary_names()}

    def element_wise(cf, measure=boundary):
        return ngs.Integrate(cf * measure, mesh, element_wise=True).NumPy().copy()

    residual = _vector(problem.f) + (div_stress(problem, u) if disc.order > 1 else ngs.CF((0, 0)))
    jump_sigma = sigma_n - stress(problem, strain(u)).Other() * n
    contact = on[problem.contact]
    traction_residual = sigma_n - _vector(problem.g)
    parts = {
        "eta1": element_wise((h_T / p) ** 2 * residual * residual, ngs.dx),
        "eta2": element_wise(0.5 * h_e / p * jump_sigma * jump_sigma),
        "eta3": element_wise(0.5 * penalty * jump_inner(jump_u, jump_u, n))
        + element_wise(on[problem.dirichlet] * boundary_penalty * jump_inner(u, u, n)),
        "eta4": element_wise(contact * h_e / p * (sigma_n * t + disc.bound(u) * sol.lam_tau) ** 2),
        "eta5": element_wise(on[problem.traction] * h_e / p * ngs.InnerProduct(traction_residual, traction_residual)),
        "eta6": element_wise(contact * h_e / p * (sigma_n * n + compliance(problem, u)) ** 2),
    }
    element = sum(parts.values())
    return Estimate(element=element, parts={k: float(v.sum()) for k, v in parts.items()},
                    total=float(np.sqrt(element.sum())), element_parts=parts)
