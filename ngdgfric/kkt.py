"""Contact quantities at the Gauss points of Gamma_C and the KKT residuals of Lemma 3.1."""

import ngsolve as ngs
import numpy as np

from .contact import compliance, evaluate_on_contact, normal_tangent, penetration
from .problem import strain, stress

__all__ = ["contact_state", "kkt_residuals", "rounding_residual"]


def contact_state(sol):
    """Arrays over the contact Gauss points (in the order of ``disc.contact_points()``).

    x, y: coordinates; u_n, u_tau: normal and tangential displacement (u_tau = u . t);
    gap: u_n - g_a; pressure: c_n (u_n - g_a)_+^{m_n}; l: multiplier (lam_tau = l t);
    sigma_n, sigma_tau: normal and tangential stress of u_h (sigma_tau = sigma_h(u) n . t);
    c_tau: friction coefficient; bound: friction bound c_tau (u_n - g_a)_+^{m_t} (1.9) (c_tau for m_t = 0).
    """
    disc = sol.discretization
    points = disc.contact_points()
    n, t = normal_tangent()
    u = sol.u
    sigma_n_vec = stress(sol.problem, strain(u)) * n
    values = {
        "x": np.asarray(ngs.x(points)).ravel(),
        "y": np.asarray(ngs.y(points)).ravel(),
        "u_n": evaluate_on_contact(u * n, points),
        "u_tau": evaluate_on_contact(u * t, points),
        "gap": evaluate_on_contact(penetration(sol.problem, u), points),
        "pressure": evaluate_on_contact(compliance(sol.problem, u), points),
        "sigma_n": evaluate_on_contact(sigma_n_vec * n, points),
        "sigma_tau": evaluate_on_contact(sigma_n_vec * t, points),
        "l": np.asarray(sol.lam_tau(points)).ravel(),
        "c_tau": np.asarray(disc.c_tau(points)).ravel() * np.ones(len(points)),
        "bound": evaluate_on_contact(disc.bound(u), points) * np.ones(len(points)),
    }
    return values


def kkt_residuals(sol):
    """Violations of the discrete KKT system (3.3)-(3.4) at the Gauss points of Gamma_C.

    lam_excess: max(|l| - 1, 0);  complementarity: max |l u_tau - |u_tau|| / max(|u|);
    equilibrium: ||A u + j_n(u) + g(l) - F||_2 / ||F||_2 (round-off level at a solution), where
    g(l, v) = int c_tau (u_n - g_a)_+^{m_t} l v.t ds carries the friction bound at u_h.
    """
    state = contact_state(sol)
    disc = sol.discretization
    scale = max(np.max(np.abs(sol.u.vec.FV().NumPy())), 1e-300)
    r = disc.residual(sol.u, sol.lam_tau)
    f_norm = max(np.linalg.norm(disc.F.FV().NumPy()), 1e-300)
    return {
        "lam_excess": float(max(np.max(np.abs(state["l"]), initial=0.0) - 1.0, 0.0)),
        "complementarity": float(np.max(np.abs(state["l"] * state["u_tau"] - np.abs(state["u_tau"])),
                                        initial=0.0) / scale),
        "equilibrium": float(np.linalg.norm(r.FV().NumPy()) / f_norm),
    }


def rounding_residual(sol):
    """The equilibrium residual of :func:`kkt_residuals` for u rounded once more, u (1 +- eps) with
    fixed random signs: what round-off in u alone leaves, the floor to compare ``equilibrium`` with."""
    disc, u = sol.discretization, ngs.GridFunction(sol.u.space)
    signs = np.random.default_rng(0).choice([-1.0, 1.0], size=len(u.vec))
    u.vec.FV().NumPy()[:] = sol.u.vec.FV().NumPy() * (1 + np.finfo(float).eps * signs)
    r = disc.residual(u, sol.lam_tau).FV().NumPy()
    return float(np.linalg.norm(r) / max(np.linalg.norm(disc.F.FV().NumPy()), 1e-300))
