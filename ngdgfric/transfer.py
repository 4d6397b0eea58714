"""Warm starts: a solution on one mesh as the initial guess on another (coarser -> finer)."""

import ngsolve as ngs

from .contact import normal_tangent, project_unit
from .forms import strain, stress
from .nonlinear import multiplier_update

__all__ = ["initial_guess"]


def initial_guess(sol, disc):
    """(u, l) GridFunctions on ``disc``'s spaces from the Solution ``sol``.

    On the same mesh and spaces the vectors are copied.  Otherwise u is interpolated (exact for
    nested meshes and equal or higher order) and the multiplier is estimated from the transferred
    stress: at a solution sigma_tau(u_h) + c_tau l ~ 0 (estimator eta_4), so l0 = P(-sigma_tau / c_tau)
    (0 where c_tau = 0); facet functions cannot be evaluated on another mesh.
    """
    u = ngs.GridFunction(disc.V)
    lam = ngs.GridFunction(disc.Q)
    if sol.u.space.ndof == disc.V.ndof and sol.mesh is disc.mesh and sol.lam_tau.space.ndof == disc.Q.ndof:
        u.vec.data = sol.u.vec
        lam.vec.data = sol.lam_tau.vec
        return u, lam
    u.Set(sol.u)
    n, t = normal_tangent()
    sigma_tau = stress(disc.problem, strain(u)) * n * t
    c_tau = disc.c_tau
    estimate = ngs.IfPos(c_tau, -sigma_tau / ngs.IfPos(c_tau, c_tau, 1), 0)
    multiplier_update(disc, lam, project_unit(estimate))()
    return u, lam
