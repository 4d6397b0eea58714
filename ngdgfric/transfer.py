"""Warm starts: a solution on one mesh as the initial guess on another (coarser -> finer)."""

import ngsolve as ngs
import numpy as np

from .contact import friction_bound, normal_tangent, project_unit
from .nonlinear import multiplier_update
from .problem import strain, stress

__all__ = ["initial_guess", "starting_point", "multiplier_snapshot", "copy_orders"]


def _local(p, q):
    """Positions, in an element's block of order p, of the basis functions of total degree <= q."""
    i, j = np.array([(i, j) for i in range(q + 1) for j in range(q + 1 - i)]).T
    return i * (p + 1) - i * (i - 1) // 2 + j


def copy_orders(source, source_orders, target, target_orders):
    """target = source for GridFunctions of two variable-order ``L2**2`` spaces on one mesh, by copying
    coefficients: exact where p_T(target) >= p_T(source), else the element-wise L2 projection.

    NGSolve's L2 triangle basis is hierarchical and L2-orthogonal (Dubiner): the element's functions
    are ordered by (i, j), i = 0..p, j = 0..p - i, the same functions for every p, and an element's
    coefficients are contiguous, elements in order, one component after the other; so the
    functions of degree <= min(p, p') carry over and truncation is the projection onto lower p.
    The same as ``target.Set(source)`` with a quadrature exact for both degrees (tested; ``Set``'s
    default rule of degree 2 p_T is not exact onto lower orders), without the quadrature: ``Set``
    took 0.11 s for 512 elements into p = 8, 18 % of a solve on that mesh.
    """
    source_orders = np.asarray(source_orders, dtype=np.int64)
    target_orders = np.asarray(target_orders, dtype=np.int64)
    sizes = lambda p: (p + 1) * (p + 2) // 2  # noqa: E731
    blocks = []
    for orders, gf in ((source_orders, source), (target_orders, target)):
        first = np.concatenate([[0], np.cumsum(sizes(orders))])
        if 2 * first[-1] != len(gf.vec):
            raise ValueError(f"a space with {len(gf.vec)} DOFs does not have the orders given ({2 * first[-1]} DOFs)")
        blocks.append(first)
    values, out = source.vec.FV().NumPy(), np.zeros(len(target.vec))
    pairs = np.stack([source_orders, target_orders], axis=1)
    for ps, pt in np.unique(pairs, axis=0):
        elements = np.flatnonzero((source_orders == ps) & (target_orders == pt))
        q = min(ps, pt)
        from_ = blocks[0][elements][:, None] + _local(ps, q)[None, :]
        to = blocks[1][elements][:, None] + _local(pt, q)[None, :]
        for component in range(2):
            out[to + component * blocks[1][-1]] = values[from_ + component * blocks[0][-1]]
    target.vec.FV().NumPy()[:] = out


def multiplier_snapshot(sol):
    """The multiplier of a Solution as mesh-independent Gauss values (:class:`GaussValues`)."""
    return sol.discretization.gauss.snapshot(sol.lam_tau)


def starting_point(disc, initial=None):
    """New GridFunctions (u, lam_tau) on ``disc.V`` and ``disc.Q``: zero, or copies of the pair ``initial``
    (the iterates a solver changes in place; the caller's pair is left alone)."""
    u, lam_tau = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    if initial is not None:
        u.vec.data, lam_tau.vec.data = initial[0].vec, initial[1].vec
    return u, lam_tau


def initial_guess(sol, disc):
    """(u, lam_tau) GridFunctions on ``disc``'s spaces from the Solution ``sol``.

    On the same mesh and spaces the vectors are copied.  Otherwise u is interpolated (exact for
    nested meshes and equal or higher order) and l is the old multiplier, a piecewise polynomial
    on the old edges of Gamma_C, evaluated at the new Gauss points.  ``sol`` may also be any
    object with ``u``, ``mesh`` and ``multiplier`` (a :class:`GaussValues`, or None: then lam_tau is
    estimated from the stress, lam_tau = P(-sigma_tau(u) / b) with b the friction bound at u, since
    sigma_tau + b lam_tau ~ 0 at a solution, estimator eta_4).
    """
    old_lam = getattr(sol, "lam_tau", None)
    if sol.mesh is disc.mesh and sol.u.space.ndof == disc.V.ndof and old_lam is not None \
            and old_lam.space.ndof == disc.Q.ndof:
        return starting_point(disc, (sol.u, old_lam))
    u, lam = starting_point(disc)
    u.Set(sol.u)
    multiplier = sol.multiplier if hasattr(sol, "multiplier") else multiplier_snapshot(sol)
    if multiplier is not None:
        gauss = disc.gauss
        disc.gauss.set_values(lam, np.clip(multiplier(gauss.xy.reshape(-1, 2)), -1, 1).reshape(-1, gauss.q))
        return u, lam
    n, t = normal_tangent()
    sigma_tau = stress(disc.problem, strain(u)) * n * t
    bound = friction_bound(disc.problem, u)
    estimate = ngs.IfPos(bound, -sigma_tau / ngs.IfPos(bound, bound, 1), 0)
    multiplier_update(disc, lam, project_unit(estimate))()
    return u, lam
