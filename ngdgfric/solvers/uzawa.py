r"""The Uzawa iteration of Section 6 for the characterisation (3.3)-(3.4).

.. math::

    \lambda_\tau^{k+1} &= P_{[-1,1]}(\lambda_\tau^k + \rho\, c_\tau u_\tau^k)
        \quad \text{at the contact Gauss points}, \\
    u^{k+1}: \quad B_h(u, v) + j_n(u, v) &= (f, v) - g(\lambda_\tau^{k+1}, v)
        \quad \text{(Newton on the compliance term)},

(:math:`\lambda_\tau^{k+1} = \operatorname{sign}(u_\tau^k)` where :math:`c_\tau = 0`: there :math:`\lambda_\tau`
does not enter (3.3), only (3.4)). At the points of the contact pairs (:class:`~ngdgfric.ContactPair`) the same
update acts on the relative displacement :math:`[u]_\tau` (the tangential rows of :math:`B`), with the pair's
multiplier an array of point values (``info["pair_multiplier"]``, as the Newton solver's), and the pairs' terms of
the inner problem are written at their points (``PairTerms`` of :mod:`ngdgfric.solvers.nonlinear`). A body held by
contact only (no Dirichlet side) is refused: the inner problem's matrix :math:`A + K_n(u)` is singular while that
body does not touch (the Newton solver's proximal steps, :mod:`ngdgfric.solvers.floating`, handle it). Uzawa keeps
the full sparse system (NGSolve's factorisations), independent of the condensed linear algebra of the default
solver, so the two check each other.

**Stopping test.**  :math:`\|u^{k+1} - u^k\|_\infty \le` ``solver_tol`` :math:`\|u^{k+1}\|_\infty` (the
paper's relative max-norm criterion, here on the coefficient vector of :math:`u_h`) and the complementarity
residual of (3.4) (``complementarity``, the part of the KKT system that Uzawa's iterates do not satisfy exactly)
at most the larger of ``solver_tol`` and ``kkt_tol``: with a tiny :math:`\rho` the multiplier, and so
:math:`u`, moves by almost nothing per iteration far from the solution, and the change alone would report
convergence (:math:`\rho = 10^{-12}` stopped after 2 iterations, 45 % off).  At the paper's ``solver_tol`` =
1e-8 the residual is about 1e-6 (it falls at the iteration's rate, 100-500 times the change).

**Failing fast.**  A :class:`ngdgfric.SolverError` with the history of changes is raised when the iteration
diverges (a non-finite change, or a change 1000 times above its minimum), when the KKT residual makes
no progress over ``WINDOW`` = 250 iterations (its minimum over them above 0.99 times that over the window
before: the multiplier oscillates, :math:`\rho` too large, or :math:`u` does not move, :math:`\rho` too small),
or when its rate of decrease over the last window predicts more than ten times ``maxit`` iterations.
"""

import time
from collections.abc import Callable
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..checks import callback, optional, positive_integer, positive_number
from ..contact.boundary import evaluate_on_contact, normal_tangent
from ..contact.forms import friction_matrix
from ..contact.laws import project_unit, project_unit_values
from ..errors import SolverError, check_deadline, deadline
from ..problem import coefficient, exponents
from ..sparse import direct_inverse
from ..threads import threads
from ..transfer import starting_point
from .floating import FloatingSolve
from .nonlinear import ContactOperator, PairTerms, ReusedFactorization, multiplier_update, newton_step, relative_change
from .options import SolverOptions
from .reduced import pair_forces

__all__ = ["uzawa", "UzawaOptions", "default_rho", "complementarity", "multiplier_step"]

WINDOW = 250  # iterations between the progress checks
REPORT_EVERY = 100  # iterations between two calls of ``progress``


@dataclass(frozen=True)
class UzawaOptions(SolverOptions):
    r"""The options of the Uzawa solver (the keywords of ``solve(solver="uzawa")``, :func:`ngdgfric.solve`).

    The paper's method (:mod:`ngdgfric.solvers.uzawa`), for :math:`m_t = 0` only.

    Parameters
    ----------
    solver_tol : float, optional
        The relative change of :math:`u` at which the iteration stops (the paper's test, Section 6), once the
        complementarity residual is at most the larger of ``solver_tol`` and ``kkt_tol`` too (see
        :mod:`ngdgfric.solvers.uzawa`).  Default ``1e-8``.
    maxit : int, optional
        Iterations.  Default ``100000``.
    progress : callable or None, optional
        ``progress(message)`` is called every ``REPORT_EVERY`` = 100 iterations with a line
        ``"uzawa k: relative change ..., complementarity ..."``.  Default ``None``: no messages.
    rho : float or None, optional
        The step size :math:`\rho` of the multiplier update.  Default ``None``: ``default_rho`` of
        :mod:`ngdgfric.solvers.uzawa` (1.5 over the largest eigenvalue of the linearised Uzawa map).
    kkt_tol : float, optional
        The complementarity residual's part of the stopping test (``kkt_tol=solver_tol``: a strict test).
        Default ``1e-6``.
    max_seconds : float or None, optional
        Stop with :class:`ngdgfric.TimeLimitError` (a :class:`ngdgfric.SolverError`) after this long.  Default
        ``None``: no limit.

    Raises
    ------
    ValueError
        A value out of its range, named with the value.

    See Also
    --------
    ngdgfric.NewtonOptions, ngdgfric.FixedPointOptions : The options of the other solvers.
    """

    solver = "uzawa"
    checks = dict(solver_tol=positive_number, maxit=positive_integer, progress=callback,
                  rho=optional(positive_number), kkt_tol=positive_number, max_seconds=optional(positive_number))

    solver_tol: float = 1e-8
    maxit: int = 100000
    progress: Callable[[str], None] | None = None
    rho: float | None = None
    kkt_tol: float = 1e-6
    max_seconds: float | None = None


def default_rho(disc, contact, problem=None, iterations=30, safety=1.5, pairs=None):
    """rho = safety / L with L the largest eigenvalue of the linearised Uzawa map of ``problem`` (default
    ``disc.problem``) on ``disc``, with the contact pairs' points ``pairs`` (a ``PairTerms``, or None).

    The map lam_tau -> c_tau u_tau(lam_tau) of the linear problem (compliance inactive) has the matrix
    H = M^-1 G^T A^-1 G (at the pairs' points G = B_t^T diag(omega c_tau) and M = diag(omega)); projected
    gradient ascent on the dual converges for rho < 2/L.  L is estimated by ``iterations`` power iterations with
    the factorised A; the compliance term only adds stiffness and lowers L, so rho = 1.5/L is safe with margin.
    """
    points = 0 if pairs is None else pairs.M
    if contact.Q.ndof + points == 0:
        return 1.0
    foundation = contact.Q.ndof > 0
    G = friction_matrix(contact, (disc.problem if problem is None else problem).c_tau) if foundation else None
    with threads(disc.V.ndof):
        inverse = direct_inverse(disc.A, disc.symmetric)
    x_Q, load, z = ngs.GridFunction(contact.Q).vec, disc.F.CreateVector(), disc.F.CreateVector()
    y_Q = x_Q.CreateVector()

    def apply(x):  # H x for x = (lam_tau's coefficients, the pairs' point values)
        x_Q.FV().NumPy()[:] = x[:contact.Q.ndof]
        load.FV().NumPy()[:] = 0.0 if pairs is None else pairs.friction_load(x[contact.Q.ndof:])
        if foundation:
            load.data += G * x_Q
        z.data = inverse * load
        if foundation:
            y_Q.data = contact.M_inv * (G.T * z)
        pair_part = np.zeros(0) if pairs is None else pairs.traces.c_tau * pairs.traces_at(z.FV().NumPy())[points:]
        return np.concatenate([y_Q.FV().NumPy(), pair_part])

    rng = np.random.default_rng(0)
    x = rng.random(contact.Q.ndof + points) + 0.5
    estimate = 0.0
    for _ in range(iterations):
        y = apply(x)
        norm_y, norm_x = np.linalg.norm(y), np.linalg.norm(x)
        if norm_y == 0 or norm_x == 0:
            return 1.0
        estimate = norm_y / norm_x
        x = y / norm_y
    return safety / estimate


def solve_displacement(op, linear_solver, du, solver_tol=1e-13, maxit=50):
    """u for the current, fixed lam_tau: Newton for F_lam_tau(u) = 0 on the operator's u, in place (Uzawa's inner
    problem); returns the step count.

    For m_n = 1, F_lam_tau is affine on each set of penetrating points, so a step after which that
    set is unchanged is exact.
    """
    for step in range(1, maxit + 1):
        state = newton_step(op, linear_solver, du)
        op.u.vec.data -= du
        unchanged = op.linear_compliance and np.array_equal(op.state(), state)
        if unchanged or relative_change(du, op.u.vec) <= solver_tol:
            return step
    raise SolverError(f"Newton for the compliance term did not converge in {maxit} steps",
                      solver="uzawa (inner Newton)")


def complementarity(contact, u, lam_tau, pairs=None):
    """max_q |lam_tau u_tau - |u_tau|| / ||u||_inf at the contact Gauss points and at the pairs' points (``pairs``, a
    ``PairTerms`` with its multiplier, or None; there u_tau is [u]_tau): the residual of (3.4)."""
    _, t = normal_tangent()
    u_tau = evaluate_on_contact(u * t, contact.gauss.points)
    values = contact.gauss.values(lam_tau).ravel()
    if pairs is not None:
        u_tau = np.concatenate([u_tau, pairs.traces_at(u.vec.FV().NumPy())[pairs.M:]])
        values = np.concatenate([values, pairs.lam_tau])
    scale = max(np.max(np.abs(u.vec.FV().NumPy()), initial=0.0), 1e-300)
    return float(np.max(np.abs(values * u_tau - np.abs(u_tau)), initial=0.0)) / scale


def multiplier_step(lam_tau, rho, c_tau, u_tau, values=False):
    """The multiplier update of the module docstring, P_[-1,1](lam_tau + rho c_tau u_tau), and sign(u_tau) where
    c_tau = 0: CoefficientFunctions, or with ``values`` arrays of point values (the pairs' points)."""
    if values:
        return np.where(c_tau > 0, project_unit_values(lam_tau + rho * c_tau * u_tau), np.where(u_tau > 0, 1.0, -1.0))
    return ngs.IfPos(c_tau, project_unit(lam_tau + rho * c_tau * u_tau), ngs.IfPos(u_tau, 1, -1))


def _refuse_floating(disc):
    """ValueError naming a body held by contact only (:mod:`ngdgfric.solvers.floating`): Uzawa has no proximal
    steps, and its inner matrix A + K_n(u) is singular while that body does not touch."""
    floating = FloatingSolve.of(disc)
    if floating is not None:
        number, regions, name, _ = floating.motions[0]
        raise ValueError(f"uzawa cannot solve a body held by contact only: nothing but the contact pairs holds the "
                         f"{name} of body {number} (regions {', '.join(map(repr, regions))}), so the inner problem's "
                         f"matrix A + K_n(u) is singular while that body does not touch; use solver='newton' (its "
                         f"proximal steps), or hold the body by a Dirichlet or symmetry side")


def uzawa(disc, contact, options=None, initial=None, problem=None):
    """Uzawa's method of Section 6 with the ``UzawaOptions`` ``options`` (default: the defaults);
    returns (u, lam_tau, info) with info a dict of diagnostics.

    initial: None or a pair of GridFunctions (u, lam_tau) on ``disc.V``, ``contact.Q`` to start from.
    problem: the problem whose contact law is solved (default ``disc.problem``; the fixed point passes its
    frozen-bound problem, ``ngdgfric.contact.forms.frozen_bound``).
    info: ``iterations``, ``history`` (changes), ``kkt_history`` (complementarity residuals), ``rho``,
    ``inner_steps``, ``factorizations``, ``timings``.  Raises ``SolverError`` (module docstring) and
    ValueError for m_t > 0 (Uzawa solves the reduced law; the fixed point of :mod:`ngdgfric.solvers.fixed_point`
    runs it with the friction bound frozen).
    """
    options = UzawaOptions() if options is None else options
    problem = disc.problem if problem is None else problem
    pairs = PairTerms(contact.traces.pair_part(), np.zeros(contact.traces.M - contact.traces.foundation)) \
        if contact.pairs else None
    m_t = exponents(problem.m_t) + ([] if pairs is None else [pair.m_t for pair in problem.pairs])
    if max(m_t) != 0:
        raise ValueError(f"uzawa solves the reduced law m_t = 0 only, got m_t = {m_t}: use "
                         "solver='newton', or solver='fixed_point' with inner='uzawa'")
    if pairs is not None:
        _refuse_floating(disc)
    start = time.perf_counter()
    until = deadline(options.max_seconds)
    u, lam_tau = starting_point(contact, initial)
    rho = default_rho(disc, contact, problem, pairs=pairs) if options.rho is None else options.rho
    op, update = _operators(disc, contact, problem, u, lam_tau, rho, pairs)
    linear_solver = ReusedFactorization(op.jacobian, disc.symmetric)
    du, u_old = u.vec.CreateVector(), u.vec.CreateVector()
    history, kkt, inner_steps = [], [], 0
    for k in range(1, options.maxit + 1):
        if k > 1 or initial is not None:
            update()
        u_old.data = u.vec
        inner_steps += solve_displacement(op, linear_solver, du)
        u_old.data -= u.vec
        history.append(relative_change(u_old, u.vec))
        kkt.append(complementarity(contact, u, lam_tau, pairs))
        _report(options.progress, k, history, kkt)
        _check_divergence(rho, history, k)
        if _converged(options, history, kkt, k):
            break
        if k % WINDOW == 0 and k >= 2 * WINDOW:
            _check_progress(kkt, history, k, max(options.solver_tol, options.kkt_tol), options.maxit, rho)
        check_deadline(until, f"Uzawa (rho = {rho:.4g})", history,
                       f"after {k} iterations (relative change {history[-1]:.3e}, complementarity {kkt[-1]:.3e})")
    else:
        _fail(rho, history, f"did not reach solver_tol = {options.solver_tol:g} in {options.maxit} iterations "
                            f"(last relative change {history[-1]:.3e}, complementarity residual {kkt[-1]:.3e})")
    info = dict(iterations=k, history=history, kkt_history=kkt, rho=rho, inner_steps=inner_steps,
                **linear_solver.counts, timings=dict(**linear_solver.times, total=time.perf_counter() - start))
    if pairs is not None:
        info.update(pair_multiplier=pairs.lam_tau.copy(),
                    pair_forces=pair_forces(pairs.traces, pairs.forces(u.vec.FV().NumPy())))
    return u, lam_tau, info


def _operators(disc, contact, problem, u, lam_tau, rho, pairs=None):
    """Uzawa's inner operator F_lam_tau(u) (``ContactOperator`` with the friction force density c_tau lam_tau, and
    the pairs' terms ``pairs``) and the update of lam_tau and of the pairs' multiplier (``multiplier_step``), a
    callable."""
    _, t = normal_tangent()
    c_tau = coefficient(problem.c_tau)
    op = ContactOperator(disc, contact, u, c_tau, lam_tau, pairs)
    foundation = multiplier_update(contact, lam_tau, multiplier_step(lam_tau, rho, c_tau, u * t)) \
        if contact.Q.ndof else None

    def update():
        if foundation is not None:
            foundation()
        if pairs is not None:
            u_tau = pairs.traces_at(u.vec.FV().NumPy())[pairs.M:]
            pairs.lam_tau[:] = multiplier_step(pairs.lam_tau, rho, pairs.traces.c_tau, u_tau, values=True)

    return op, update


def _fail(rho, history, message):
    raise SolverError(f"Uzawa (rho = {rho:.4g}) {message}", history=history, solver="uzawa")


def _report(progress, k, history, kkt):
    """Call ``progress`` (if any) every REPORT_EVERY iterations with the change and the complementarity."""
    if progress is not None and k % REPORT_EVERY == 0:
        progress(f"uzawa {k}: relative change {history[-1]:.2e}, complementarity {kkt[-1]:.2e}")


def _check_divergence(rho, history, k):
    """Raise ``SolverError`` if the change is not finite, or (after 50 iterations) 1000 times its minimum."""
    change = history[-1]
    if not np.isfinite(change) or (k > 50 and change > 1e3 * min(history)):
        _fail(rho, history, f"diverged at iteration {k} (relative change {change:.3e}); rho is probably too "
                            "large (it must be below 2/L, see default_rho)")


def _converged(options, history, kkt, k):
    """The stopping test of the module docstring after iteration k > 1: change <= solver_tol and
    complementarity <= max(solver_tol, kkt_tol)."""
    return k > 1 and history[-1] <= options.solver_tol and kkt[-1] <= max(options.solver_tol, options.kkt_tol)


def _check_progress(kkt, changes, k, kkt_tol, maxit, rho):
    """Stop Uzawa early when its KKT residual stalls above ``kkt_tol`` or decays too slowly to reach it
    within maxit (once it is below, only the change is waited for)."""
    recent, earlier = min(kkt[k - WINDOW:k]), min(kkt[k - 2 * WINDOW:k - WINDOW])
    if recent <= kkt_tol:
        return
    if recent > 0.99 * earlier:
        moves = float(np.median(changes[k - WINDOW:k]))
        why = (f"u hardly moves (median change {moves:.1e} per iteration): rho is probably too small"
               if moves <= 1e-3 * recent else "the multiplier oscillates: rho is probably too large")
        _fail(rho, changes, f"makes no progress: the complementarity residual stays at {recent:.3e} over "
                            f"iterations {k - WINDOW + 1}-{k}; {why} (see default_rho)")
    rate = (recent / earlier) ** (1 / WINDOW)
    needed = np.log(kkt_tol / recent) / np.log(rate)
    if k + needed > 10 * maxit:
        _fail(rho, changes, f"converges too slowly: the complementarity residual {recent:.3e} falls by a factor "
                            f"{rate:.6f} per iteration and needs about {needed:.3g} more iterations (maxit = {maxit}; "
                            "rho is probably too small, see default_rho)")
