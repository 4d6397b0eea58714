"""The Uzawa iteration of Section 6 for the characterisation (3.3)-(3.4).

    l^{k+1} = P_[-1,1](l^k + rho c_tau u_tau^k)    at the contact Gauss points,
    u^{k+1}:  B_h(u, v) + j_n(u, v) = (f, v) - g(l^{k+1}, v)   (Newton on the compliance term),

(l^{k+1} = sign(u_tau^k) where c_tau = 0: there l does not enter (3.3), only (3.4)),
stopped when ||u^{k+1} - u^k||_inf <= tol ||u^{k+1}||_inf (the paper's relative max-norm
criterion, here on the coefficient vector of u_h).
"""

import time

import ngsolve as ngs
import numpy as np

from .contact import normal_tangent, project_unit
from .errors import SolverError
from .linalg import direct_inverse, threads
from .nonlinear import ContactOperator, ReusedFactorization, multiplier_update, newton_step, relative_change

__all__ = ["uzawa", "default_rho"]


def default_rho(disc, iterations=30, safety=1.5):
    """rho = safety / L with L the largest eigenvalue of the linearised Uzawa map.

    The map l -> c_tau u_tau(l) of the linear problem (compliance inactive) has the matrix
    H = M^-1 G^T A^-1 G; projected gradient ascent on the dual converges for rho < 2/L.  L is
    estimated by ``iterations`` power iterations with the factorised A; the compliance term
    only adds stiffness and lowers L, so rho = 1.5/L is safe with margin.
    """
    if disc.Q.ndof == 0:
        return 1.0
    with threads(disc.V.ndof):
        inverse = direct_inverse(disc.A, disc.symmetric)
    x = ngs.GridFunction(disc.Q).vec
    rng = np.random.default_rng(0)
    x.FV().NumPy()[:] = rng.random(len(x)) + 0.5
    y = x.CreateVector()
    estimate = 0.0
    for _ in range(iterations):
        y.data = disc.M_inv * (disc.G.T * (inverse * (disc.G * x)))
        norm_y = np.linalg.norm(y.FV().NumPy())
        norm_x = np.linalg.norm(x.FV().NumPy())
        if norm_y == 0 or norm_x == 0:
            return 1.0
        estimate = norm_y / norm_x
        x.data = (1 / norm_y) * y
    return safety / estimate


def solve_for_multiplier(op, linear_solver, du, tol=1e-13, maxit=50):
    """Newton for F_l(u) = 0 with l fixed (the inner problem of Uzawa); returns the step count.

    For m_n = 1, F_l is affine on each set of penetrating points, so a step after which that
    set is unchanged is exact.
    """
    for step in range(1, maxit + 1):
        state, _ = newton_step(op, linear_solver, du)
        op.u.vec.data -= du
        if (op.linear_compliance and np.array_equal(op.state(), state)) or relative_change(du, op.u.vec) <= tol:
            return step
    raise SolverError(f"Newton for the compliance term did not converge in {maxit} steps",
                      solver="uzawa (inner Newton)")


def uzawa(disc, tol=1e-8, rho=None, maxit=100000, initial=None, progress=None):
    """Uzawa's method of Section 6; returns (u, lam, info) with info a dict of diagnostics.

    ``initial``: optional (u, lam) GridFunctions on ``disc.V``, ``disc.Q`` to start from.
    ``rho``: step size; None picks :func:`default_rho`.
    ``progress``: callable(iteration, change) called every 100 iterations, or None.
    Raises :class:`SolverError` (with the history of changes) on divergence or after ``maxit``, and
    ValueError for m_t > 0 (Uzawa solves the reduced law; the fixed point of
    :mod:`ngdgfric.fixed_point` runs it with the friction bound frozen).
    """
    if disc.problem.m_t != 0:
        raise ValueError(f"uzawa solves the reduced law m_t = 0 only, got m_t = {disc.problem.m_t!r}: use "
                         "solver='newton', or solver='fixed_point' with inner='uzawa'")
    start = time.perf_counter()
    u, lam = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    if initial is not None:
        u.vec.data, lam.vec.data = initial[0].vec, initial[1].vec
    if rho is None:
        rho = default_rho(disc)
    elif not (np.isfinite(rho) and rho > 0):
        raise ValueError(f"rho must be a positive number, got {rho!r}")
    _, t = normal_tangent()
    op = ContactOperator(disc, u, lambda trial: disc.c_tau * lam)
    linear_solver = ReusedFactorization(disc.symmetric)
    u_tau = u * t
    update = multiplier_update(disc, lam, ngs.IfPos(disc.c_tau, project_unit(lam + rho * disc.c_tau * u_tau),
                                                    ngs.IfPos(u_tau, 1, -1)))
    du, u_old = u.vec.CreateVector(), u.vec.CreateVector()
    history = []
    inner_steps = 0
    for k in range(1, maxit + 1):
        if k > 1 or initial is not None:
            update()
        u_old.data = u.vec
        inner_steps += solve_for_multiplier(op, linear_solver, du)
        u_old.data -= u.vec
        change = relative_change(u_old, u.vec)
        history.append(change)
        if progress is not None and k % 100 == 0:
            progress(k, change)
        if not np.isfinite(change) or (k > 50 and change > 1e3 * min(history)):
            raise SolverError(f"Uzawa diverged at iteration {k} (relative change {change:.3e}); "
                              f"rho = {rho:.4g} is probably too large (it must be below 2/L, see default_rho)",
                              history=history, solver="uzawa")
        if change <= tol and k > 1:
            break
    else:
        raise SolverError(f"Uzawa did not reach tol = {tol:g} in {maxit} iterations "
                          f"(last relative change {history[-1]:.3e}, rho = {rho:.4g})",
                          history=history, solver="uzawa")
    info = dict(iterations=k, history=history, rho=rho, inner_steps=inner_steps, **linear_solver.counts,
                timings=dict(**linear_solver.times, total=time.perf_counter() - start))
    return u, lam, info
