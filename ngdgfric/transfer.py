"""Warm starts: a solution on one mesh as the initial guess on another (coarser -> finer)."""

import ngsolve as ngs
import numpy as np

from .contact import normal_tangent, project_unit
from .forms import strain, stress
from .nonlinear import multiplier_update

__all__ = ["initial_guess", "multiplier_snapshot"]


def multiplier_snapshot(sol):
    """The multiplier of a Solution as mesh-independent Gauss values (:class:`GaussValues`)."""
    return sol.discretization.gauss.snapshot(sol.lam_tau)


def initial_guess(sol, disc):
    """(u, l) GridFunctions on ``disc``'s spaces from the Solution ``sol``.

    On the same mesh and spaces the vectors are copied.  Otherwise u is interpolated (exact for
    nested meshes and equal or higher order) and l is the old multiplier, a piecewise polynomial
    on the old edges of Gamma_C, evaluated at the new Gauss points.  ``sol`` may also be any
    object with ``u``, ``mesh`` and ``multiplier`` (a :class:`GaussValues`, or None: then l is
    estimated from the stress, l = P(-sigma_tau(u) / b) with b the friction bound at u, since
    sigma_tau + b l ~ 0 at a solution, estimator eta_4).
    """
    u, lam = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    old_lam = getattr(sol, "lam_tau", None)
    if sol.mesh is disc.mesh and sol.u.space.ndof == disc.V.ndof and old_lam is not None \
            and old_lam.space.ndof == disc.Q.ndof:
        u.vec.data, lam.vec.data = sol.u.vec, old_lam.vec
        return u, lam
    u.Set(sol.u)
    multiplier = sol.multiplier if hasattr(sol, "multiplier") else multiplier_snapshot(sol)
    if multiplier is not None:
        gauss = disc.gauss
        disc.gauss.set_values(lam, np.clip(multiplier(gauss.xy.reshape(-1, 2)), -1, 1).reshape(-1, gauss.q))
        return u, lam
    n, t = normal_tangent()
    sigma_tau = stress(disc.problem, strain(u)) * n * t
    bound = disc.bound(u)
    estimate = ngs.IfPos(bound, -sigma_tau / ngs.IfPos(bound, bound, 1), 0)
    multiplier_update(disc, lam, project_unit(estimate))()
    return u, lam
