r"""The contact terms of (3.1)/(3.3) as symbolic forms on :math:`\Gamma_C`, the residual of (3.3), and the contact
residuals of the estimator.

With the multiplier :math:`\lambda_\tau t` of Lemma 3.1 (a scalar :math:`\lambda_\tau` in 2D)

.. math::

    j_n(u, v) = \int_{\Gamma_C} c_n (u_n - g_a)_+^{m_n} v_n \, ds, \qquad
    g(u; \lambda_\tau, v) = \int_{\Gamma_C} c_\tau (u_n - g_a)_+^{m_t} \lambda_\tau (v \cdot t) \, ds,

by the contact Gauss rule (:mod:`ngdgfric.contact.boundary`).  For :math:`m_t > 0` the friction bound depends on
:math:`u` (1.9); the residual of (3.3) is written once for both laws, its friction term with the bound at
:math:`u` (:math:`c_\tau` itself for :math:`m_t = 0`).  The fixed point on the bound solves problems with the bound
frozen (``frozen_bound``).  The laws themselves are :mod:`ngdgfric.contact.laws`; here they are applied to a
problem, side by side where the contact sides have their own exponents.
"""

import dataclasses

import ngsolve as ngs

from ..problem import PerSide, coefficient, exponents
from ..threads import threads
from . import laws
from .boundary import normal_tangent

__all__ = ["penetration", "compliance", "friction_bound", "compliance_form", "friction_force", "friction_matrix",
           "frozen_bound", "residual_terms", "residual", "contact_residuals"]


def penetration(problem, u):
    """u_n - g_a: positive where the body penetrates the foundation (1.8)."""
    n, _ = normal_tangent()
    return u * n - coefficient(problem.g_a)


def _side_by_side(exponent, law):
    """law(m) for an exponent m given as a number; on a mesh where it is given per contact side
    (:class:`ngdgfric.problem.PerSide`) the sum of law(m_s) times the indicator of side s."""
    return exponent.combine(law) if isinstance(exponent, PerSide) else law(exponent)


def compliance(problem, u):
    """Contact pressure c_n (u_n - g_a)_+^{m_n}, so that sigma_n(u) = -compliance (1.8)."""
    d = penetration(problem, u)
    return _side_by_side(problem.m_n, lambda m: laws.pressure(d, coefficient(problem.c_n), m))


def friction_bound(problem, u):
    """The friction bound c_tau (u_n - g_a)_+^{m_t} of (1.9) at u; c_tau itself for the reduced law m_t = 0
    (also on the contact sides with m_t = 0 when the sides have their own m_t)."""
    if max(exponents(problem.m_t)) == 0:
        return coefficient(problem.c_tau)
    d = penetration(problem, u)
    return _side_by_side(problem.m_t, lambda m: laws.bound(d, coefficient(problem.c_tau), m))


def compliance_form(problem, dS, u, v):
    """j_n(u, v) = int_{Gamma_C} c_n (u_n - g_a)_+^{m_n} v_n ds (Gauss rule ``dS``), a symbolic integral."""
    n, _ = normal_tangent()
    return compliance(problem, u) * (v * n) * dS


def friction_force(bound, lam_tau, v, dS):
    """g(lam_tau, v) = int_{Gamma_C} bound lam_tau (v . t) ds for a friction bound (a number or a
    CoefficientFunction), a symbolic integral."""
    _, t = normal_tangent()
    return coefficient(bound) * lam_tau * (v * t) * dS


def friction_matrix(contact, bound):
    """The matrix of g(lam_tau, v) (trial space ``contact.Q``, test space V_h) for a friction bound given as a
    number or a CoefficientFunction: c_tau (m_t = 0), or the bound at a fixed u."""
    lam_tau, v = contact.Q.TrialFunction(), contact.V_plain.TestFunction()
    g = ngs.BilinearForm(trialspace=contact.Q, testspace=contact.V_plain)
    g += friction_force(bound, lam_tau, v, contact.dS)
    with threads(contact.V.ndof):
        g.Assemble()
    return g.mat


def frozen_bound(problem, u):
    """``problem`` with the reduced law (m_t = 0) and, as its friction coefficient, the bound
    c_tau (u_n - g_a)_+^{m_t} of (1.9) at (a copy of) the GridFunction ``u``: the problem of one step of
    the fixed point (:mod:`ngdgfric.solvers.fixed_point`).  Only c_tau and m_t differ, so a discretisation of
    ``problem`` serves it too."""
    u_frozen = ngs.GridFunction(u.space)
    u_frozen.vec.data = u.vec
    return dataclasses.replace(problem, c_tau=friction_bound(problem, u_frozen), m_t=0.0)


def residual_terms(disc, contact, u, lam_tau):
    """The terms of the residual of (3.3) at the GridFunctions (u, lam_tau), vectors on V_h:

        B_h(u, v),   j_n(u, v),   g(u; lam_tau, v) = int_{Gamma_C} c_tau (u_n - g_a)_+^{m_t} lam_tau v.t ds,
        -(f, v),

    the friction term with the bound at u (:func:`friction_bound`; c_tau itself for m_t = 0), assembled
    at that bound (:func:`friction_matrix`): one code path for m_t = 0 and m_t > 0."""
    trial, test = disc.V.TnT()
    compliance_part = ngs.BilinearForm(disc.V)
    compliance_part += compliance_form(disc.problem, contact.dS, trial, test)
    terms = [disc.F.CreateVector() for _ in range(4)]
    terms[0].data = disc.A * u.vec
    compliance_part.Apply(u.vec, terms[1])
    terms[2].data = friction_matrix(contact, friction_bound(disc.problem, u)) * lam_tau.vec
    terms[3].data = -disc.F
    return terms


def residual(disc, contact, u, lam_tau):
    """The residual of (3.3) at (u, lam_tau): the sum of :func:`residual_terms`,
    B_h(u, v) + j_n(u, v) + g(u; lam_tau, v) - (f, v), a vector on V_h."""
    terms = residual_terms(disc, contact, u, lam_tau)
    r = terms[0]
    for term in terms[1:]:
        r.data += term
    return r


def contact_residuals(problem, sigma_n, u, lam_tau):
    r"""The residuals of the contact laws on :math:`\Gamma_C` that the estimator weighs (eta_4 and eta_6 of
    Section 4): (:math:`\sigma_{h,\tau}(u) + c_\tau (u_n - g_a)_+^{m_t} \lambda_\tau`,
    :math:`\sigma_{h,n}(u) + c_n (u_n - g_a)_+^{m_n}`), CoefficientFunctions; ``sigma_n``: the traction
    :math:`\sigma_h(u) n` the estimator takes (its stress variant)."""
    n, t = normal_tangent()
    return sigma_n * t + friction_bound(problem, u) * lam_tau, sigma_n * n + compliance(problem, u)
