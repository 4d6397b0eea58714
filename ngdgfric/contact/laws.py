r"""The contact laws (1.8)-(1.9), each written once in two forms side by side: a CoefficientFunction (the forms, the
estimators and the equilibrated bound integrate it) and a numpy function of point values (the condensed solvers
evaluate it at the contact Gauss points; its name ends in ``_values``).  ``tests/test_contact_laws.py`` evaluates
both at random points.

With the gap :math:`d = u_n - g_a` (positive where the body penetrates the foundation):

.. math::

    p(d) &= c_n d_+^{m_n} \quad \text{(pressure, (1.8): } \sigma_n = -p), \qquad
    p'(d) = c_n m_n d_+^{m_n - 1}, \\
    \beta(d) &= c_\tau d_+^{m_t} \quad \text{(friction bound, (1.9); } c_\tau \text{ itself for the reduced law }
    m_t = 0 \text{ (1.10))}, \\
    \phi(d) &= \tfrac{c_n}{m_n + 1} d_+^{m_n + 1} \quad \text{(compliance energy, } \phi' = p), \qquad
    \beta |v_\tau| \quad \text{(friction energy: the density of } j_\tau \text{ in (1.4))}, \\
    \phi^*(t) &= g_a t + \tfrac{m_n}{m_n + 1} c_n^{-1/m_n} t^{(m_n + 1)/m_n} \quad (t \ge 0;
    \text{ the conjugate of } v_n \mapsto \phi(v_n - g_a); 0 \text{ where } c_n = 0), \\
    P(z) &= \max(-1, \min(1, z)) \quad \text{(the projection onto } [-1, 1] \text{ of Lemma 3.1)}.

:math:`(\phi^*)'(t) = g_a + (t / c_n)^{1/m_n}` inverts the pressure law.  ``smooth_unit`` is a :math:`C^1` stand-in
for :math:`P` that the equilibrated bound uses on edges where :math:`P(\lambda_\tau)` would have a kink.
"""

import ngsolve as ngs
import numpy as np

__all__ = ["positive_power", "pressure", "bound", "compliance_energy", "friction_energy", "pressure_conjugate",
           "project_unit", "smooth_unit", "positive_power_values", "pressure_values", "pressure_rate_values",
           "bound_rate", "compliance_energy_values", "friction_energy_values", "pressure_conjugate_values",
           "pressure_inverse_values", "pressure_inverse_rate_values", "project_unit_values", "smooth_unit_values",
           "law_forces"]


# ---------------------------------------------------------------------------- CoefficientFunctions
def positive_power(d, m):
    """(d)_+^m (m != 0), written IfPos(d, d^m, 0): the form IfPos(d, d, 0)^m has NaN Jacobians at d = 0."""
    return ngs.IfPos(d, d if m == 1 else d**m, 0)


def pressure(gap, c_n, m_n):
    """p(d) = c_n d_+^{m_n} of (1.8) for one exponent m_n."""
    return c_n * positive_power(gap, m_n)


def bound(gap, c_tau, m_t):
    """beta(d) = c_tau d_+^{m_t} of (1.9) for one exponent m_t; c_tau itself for m_t = 0 (1.10)."""
    return c_tau if m_t == 0 else c_tau * positive_power(gap, m_t)


def compliance_energy(gap, c_n, m_n):
    """phi(d) = c_n / (m_n + 1) d_+^{m_n + 1}, whose derivative is the pressure."""
    return c_n / (m_n + 1) * positive_power(gap, m_n + 1)


def pressure_conjugate(t, g_a, c_n, m_n):
    """phi*(t) = g_a t + m_n / (m_n + 1) c_n^{-1/m_n} t_+^{(m_n + 1)/m_n} (0 where c_n = 0), the convex conjugate of
    v_n -> phi(v_n - g_a)."""
    safe = ngs.IfPos(c_n, c_n, 1.0)
    return ngs.IfPos(c_n, t * g_a + m_n / (m_n + 1) * safe ** (-1 / m_n)
                     * ngs.IfPos(t, t, 0.0) ** ((m_n + 1) / m_n), 0.0)


def friction_energy(bound, slip):
    """The density beta |v_tau| of the friction functional j_tau (1.4) for a bound beta and a slip v_tau."""
    return bound * ngs.sqrt(slip**2)


def project_unit(z):
    """P(z): the projection onto [-1, 1], pointwise."""
    return ngs.IfPos(z - 1, 1, ngs.IfPos(-1 - z, -1, z))


def smooth_unit(z):
    """A C^1 map of the real line onto [-1, 1]: sign(z) H(min(|z|, 1)) with H(a) = a + a^2 - a^3 (H(0) = 0,
    H'(0) = 1, H(1) = 1, H'(1) = 0, increasing); it equals P(z) = +-1 where |z| >= 1."""
    a = ngs.IfPos(z, z, -z)
    a = ngs.IfPos(a - 1, 1, a)
    return ngs.IfPos(z, 1, -1) * (a + a * a - a * a * a)


# ---------------------------------------------------------------------------- numpy, point by point
def positive_power_values(x, m):
    """x_+^m for any real m, a number or one per point (1 where x > 0 for m = 0; 0 where x <= 0, also for m < 0)."""
    out = np.zeros_like(x, dtype=float)
    positive = x > 0
    if np.ndim(m) == 0:
        out[positive] = x[positive] if m == 1 else x[positive] ** m
    else:
        out[positive] = x[positive] ** np.asarray(m)[positive]
    return out


def pressure_values(gap, c_n, m_n):
    """p(d) = c_n d_+^{m_n} at points (``c_n``: a number or one per point, e.g. the weights omega c_n)."""
    return c_n * positive_power_values(gap, m_n)


def pressure_rate_values(gap, c_n, m_n):
    """p'(d) = c_n m_n d_+^{m_n - 1} at points (c_n where d > 0 for m_n = 1)."""
    return c_n * m_n * positive_power_values(gap, m_n - 1)


def bound_rate(gap, c_tau, m_t):
    """(beta, beta') = c_tau d_+^{m_t} and its derivative in d, point by point; c_tau and 0 where m_t = 0 (the
    reduced law: the bound does not depend on the gap)."""
    reduced = m_t == 0
    exponent = np.where(reduced, 1.0, m_t)
    beta = np.where(reduced, c_tau, c_tau * positive_power_values(gap, exponent))
    rate = np.where(reduced, 0.0, c_tau * exponent * positive_power_values(gap, exponent - 1))
    return beta, rate


def compliance_energy_values(gap, c_n, m_n):
    """phi(d) = c_n / (m_n + 1) d_+^{m_n + 1} at points."""
    return c_n / (m_n + 1) * positive_power_values(gap, m_n + 1)


def friction_energy_values(bound, slip):
    """beta |v_tau| at points."""
    return bound * np.abs(slip)


def pressure_conjugate_values(t, g_a, c_n, m_n):
    """phi*(t) at points t >= 0 (0 where c_n = 0); t^2 / (2 c_n) + g_a t for m_n = 1."""
    compliant = c_n > 0
    safe = np.where(compliant, c_n, 1.0)
    power = np.where(m_n == 1, t * t / (2 * safe), m_n / (m_n + 1) * safe ** (-1 / m_n) * t ** ((m_n + 1) / m_n))
    return np.where(compliant, g_a * t + power, 0.0)


def pressure_inverse_values(t, c_n, m_n):
    """(t / c_n)^{1/m_n}: the gap at which the pressure is t >= 0 ((phi*)' - g_a; 0 where c_n = 0)."""
    compliant = c_n > 0
    return np.where(compliant, (t / np.where(compliant, c_n, 1.0)) ** (1 / m_n), 0.0)


def pressure_inverse_rate_values(t, c_n, m_n):
    """The derivative of ``pressure_inverse_values`` in t > 0: (phi*)''(t) = (1/m_n) c_n^{-1/m_n} t^{1/m_n - 1}
    (1 / c_n for m_n = 1)."""
    safe = np.where(c_n > 0, c_n, 1.0)
    return np.where(m_n == 1, 1 / safe, (1 / m_n) * safe ** (-1 / m_n) * t ** (1 / m_n - 1))


def project_unit_values(z):
    """P(z) at points."""
    return np.clip(z, -1.0, 1.0)


def smooth_unit_values(z):
    """``smooth_unit`` at points."""
    a = np.minimum(np.abs(z), 1.0)
    return np.where(z > 0, 1.0, -1.0) * (a + a * a - a * a * a)


def law_forces(law, w, lam_tau):
    """The forces of the laws at M points, (N(w_n), beta(w_n) lam_tau): the compliance force (1.8) and the friction
    force (1.9) at traces w (2 M: normal, then tangential) with multiplier values ``lam_tau`` (projected onto
    [-1, 1]).  ``law``: the point data ``omega``, ``g_a``, ``c_n``, ``c_tau`` (arrays of length M) and ``m_n``,
    ``m_t`` (numbers or such arrays), e.g. a :class:`~ngdgfric.contact.traces.ContactTraces`."""
    M = len(law.omega)
    m_n, m_t = (np.broadcast_to(np.asarray(m, dtype=float), (M,)) for m in (law.m_n, law.m_t))
    gap = w[:M] - law.g_a
    normal = pressure_values(gap, law.omega * law.c_n, m_n)
    beta = bound_rate(gap, law.omega * law.c_tau, m_t)[0]
    return np.concatenate([normal, beta * project_unit_values(lam_tau)])
