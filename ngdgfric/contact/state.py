r"""The state of a solution on :math:`\Gamma_C`: displacements, stresses, the laws and the multiplier at the contact
Gauss points, the ends of the contact and stick zones, and the violations of the discrete KKT system (3.3)-(3.4).
"""

import ngsolve as ngs
import numpy as np

from ..problem import coefficient, strain, stress
from .boundary import evaluate_on_contact, normal_tangent
from .forms import compliance, friction_bound, penetration, residual_terms
from .pair_state import pair_law_term, pair_state

__all__ = ["contact_state", "transitions", "kkt_residuals", "rounding_residual", "STATE_KEYS"]

STATE_KEYS = ("x", "y", "u_n", "u_tau", "gap", "pressure", "sigma_n", "sigma_tau", "lam_tau", "c_tau", "bound")
"""The arrays of :func:`contact_state`."""


def contact_state(sol):
    r"""The state of a solution at the contact Gauss points.

    The points are those of the discrete problem's contact rule on :math:`\Gamma_C`, :math:`p + 1` per edge, in
    the order of :meth:`ngdgfric.Contact.points` (none without a contact side; the points of contact pairs:
    :func:`ngdgfric.pair_state`).

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve`.

    Returns
    -------
    dict of str to numpy.ndarray
        One array over the points each:

        - ``x``, ``y``: coordinates;
        - ``u_n``, ``u_tau``: normal and tangential displacement (:math:`u_\tau = u \cdot t`);
        - ``gap``: :math:`u_n - g_a`;
        - ``pressure``: :math:`c_n (u_n - g_a)_+^{m_n}`;
        - ``lam_tau``: the multiplier :math:`\lambda_\tau` (Lemma 3.1);
        - ``sigma_n``, ``sigma_tau``: normal and tangential stress of :math:`u_h`
          (:math:`\sigma_\tau = \sigma_h(u) n \cdot t`);
        - ``c_tau``: the friction coefficient;
        - ``bound``: the friction bound :math:`c_\tau (u_n - g_a)_+^{m_t}` (1.9) (:math:`c_\tau` for
          :math:`m_t = 0`).

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> state = ndf.contact_state(ndf.solve(problem, ndf.uniform_mesh(problem, 0.5)))
    >>> len(state["x"]), bool(abs(state["lam_tau"]).max() <= 1 + 1e-12)
    (4, True)
    """
    points = sol.contact.points()
    if len(points) == 0:  # no side on the foundation (two bodies in contact only)
        return {name: np.zeros(0) for name in STATE_KEYS}
    n, t = normal_tangent()
    u, problem = sol.u, sol.discretization.problem
    sigma_n_vec = stress(sol.discretization.material, strain(u)) * n
    return {
        "x": np.asarray(ngs.x(points)).ravel(),
        "y": np.asarray(ngs.y(points)).ravel(),
        "u_n": evaluate_on_contact(u * n, points),
        "u_tau": evaluate_on_contact(u * t, points),
        "gap": evaluate_on_contact(penetration(problem, u), points),
        "pressure": evaluate_on_contact(compliance(problem, u), points),
        "sigma_n": evaluate_on_contact(sigma_n_vec * n, points),
        "sigma_tau": evaluate_on_contact(sigma_n_vec * t, points),
        "lam_tau": np.asarray(sol.lam_tau(points)).ravel(),
        "c_tau": np.asarray(coefficient(problem.c_tau)(points)).ravel() * np.ones(len(points)),
        "bound": evaluate_on_contact(friction_bound(problem, u), points) * np.ones(len(points)),
    }


def transitions(sol, tol=1e-8):
    """The points of Gamma_C where the contact zone or the stick zone of a Solution ends, an (n, 2) array: midway
    between two neighbouring Gauss points of an edge where u_n - g_a changes sign, or |lam_tau| crosses 1 - ``tol``
    (where u may be singular; the adaptive loop grades its meshes towards them, :func:`ngdgfric.hp.hp_refine`)."""
    gauss = sol.contact.gauss
    state = contact_state(sol)
    shape = gauss.xy.shape[:2]
    in_contact = (state["gap"] > 0).reshape(shape)
    sticking = (np.abs(state["lam_tau"]) < 1 - tol).reshape(shape) & in_contact
    flips = (np.diff(in_contact, axis=1) != 0) | (np.diff(sticking, axis=1) != 0)
    edge, k = np.nonzero(flips)
    return np.vstack([0.5 * (gauss.xy[edge, k] + gauss.xy[edge, k + 1]), _pair_transitions(sol, tol)])


def _pair_transitions(sol, tol):
    """The transitions of ``transitions`` at the points of the contact pairs (between neighbouring points of an
    edge of a pair's side, :func:`pair_state`), on the pair's side and their closest points on the other side: an
    (n, 2) array."""
    found = [np.empty((0, 2))]
    for state, (_, points, _) in zip(pair_state(sol), sol.contact.pairs, strict=True):
        in_contact = state["penetration"] > 0
        sticking = (np.abs(state["lam_tau"]) < 1 - tol) & in_contact
        flips = (points.edge[1:] == points.edge[:-1]) & ((in_contact[1:] != in_contact[:-1])
                                                         | (sticking[1:] != sticking[:-1]))
        k = np.flatnonzero(flips)
        found += [0.5 * (points.xy[k] + points.xy[k + 1]), 0.5 * (points.other_xy[k] + points.other_xy[k + 1])]
    return np.vstack(found)


def _relative_residual(disc, contact, u, lam_tau, pair_lam_tau=None):
    """||:func:`residual`||_2 divided by the largest of the norms of its terms (:func:`residual_terms`: B_h(u, .),
    j_n, g, (f, .), and with contact pairs their forces B^T f at u and the pairs' multiplier values
    ``pair_lam_tau``, :func:`ngdgfric.contact.pair_state.pair_law_term`), a scale that exists without loads too (a
    body pushed by a penetration only: f = 0, g = 0); 0 if every term is zero."""
    terms = [term.FV().NumPy() for term in residual_terms(disc, contact, u, lam_tau)]
    if contact.pairs:
        terms.append(pair_law_term(contact, u.vec.FV().NumPy(), pair_lam_tau))
    scale = max(float(np.linalg.norm(term)) for term in terms)
    return float(np.linalg.norm(np.sum(terms, axis=0)) / scale) if scale > 0 else 0.0


def kkt_residuals(sol):
    r"""Violations of the discrete KKT system (3.3)-(3.4) at the contact points of a solution.

    The points: the Gauss points of :math:`\Gamma_C` and the points of the contact pairs.  All three are at round-off
    level at a solution.  At a pair's points the multiplier and the slip are those of
    the jump :math:`[u_h]_\tau` (:func:`ngdgfric.contact.pair_state`); the compliance law needs no residual of its
    own there, as on the foundation: the equilibrium residual evaluates it at :math:`u_h`.

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve`.

    Returns
    -------
    dict of str to float
        - ``lam_excess``: :math:`\max(|\lambda_\tau| - 1, 0)`;
        - ``complementarity``: :math:`\max |\lambda_\tau u_\tau - |u_\tau|| / \max |u|` (:math:`\max |u|` over
          the coefficients of :math:`u_h`; :math:`[u_h]_\tau` for :math:`u_\tau` at a pair's points);
        - ``equilibrium``: the Euclidean norm of the residual of (3.3) relative to the largest of its terms
          :math:`B_h(u_h, \cdot)`, :math:`j_n`, :math:`g` and :math:`(f, \cdot)`, the friction term with the bound
          at :math:`u_h` (``residual`` of :mod:`ngdgfric.contact.forms`), and the pairs' forces by the laws at
          :math:`u_h` (``pair_law_term`` of :mod:`ngdgfric.contact.pair_state`).

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> residuals = ndf.kkt_residuals(ndf.solve(problem, ndf.uniform_mesh(problem, 0.5)))
    >>> sorted(residuals)
    ['complementarity', 'equilibrium', 'lam_excess']
    >>> all(value < 1e-10 for value in residuals.values())
    True
    """
    state = contact_state(sol)
    pairs = pair_state(sol) if sol.contact.pairs else []
    scale = max(np.max(np.abs(sol.u.vec.FV().NumPy())), 1e-300)
    lam_tau = np.concatenate([state["lam_tau"]] + [pair["lam_tau"] for pair in pairs])
    u_tau = np.concatenate([state["u_tau"]] + [pair["jump_tau"] for pair in pairs])
    return {
        "lam_excess": float(max(np.max(np.abs(lam_tau), initial=0.0) - 1.0, 0.0)),
        "complementarity": float(np.max(np.abs(lam_tau * u_tau - np.abs(u_tau)), initial=0.0) / scale),
        "equilibrium": _relative_residual(sol.discretization, sol.contact, sol.u, sol.lam_tau, _pair_multiplier(sol)),
    }


def _pair_multiplier(sol):
    """The multiplier at the pairs' points (``sol.info["pair_multiplier"]``), None without pairs."""
    return np.asarray(sol.info["pair_multiplier"]) if sol.contact.pairs else None


def rounding_residual(sol):
    """The equilibrium residual of :func:`kkt_residuals` for u rounded once more, u (1 +- eps) with
    fixed random signs: what round-off in u alone leaves, the floor to compare ``equilibrium`` with."""
    u = ngs.GridFunction(sol.u.space)
    signs = np.random.default_rng(0).choice([-1.0, 1.0], size=len(u.vec))
    u.vec.FV().NumPy()[:] = sol.u.vec.FV().NumPy() * (1 + np.finfo(float).eps * signs)
    return _relative_residual(sol.discretization, sol.contact, u, sol.lam_tau, _pair_multiplier(sol))
