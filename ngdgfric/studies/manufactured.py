r"""Manufactured solutions (:math:`f`, :math:`g` from a chosen :math:`u`) for convergence, locking and solver studies.

``elasticity_manufactured``: smooth linear elasticity without contact forces.
``contact_manufactured`` (:math:`m_t = 0`) and ``friction_manufactured`` (:math:`m_t \ge 1`): frictional
contact with normal compliance, with contact and no-contact, stick and slip zones on :math:`\Gamma_C` (the
constructions are in their docstrings).
"""

import dataclasses
import math

import ngsolve as ngs

from ..problem import ContactProblem, Polygon, strain_of, stress

__all__ = ["body_force_and_traction", "elasticity_manufactured", "contact_manufactured",
           "incompressible_contact_manufactured", "friction_manufactured"]


def body_force_and_traction(problem, u):
    """f = -div sigma(u) and g = sigma(u) n for a smooth CoefficientFunction u."""
    x, y = ngs.x, ngs.y
    sigma = stress(problem, strain_of(u))
    f = -ngs.CF((sigma[0, 0].Diff(x) + sigma[0, 1].Diff(y), sigma[1, 0].Diff(x) + sigma[1, 1].Diff(y)))
    return f, sigma * ngs.specialcf.normal(2)


def _with_loads(problem, u):
    """(problem with f = -div sigma(u) and g = sigma(u) n, u): u solves it where the contact conditions hold."""
    f, g = body_force_and_traction(problem, u)
    return dataclasses.replace(problem, f=f, g=g), u


def _square_on_foundation(E, nu, c_n, c_tau=0.0, m_t=0.0):
    """Omega = (0, 1)^2 with Gamma_C = bottom (n = (0, -1), t = (1, 0)), Gamma_D = top, Gamma_F = left and
    right; m_n = 1, no loads and no gap yet (set from the chosen u)."""
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="traction", top="dirichlet", left="traction")
    return ContactProblem(E=E, nu=nu, f=(0, 0), g=(0, 0), c_n=c_n, m_n=1, g_a=0.0, c_tau=c_tau, geometry=geometry,
                          m_t=m_t)


def _positive_part(z):
    return ngs.IfPos(z, z, 0)


def _fourth(z):
    """z^4 as a product: Diff of a power of IfPos gives NaN at 0."""
    return z * z * z * z


def elasticity_manufactured(E=1000.0, nu=0.3):
    """Smooth u with u = 0 on Gamma_D = {x = 1} and sigma(u) n = 0 on Gamma_C = {y = 0}.

    u = y^2 (1 - x) (sin(x + y), cos(2x - y)): every strain component carries y, so sigma = 0
    on y = 0; with c_tau = 0 and a gap g_a = 1 larger than |u_n| the contact terms vanish and
    u solves (1.5)-(1.9) (linear elasticity) with f = -div sigma(u) and g = sigma(u) n on Gamma_F.
    """
    x, y = ngs.x, ngs.y
    u = ngs.CF((y**2 * (1 - x) * ngs.sin(x + y), y**2 * (1 - x) * ngs.cos(2 * x - y)))
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="dirichlet", top="traction", left="traction")
    return _with_loads(ContactProblem(E=E, nu=nu, f=(0, 0), g=(0, 0), c_n=1.0, m_n=1, g_a=1.0, c_tau=0.0,
                                      geometry=geometry), u)


def contact_manufactured(E=1000.0, nu=0.3, c_n=10.0, K=50.0):
    """(problem, u_exact) of a contact problem with a known solution (m_t = 0):

    Contact problem on Omega = (0,1)^2: Gamma_C = bottom (n = (0,-1), t = (1,0)), Gamma_D = top,
    Gamma_F = left and right.  With s = x - 1/2, a = 1/4 and

        psi(x) = s_+^3,   chi(x) = K (a - x)_+^3,   phi(x) = (lam psi'' ... ) see below,
        u(x, y) = (1 - y) (psi(x), phi(x)),     phi = (lam psi' + chi) / (2 mu + lam),

    u vanishes on Gamma_D (y = 1).  At y = 0:

        u_tau = u . t = psi,                     u_n = u . n = -phi,
        sigma_n = sigma_22 = -(2mu+lam) phi + lam psi' = -chi,
        sigma_tau = sigma n . t = -sigma_12 = -mu (phi' - psi).

    * Compliance (1.8): sigma_n = -c_n (u_n - g_a)_+ with c_n constant and
      g_a = u_n - chi / c_n + (x - a)_+^3: penetration chi / c_n > 0 for x < a (contact),
      gap (x - a)_+^3 > 0 for x > a (no contact).
    * Friction (1.9), m_t = 0: for x < 1/2, u_tau = 0 (stick) and we need |sigma_tau| <= c_tau;
      for x > 1/2, u_tau = s^3 > 0 (slip) and we need sigma_tau = -c_tau, i.e.
      c_tau = mu (phi' - psi) >= 0, true since phi' = 6 lam s / (2mu+lam) > s^3 for s <= 1/2 when
      6 lam / (2mu+lam) > 1/4.  So c_tau = mu (phi' - psi) for x > 1/2 and
      c_tau = mu (|phi'| + 1/2 - x) for x < 1/2 (continuous, strictly above |sigma_tau| in the
      stick zone but at x = 1/2, where both vanish).  The multiplier is lam_tau = t for x > 1/2 and
      -sigma_tau / c_tau inside the stick zone.
    * f = -div sigma(u) in Omega, g = sigma(u) n on Gamma_F.

    The solution has contact and no-contact zones and stick and slip zones on Gamma_C.
    """
    x = ngs.x
    base = _square_on_foundation(E, nu, c_n)
    mu, lam = base.mu, base.lam
    s = x - 0.5
    s_plus = _positive_part(s)
    psi = s_plus * s_plus * s_plus
    dpsi = 3 * s_plus * s_plus
    d2psi = 6 * s_plus
    r = _positive_part(0.25 - x)
    chi = K * r * r * r
    dchi = -3 * K * r * r
    phi = (lam * dpsi + chi) / (2 * mu + lam)
    dphi = (lam * d2psi + dchi) / (2 * mu + lam)
    u = (1 - ngs.y) * ngs.CF((psi, phi))
    u_n = -phi
    q = _positive_part(x - 0.25)
    g_a = u_n - chi / c_n + q * q * q
    c_tau = ngs.IfPos(s, mu * (dphi - psi), mu * (ngs.IfPos(dphi, dphi, -dphi) - s))
    return _with_loads(dataclasses.replace(base, g_a=g_a, c_tau=c_tau), u)


def friction_manufactured(m_t=1, E=1000.0, nu=0.3, c_n=10.0, c_tau=100.0, K=50.0, M=32.0):
    """(problem, u_exact) with the penetration-dependent friction bound c_tau (u_n - g_a)_+^{m_t}.

    Same domain and boundary parts as ``contact_manufactured``; on Gamma_C (y = 0) n = (0, -1),
    t = (1, 0).  Three zones along Gamma_C:

        x < 1/4:        contact, stick   (u_tau = 0,  |sigma_tau| < bound),
        1/4 < x < 1/2:  contact, slip    (u_tau > 0,  sigma_tau = -bound),
        x > 1/2:        no contact       (bound = 0, so sigma_n = sigma_tau = 0 and u_tau is free).

    Choose the penetration p = K (1/2 - x)_+^4 / c_n, so sigma_n = -c_n p is the compliance (1.8),
    and the tangential traction sigma_tau = T = -c_tau p^{m_t} w with w = 1 - M (1/4 - x)_+^4
    (w in [1/2, 1] for M <= 32): T = -bound where w = 1 (slip and no-contact zones, where the bound
    c_tau p^{m_t} is 0), |T| < bound in the stick zone.  Choose u on Gamma_C: u_tau = psi =
    (x - 1/4)_+^4 (> 0 exactly for x > 1/4, also in the no-contact zone), u_n = -phi, phi = x^2/4,
    and the gap g_a = u_n - p + (x - 1/2)_+^4.  The displacement

        u(x, y) = (1 - y) (psi, phi) + y (1 - y) (alpha, beta)

    vanishes on Gamma_D (y = 1), equals (psi, phi) at y = 0, and its y-derivative there,
    (alpha - psi, beta - phi), sets the tractions: sigma_tau = -sigma_12 = -mu (alpha - psi + phi')
    and sigma_n = sigma_22 = lam psi' + (2 mu + lam)(beta - phi), so

        alpha = psi - phi' - T / mu,      beta = phi + (-c_n p - lam psi') / (2 mu + lam).

    m_t is a positive integer here.  Every function is C^3 in x, u is in H^3 (optimal rates up to
    p = 2).  The multiplier is
    l = -T / bound = w in the contact zone and l = sign(u_tau) = 1 in the no-contact zone.
    f = -div sigma(u) in Omega, g = sigma(u) n on Gamma_F.
    """
    x, y = ngs.x, ngs.y
    base = _square_on_foundation(E, nu, c_n, c_tau=c_tau, m_t=m_t)
    mu, lam = base.mu, base.lam
    r, s, q = _positive_part(0.5 - x), _positive_part(x - 0.25), _positive_part(x - 0.5)
    w = 1 - M * _fourth(_positive_part(0.25 - x))
    penetration = K / c_n * _fourth(r)
    traction = -c_tau * math.prod([penetration] * m_t, start=ngs.CF(1)) * w
    psi, dpsi = _fourth(s), 4 * s * s * s
    phi, dphi = x * x / 4, x / 2
    alpha = psi - dphi - traction / mu
    beta = phi + (-c_n * penetration - lam * dpsi) / (2 * mu + lam)
    u = ngs.CF(((1 - y) * psi + y * (1 - y) * alpha, (1 - y) * phi + y * (1 - y) * beta))
    return _with_loads(dataclasses.replace(base, g_a=-phi - penetration + _fourth(q)), u)


def incompressible_contact_manufactured(E=1000.0, nu=0.3, c_n=10.0, K=16.0):
    """(problem, u_exact) of a contact problem (m_t = 0) with a divergence-free solution.

    Same domain and boundary parts as ``contact_manufactured`` (Gamma_C = bottom, n = (0, -1),
    t = (1, 0); Gamma_D = top).  u is the curl of the stream function psi = phi(y) T(x),

        u = (phi'(y) T(x), -phi(y) T'(x)),   phi(y) = -(1 - y)^2 e^y,

    so div u = 0 for every nu: sigma(u) = 2 mu eps(u) does not depend on lam, and neither do the
    data f, g, c_tau, g_a.  This is the physically meaningful nearly incompressible limit (stresses
    stay bounded as nu -> 1/2), unlike ``contact_manufactured``, whose stresses grow with lam.
    phi(0) = -1, phi'(0) = phi''(0) = 1 give at y = 0

        u_tau = T,  u_n = -T',  sigma_n = sigma_22 = -2 mu T',  sigma_tau = -sigma_12 = -mu (T + T'').

    With s = x - 1/2, r = 1/4 - x: T = e^x s_+^4 for x > 1/2, T = -K e^x r_+^4 for x < 1/4, 0
    between.  Then T' > 0 in both outer zones (contact, sigma_n < 0); u_tau > 0 and T + T'' > 0 on
    the right, u_tau < 0 and T + T'' < 0 on the left (slip: sigma_tau = -c_tau sign(u_tau) with
    c_tau = mu |T + T''|); in 1/4 < x < 1/2 u = 0 on Gamma_C (stick, no contact).  Compliance with
    constant c_n: g_a = u_n - 2 mu T' / c_n + G with a gap bump G > 0 only in the middle zone;
    c_tau = mu |T + T''| + mu B with a bump B > 0 only in the stick zone.  f = -div sigma(u),
    g = sigma(u) n on Gamma_F.  Every function is C^3 and not a polynomial (no p gives u exactly).
    """
    x, y = ngs.x, ngs.y
    base = _square_on_foundation(E, nu, c_n)
    mu = base.mu
    s, r = _positive_part(x - 0.5), _positive_part(0.25 - x)
    ex = ngs.exp(x)
    T = ex * (_fourth(s) - K * _fourth(r))
    dT = ex * (_fourth(s) + 4 * s * s * s + K * r * r * r * (4 - r))
    d2T = ex * (_fourth(s) + 8 * s * s * s + 12 * s * s + K * r * r * (-r * r + 8 * r - 12))
    phi = -(1 - y) * (1 - y) * ngs.exp(y)
    u = ngs.CF((phi.Diff(y) * T, -phi * dT))
    middle = _positive_part(x - 0.25) * _positive_part(0.5 - x)
    slip = T + d2T
    c_tau = mu * (ngs.IfPos(slip, slip, -slip) + 256 * middle * middle)
    return _with_loads(dataclasses.replace(base, g_a=-dT - 2 * mu * dT / c_n + 4096 * _fourth(middle), c_tau=c_tau),
                       u)
