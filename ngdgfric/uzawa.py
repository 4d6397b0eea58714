"""The Uzawa iteration of Section 6 for the characterisation (3.3)-(3.4).

    l^{k+1} = P_[-1,1](l^k + rho c_tau u_tau^k)    at the contact Gauss points,
    u^{k+1}:  B_h(u, v) + j_n(u, v) = (f, v) - g(l^{k+1}, v)   (Newton on the compliance term),

(l^{k+1} = sign(u_tau^k) where c_tau = 0: there l does not enter (3.3), only (3.4)),
stopped when ||u^{k+1} - u^k||_inf <= tol ||u^{k+1}||_inf (the paper's relative max-norm
criterion, here on the coefficient vector of u_h) and the complementarity residual of (3.4) is
<= tol too.  Uzawa keeps the full sparse system (NGSolve's factorisations), independent of the
condensed linear algebra of the default solver, so the two check each other.
"""

import time

import ngsolve as ngs
import numpy as np

from .contact import evaluate_on_contact, friction_matrix, normal_tangent, project_unit
from .errors import SolverError
from .linalg import direct_inverse, threads
from .nonlinear import ContactOperator, ReusedFactorization, multiplier_update, newton_step, relative_change
from .options import callback, positive_integer, positive_number, validate
from .problem import coefficient

__all__ = ["uzawa", "default_rho", "complementarity", "OPTIONS"]


def default_rho(disc, problem=None, iterations=30, safety=1.5):
    """rho = safety / L with L the largest eigenvalue of the linearised Uzawa map.

    The map l -> c_tau u_tau(l) of the linear problem (compliance inactive) has the matrix
    H = M^-1 G^T A^-1 G; projected gradient ascent on the dual converges for rho < 2/L.  L is
    estimated by ``iterations`` power iterations with the factorised A; the compliance term
    only adds stiffness and lowers L, so rho = 1.5/L is safe with margin.
    """
    if disc.Q.ndof == 0:
        return 1.0
    G = friction_matrix(disc, (disc.problem if problem is None else problem).c_tau)
    with threads(disc.V.ndof):
        inverse = direct_inverse(disc.A, disc.symmetric)
    x = ngs.GridFunction(disc.Q).vec
    rng = np.random.default_rng(0)
    x.FV().NumPy()[:] = rng.random(len(x)) + 0.5
    y = x.CreateVector()
    estimate = 0.0
    for _ in range(iterations):
        y.data = disc.M_inv * (G.T * (inverse * (G * x)))
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


OPTIONS = dict(tol=positive_number, maxit=positive_integer, progress=callback, rho=positive_number,
               kkt_tol=positive_number)
WINDOW = 250  # iterations between the progress checks


def complementarity(disc, u, lam):
    """max_q |l u_tau - |u_tau|| / ||u||_inf at the contact Gauss points: the residual of (3.4)."""
    _, t = normal_tangent()
    u_tau = evaluate_on_contact(u * t, disc.gauss.points)
    lam_tau = disc.gauss.values(lam).ravel()
    scale = max(np.max(np.abs(u.vec.FV().NumPy()), initial=0.0), 1e-300)
    return float(np.max(np.abs(lam_tau * u_tau - np.abs(u_tau)), initial=0.0)) / scale


def uzawa(disc, tol=1e-8, rho=None, maxit=100000, initial=None, progress=None, kkt_tol=1e-6, problem=None):
    """Uzawa's method of Section 6; returns (u, lam, info) with info a dict of diagnostics.

    Stops when the relative change of u is <= ``tol`` (the paper's test) and the complementarity
    residual of (3.4) (:func:`complementarity`, the part of the KKT system that Uzawa's iterates do
    not satisfy exactly) is <= max(tol, ``kkt_tol``): with a tiny rho the multiplier, and so u,
    moves by almost nothing per iteration far from the solution, and the change alone would report
    convergence (rho = 1e-12 stopped after 2 iterations, 45 % off).  At the paper's tol = 1e-8 the
    residual is about 1e-6 (it falls at the iteration's rate, 100-500 times the change).
    Fails fast, raising :class:`SolverError` with the history of changes, when the iteration
    diverges (a non-finite change, or a change 1000 times above its minimum), when the KKT
    residual makes no progress over ``WINDOW`` iterations (its minimum over them above 0.99 times
    that over the window before: the multiplier oscillates, rho too large, or u does not move, rho
    too small), or when its rate of decrease over the last window predicts more than ten times
    ``maxit`` iterations.
    ``initial``: optional (u, lam) GridFunctions on ``disc.V``, ``disc.Q`` to start from.
    ``rho``: step size; None picks :func:`default_rho`.
    ``progress``: callable(iteration, change) called every 100 iterations, or None.
    info: ``iterations``, ``history`` (changes), ``kkt_history`` (complementarity residuals), ``rho``,
    ``inner_steps``, ``factorizations``, ``timings``.
    kkt_tol: see above (default 1e-6; kkt_tol = tol for a strict test).
    Raises ValueError for m_t > 0 (Uzawa solves the reduced law; the fixed point of
    :mod:`ngdgfric.fixed_point` runs it with the friction bound frozen).
    """
    validate(OPTIONS, "uzawa", tol=tol, maxit=maxit, progress=progress, rho=rho, kkt_tol=kkt_tol)
    problem = disc.problem if problem is None else problem
    if problem.m_t != 0:
        raise ValueError(f"uzawa solves the reduced law m_t = 0 only, got m_t = {problem.m_t!r}: use "
                         "solver='newton', or solver='fixed_point' with inner='uzawa'")
    start = time.perf_counter()
    u, lam = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    if initial is not None:
        u.vec.data, lam.vec.data = initial[0].vec, initial[1].vec
    if rho is None:
        rho = default_rho(disc, problem)
    _, t = normal_tangent()
    c_tau = coefficient(problem.c_tau)
    op = ContactOperator(disc, u, lambda trial: c_tau * lam)
    linear_solver = ReusedFactorization(disc.symmetric)
    u_tau = u * t
    update = multiplier_update(disc, lam, ngs.IfPos(c_tau, project_unit(lam + rho * c_tau * u_tau),
                                                    ngs.IfPos(u_tau, 1, -1)))
    du, u_old = u.vec.CreateVector(), u.vec.CreateVector()
    history, kkt = [], []
    inner_steps = 0

    def fail(message):
        raise SolverError(f"Uzawa (rho = {rho:.4g}) {message}", history=history, solver="uzawa")

    for k in range(1, maxit + 1):
        if k > 1 or initial is not None:
            update()
        u_old.data = u.vec
        inner_steps += solve_for_multiplier(op, linear_solver, du)
        u_old.data -= u.vec
        change = relative_change(u_old, u.vec)
        history.append(change)
        kkt.append(complementarity(disc, u, lam))
        if progress is not None and k % 100 == 0:
            progress(k, change)
        if not np.isfinite(change) or (k > 50 and change > 1e3 * min(history)):
            fail(f"diverged at iteration {k} (relative change {change:.3e}); rho is probably too large "
                 "(it must be below 2/L, see default_rho)")
        if change <= tol and kkt[-1] <= max(tol, kkt_tol) and k > 1:
            break
        if k % WINDOW == 0 and k >= 2 * WINDOW:
            _check_progress(kkt, history, k, max(tol, kkt_tol), maxit, fail)
    else:
        fail(f"did not reach tol = {tol:g} in {maxit} iterations (last relative change {history[-1]:.3e}, "
             f"complementarity residual {kkt[-1]:.3e})")
    info = dict(iterations=k, history=history, kkt_history=kkt, rho=rho, inner_steps=inner_steps,
                **linear_solver.counts, timings=dict(**linear_solver.times, total=time.perf_counter() - start))
    return u, lam, info


def _check_progress(kkt, changes, k, kkt_tol, maxit, fail):
    """Stop Uzawa early when its KKT residual stalls above ``kkt_tol`` or decays too slowly to reach it
    within maxit (once it is below, only the change is waited for)."""
    recent, earlier = min(kkt[k - WINDOW:k]), min(kkt[k - 2 * WINDOW:k - WINDOW])
    if recent <= kkt_tol:
        return
    if recent > 0.99 * earlier:
        moves = float(np.median(changes[k - WINDOW:k]))
        why = (f"u hardly moves (median change {moves:.1e} per iteration): rho is probably too small"
               if moves <= 1e-3 * recent else "the multiplier oscillates: rho is probably too large")
        fail(f"makes no progress: the complementarity residual stays at {recent:.3e} over iterations "
             f"{k - WINDOW + 1}-{k}; {why} (see default_rho)")
    rate = (recent / earlier) ** (1 / WINDOW)
    needed = np.log(kkt_tol / recent) / np.log(rate)
    if k + needed > 10 * maxit:
        fail(f"converges too slowly: the complementarity residual {recent:.3e} falls by a factor {rate:.6f} "
             f"per iteration and needs about {needed:.3g} more iterations (maxit = {maxit}; rho is probably "
             "too small, see default_rho)")
