r"""The globalised semismooth Newton method for the condensed contact problem :math:`G(f) = 0`.

The problem :math:`G(f) = 0` is that of :mod:`ngdgfric.solvers.reduced`.  Newton directions :math:`J d = -G`
(``ReducedContact.newton_direction`` of :mod:`ngdgfric.solvers.reduced`) with one of three globalisations, and two
outer loops around them:

* :math:`B_h` symmetric and :math:`m_t = 0`: descent of the complementary energy :math:`\Theta` over :math:`K`
  (:mod:`ngdgfric.solvers.complementary_energy`).
* NIPG with :math:`m_t = 0` (no energy): merit :math:`\Psi(f) = \frac12 \sum_q W_{qq} G_q^2` (energy units).
  Newton steps with non-monotone Armijo backtracking (reference: the largest of the last five :math:`\Psi`;
  Grippo, Lampariello & Lucidi 1986); when that fails, a Levenberg-Marquardt step
  :math:`(J^T S J + \mu \operatorname{diag}(J^T S J))\, d = -J^T S G` with :math:`\mu` raised until :math:`\Psi`
  decreases (More 1978; for semismooth equations Facchinei & Kanzow 1997).  For a coercive :math:`B_h`
  (:math:`W`'s symmetric part positive definite) :math:`J` is nonsingular, so :math:`\Psi`'s smooth stationary
  points solve :math:`G = 0`; :math:`\Psi`'s kinks can still stop it (seen from poor starting points with
  :math:`c_n = 10^6`).  Then a continuation from the symmetric problem:
  :math:`W(s) = \operatorname{sym}(W) + s \operatorname{skew}(W)`, :math:`s = 0` (solved by the energy method),
  1/16, 1/8, ... 1, the step in :math:`s` doubled after a success and halved after a failure, each solve started
  from the last.
* :math:`m_t > 0` (a quasi-variational inequality, (1.4)): let :math:`T(f)` be the solution with the friction bound
  frozen at :math:`\beta(w_n(f))` (the reduced law with a spatially varying :math:`c_\tau`, solved by this method
  with its own globalisation).  The merit is the fixed-point residual :math:`r(f) = |f - T(f)|_\infty`: the Newton
  point (or half a step) is taken if it lowers :math:`r` by the fraction :math:`\sigma`, else the fixed-point step
  :math:`f \leftarrow T(f)`.  Where :math:`T` is a contraction with constant :math:`L`, the regime in which the QVI
  is known to have a unique solution (small :math:`c_\tau m_t (u_n - g_a)^{m_t - 1}`), :math:`r` falls at least by
  :math:`\max(1 - \sigma/2, L)` per step, and the coupled Newton finishes quadratically.  If :math:`r` stops
  falling (:math:`T` no contraction, no Newton progress: e.g. :math:`c_n = 0`, :math:`m_t = 1`, where :math:`T`
  cycles between two states), a continuation in :math:`c_\tau` follows: :math:`c_\tau` scaled by
  :math:`s = 10^{-6}`, then :math:`s` multiplied by 4 (the factor squared after a success, square-rooted after a
  failure) up to 1, so the solution branch is followed from the contractive regime of small :math:`c_\tau`.

**Proximal point method** (redundant points, :math:`m_t = 0`, :mod:`ngdgfric.solvers.reduced`).  With :math:`W`
singular whole groups of points are degenerate (stick and slip both hold for some of the optimal forces): the
Newton steps stay in the kernel of :math:`W`, points at the friction bound flip between stick and slip at every
step and the iterates wander along the set of solutions without converging (the observations:
:ref:`decisions-semismooth`).  Such a problem is solved by the proximal point method (Rockafellar, SIAM J.
Control Optim. 14, 1976, for maximal monotone operators, so also for the non-symmetric :math:`W` of NIPG, whose
symmetric part is positive semidefinite):

.. math::

    \text{with energy:} \quad
    f_{k+1} = \operatorname{argmin}_K \Theta(f) + \tfrac{\mu_k}{2} (f - f_k) \cdot D (f - f_k),
    \qquad D = \operatorname{diag}(W),

    \text{in general:} \quad f_{k+1} \text{ solves the laws with } W + \mu_k D \text{ and } w_0 + \mu_k D f_k,

a problem of the same class with unique forces and a well-conditioned Newton system, solved by the problem's own
iteration from :math:`f_k`; :math:`\mu_0 = 10^{-3}`, :math:`\mu_{k+1} = \mu_k / 100` (the steps
:math:`1 / \mu_k` grow, so the outer iteration converges superlinearly: Luque, SIAM J. Control Optim. 22, 1984).
A subproblem not solved within ``PROXIMAL_BUDGET`` = 10 iterations (without energy; with energy within the
remaining ``maxit``), or whose globalisation gives up, is continued from where it stopped with :math:`10 \mu_k`
(an inexact proximal step: the iteration stops as soon as the original problem meets the stopping test, so the
subproblems only steer it).  If the proximal method fails, the plain iteration follows (then, without energy, the
continuation).  The proximal map is nonexpansive, so which of the optimal forces is returned depends
continuously on the data and the start; this matters because the multiplier :math:`\lambda_\tau = f_t / \beta`
enters the estimator (:math:`\eta_4`).  The choice of :math:`\mu_0`, the decrease, the budgets and the order of
the fallbacks, with their measurements: :ref:`decisions-semismooth`.
"""

import numpy as np

from ..errors import SolverError, TimeLimitError, check_deadline
from .complementary_energy import SIGMA, energy_step

__all__ = ["solve", "iterate", "merit", "SIGMA"]

PROXIMAL_START, PROXIMAL_DECREASE = 1e-3, 100.0  # mu_0 and mu_k / mu_{k+1} of the proximal point method
# without energy (NIPG), a proximal subproblem not solved within PROXIMAL_BUDGET iterations is continued with
# mu x PROXIMAL_INCREASE
PROXIMAL_BUDGET, PROXIMAL_INCREASE = 10, 10.0
# m_t > 0: the inner solves T(f) stop at INNER x the outer relative KKT residual, at most INNER_LOOSEST, at least
# the outer solver_tol
INNER, INNER_LOOSEST = 1e-3, 1e-8
# the continuation inside an inner solve T(f) gives up after this many times maxit iterations in all: a NIPG
# problem with c_n / E = 1e8, m_n = 1.5, m_t = 2 spent 4000 iterations, over a minute, in continuations nested
# in the outer one; failing fast there, the outer continuation solved it in 1 s.  The outer continuation has
# no such budget (a corner problem with m_t = 0.5, c_tau / c_n = 1e4 needs 500 iterations there)
INNER_BUDGET = 5


def solve(problem, f0=None, solver_tol=1e-12, maxit=100, progress=None, energy_tol=None, deadline=None, budget=None):
    """Globalised semismooth Newton for the :class:`~ngdgfric.solvers.reduced.ReducedContact` ``problem`` from f0
    (default 0); returns (f, info).

    Stops when :meth:`~ngdgfric.solvers.reduced.ReducedContact.converged` to ``solver_tol`` or, if ``energy_tol``
    is given, as soon as the linearisation estimate eta_lin is at most ``energy_tol`` (an inexact solve).
    ``progress``: None or callable(message), called after each iteration with a line such as
    "newton 3: KKT residual 1.2e-09".

    info: ``iterations``; ``history``: relative KKT residual after each iteration; ``initial_residual``;
    ``linearization`` (eta_lin at the end); ``converged`` (``solver_tol`` met); ``steps``: the kind of
    each step ("newton", "newton x0.5", "projected newton", "levenberg-marquardt", "fixed point",
    "continuation s = ...", "proximal mu = ..."); ``penetrating``, ``stick``: set sizes at the end;
    ``residual``; ``least_squares_solves``: the singular Newton systems solved by least squares so far on
    ``problem`` and its variants (:func:`~ngdgfric.solvers.reduced.dense_solve`).  Redundant problems with
    m_t = 0 go through the proximal point method, and if that fails the plain iteration; without energy, a
    failed iteration is followed by a continuation (module docstring).
    Raises :class:`SolverError` if the stopping test is not met within ``maxit`` iterations, and
    :class:`~ngdgfric.errors.TimeLimitError` once ``time.perf_counter()`` passes ``deadline`` (None: never).
    ``budget``: the continuation's iterations in all, as a multiple of maxit (None: no limit but its step).
    """
    f = np.zeros(2 * problem.M) if f0 is None else np.asarray(f0, dtype=float).copy()
    try:
        return _solve_directly(problem, f, solver_tol, maxit, progress, energy_tol, deadline)
    except TimeLimitError:
        raise
    except SolverError as error:
        if problem.energy_merit:
            raise
        return _continuation(problem, solver_tol, maxit, progress, error, deadline, budget)


def _solve_directly(problem, f, solver_tol, maxit, progress, energy_tol=None, deadline=None, counted=0):
    """:func:`solve` without the continuation: the proximal point method where the forces are not unique and the
    problem is monotone (redundant points, m_t = 0, with or without energy), and if that fails the plain
    :func:`iterate` from f (which solved problems where the proximal subproblems kept failing: random W with
    3 of 8 points per edge redundant); else :func:`iterate`."""
    if problem.redundant and not problem.quasi_variational:
        try:
            return _proximal(problem, problem.project(f) if problem.energy_merit else f, solver_tol, maxit,
                             progress, energy_tol, deadline, counted)
        except TimeLimitError:
            raise
        except SolverError as error:
            counted += max(len(error.history), 1)
    return iterate(problem, f, solver_tol, maxit, progress, energy_tol, counted=counted, deadline=deadline)


def _info(problem, s, solver_tol, iterations, history, initial, steps):
    """The ``info`` of :func:`solve` at the final state s."""
    return dict(iterations=iterations, history=history, initial_residual=initial, steps=steps,
                penetrating=int(np.sum(s.penetrating)), stick=int(np.sum(s.stick)), residual=problem.residual(s),
                linearization=problem.linearization(s), converged=problem.converged(s, solver_tol),
                least_squares_solves=problem.diagnostics["least_squares_solves"])


def iterate(problem, f, solver_tol, maxit, progress, energy_tol=None, outer=None, counted=0, deadline=None,
            unfinished=False):
    """The iteration of :func:`solve` from f, with the globalisation of the problem's kind (module docstring).
    ``outer``: the problem whose stopping test also ends it and whose KKT residual is recorded (a
    proximal subproblem's original problem); default ``problem``.  ``counted``: iterations done before
    (for the numbers in the progress messages); ``deadline``: as in :func:`solve`.  ``unfinished``: after
    ``maxit`` iterations return the last f (``info["converged"]`` False) instead of raising SolverError."""
    if problem.energy_merit:
        f = problem.project(f)
    outer = problem if outer is None else outer
    s = problem.evaluate(f)
    history, steps = [], []
    memory = dict(recent=[], fixed_point=None, changes=[], solver_tol=solver_tol, maxit=maxit)
    initial = problem.residual(s)
    for k in range(maxit + 1):
        outer_done = outer is not problem and outer.done(outer.evaluate(s.f), solver_tol, energy_tol)
        if outer_done or problem.done(s, solver_tol, energy_tol) or (k == maxit and unfinished):
            return s.f, _info(problem, s, solver_tol, k, history, initial, steps)
        if k == maxit:
            break
        last = history[-1] if history else initial
        check_deadline(deadline, "semismooth Newton on the contact points", history,
                       f"after {counted + k} iterations (relative KKT residual {last:.3e})")
        f, kind = _step(problem, s, problem.newton_direction(s), memory, k, history, deadline)
        s = problem.evaluate(f)
        steps.append(kind)
        history.append(outer.residual(s if outer is problem else outer.evaluate(f)))
        if progress is not None:
            progress(f"newton {counted + k + 1}: KKT residual {history[-1]:.2e}")
    raise SolverError(f"semismooth Newton on the contact points did not reach solver_tol = {solver_tol:g} in {maxit} "
                      f"iterations (relative KKT residual {history[-1] if history else initial:.3e}; "
                      f"last steps {steps[-3:]})", history=history, solver="newton")


def _step(problem, s, d, memory, k, history, deadline=None):
    """The next f from the state s (iteration k) and its Newton direction d, by the globalisation of the
    problem's kind; ``memory``: the merit values so far (``recent``), and for m_t > 0 T(f) if known
    (``fixed_point``) and |f - T(f)| per iteration (``changes``).  Returns (f, kind of step)."""
    if problem.energy_merit:
        return energy_step(problem, s, d)
    if problem.quasi_variational:
        inner = dict(solver_tol=max(memory["solver_tol"], min(INNER * problem.residual(s), INNER_LOOSEST)),
                     maxit=memory["maxit"], deadline=deadline, budget=INNER_BUDGET)
        fixed_point = _fixed_point_step(problem, s, inner) if memory["fixed_point"] is None else memory["fixed_point"]
        change = np.max(np.abs(s.f - fixed_point)) / problem.scale(s)
        changes = memory["changes"]
        changes.append(change)
        if len(changes) > 10 and min(changes[-5:]) > min(changes[:-5]):
            raise SolverError(f"semismooth Newton on the contact points: neither Newton steps nor the fixed "
                              f"point on the friction bound reduce |f - T(f)| (now {change:.3e} after {k} "
                              "iterations): the bound map is not a contraction here, and the quasi-variational "
                              "inequality (m_t > 0) may have no solution or several", history=history,
                              solver="newton")
        f, kind, memory["fixed_point"] = _qvi_step(problem, s, d, fixed_point, inner)
        return f, kind
    memory["recent"].append(merit(problem, s))
    f, kind = _merit_step(problem, s, d, memory["recent"])
    if f is None:
        raise SolverError(f"semismooth Newton on the contact points stalled at iteration {k + 1}: no "
                          f"Levenberg-Marquardt step lowers the merit function (KKT residual "
                          f"{problem.residual(s):.3e}); the problem may have no solution",
                          history=history, solver="newton")
    return f, kind


def merit(problem, s):
    """Psi = 1/2 sum_q W_qq G_q^2 at the state s (the merit function without energy)."""
    return 0.5 * float(np.sum(problem.diagonal * s.G * s.G))


def _merit_step(problem, s, d, recent):
    """Non-monotone Armijo backtracking on Psi along d, else Levenberg-Marquardt; (f, kind) or (None, "stalled")."""
    psi = merit(problem, s)
    reference = max(recent[-5:] + [psi])
    alpha = 1.0
    for _ in range(9):
        trial = s.f + alpha * d
        if merit(problem, problem.evaluate(trial)) <= reference - SIGMA * alpha * 2 * psi:
            return trial, "newton" if alpha == 1 else f"newton x{alpha:g}"
        alpha *= 0.5
    # Levenberg-Marquardt on the Gauss-Newton model of Psi
    J = problem.jacobian(s)
    JtS = J.T * problem.diagonal
    H = JtS @ J
    g = JtS @ s.G
    scaling = np.maximum(np.diag(H), 1e-300)
    mu = 1e-6
    for _ in range(24):
        step = np.linalg.lstsq(H + mu * np.diag(scaling), -g, rcond=None)[0]
        trial = s.f + step
        if merit(problem, problem.evaluate(trial)) < psi:
            return trial, "levenberg-marquardt"
        mu *= 10
    return None, "stalled"


def _qvi_step(problem, s, d, fixed_point, inner):
    """m_t > 0: the Newton point if it lowers the fixed-point residual r(f) = |f - T(f)|_inf (T: the
    solution with the bound frozen at f, solved with the keywords ``inner``), else T(f).  ``fixed_point``:
    T(s.f).  Returns (new f, kind, T(new f) or None)."""
    residual = np.max(np.abs(s.f - fixed_point))
    for alpha in (1.0, 0.5):
        trial = s.f + alpha * d
        trial_fixed_point = _fixed_point_step(problem, problem.evaluate(trial), inner)
        if np.max(np.abs(trial - trial_fixed_point)) <= (1 - SIGMA * alpha) * residual:
            return trial, "newton" if alpha == 1 else f"newton x{alpha:g}", trial_fixed_point
    return fixed_point, "fixed point", None


def _fixed_point_step(problem, s, inner):
    """T(f): the solution of the problem with the friction bound frozen at its value at f (m_t = 0, a
    spatially varying c_tau = beta / omega), by :func:`solve` with its own globalisation and the keywords
    ``inner`` (solver_tol, maxit, deadline, budget): an inexact inner solve, to :data:`INNER` times the outer KKT
    residual at f, at most :data:`INNER_LOOSEST`, but not below the outer solver_tol (T only steers the outer
    iteration, whose own test decides convergence; a fixed 1e-13 made round-off-bound inner solves fail
    where the outer would have stopped, and ignored a looser solver_tol)."""
    return solve(problem.variant(c_tau=s.beta / problem.omega, m_t=0.0), s.f, **inner)[0]


def _homotopy(problem, s):
    """The problem at continuation parameter s in [0, 1] (s = 1: ``problem``): for m_t > 0 c_tau scaled
    by s; otherwise (NIPG) W = sym(W) + s skew(W), symmetric at s = 0."""
    if problem.quasi_variational:
        return problem.variant(c_tau=s * problem.c_tau)
    symmetric_part = 0.5 * (problem.W + problem.W.T)
    return problem.variant(W=symmetric_part + s * (problem.W - symmetric_part), symmetric=s == 0)


def _continuation(problem, solver_tol, maxit, progress, error, deadline=None, budget=None):
    """After a failure without energy: follow the solution from an easy problem to this one
    (:func:`_homotopy`).  NIPG: s = 0 (the symmetric problem, solved by the energy method), then
    steps in s doubled after a success and halved after a failure, from 1/16.  m_t > 0: s = 1e-6
    (c_tau tiny: the bound map contracts), then s multiplied by a factor (4 at first) that is squared
    after a success and square-rooted after a failure.  Each solve starts from the last solution.
    Raises the original ``error`` (with a note) when the step (factor) falls below 1/1024 (1.001), or when the
    iterations of all its solves, failed ones included, pass ``budget`` x maxit (if given)."""
    f, iterations, steps, history, spent = np.zeros(2 * problem.M), 0, [], [], 0
    geometric = problem.quasi_variational
    done, step = (0.0, 1e-6) if geometric else (-1.0, 1.0)  # s = 1e-6, or s = 0 first

    def next_value():
        return min(1.0, step if done == 0 and geometric else done * step if geometric else done + step)

    while done < 1:
        s = next_value() if done >= 0 else 0.0
        try:
            f, info = _solve_directly(_homotopy(problem, s), f.copy(), solver_tol, maxit, progress,
                                      deadline=deadline, counted=iterations)
        except TimeLimitError:
            raise
        except SolverError as failure:
            if done < 0 or (geometric and done == 0):
                raise SolverError(f"{error} (and the continuation failed at its start s = {s:g})",
                                  history=error.history, solver="newton") from error
            step = np.sqrt(step) if geometric else step / 2
            spent += max(len(failure.history), 1)
            if (geometric and step < 1.001) or (not geometric and step < 1 / 1024) \
                    or (budget is not None and spent > budget * maxit):
                raise SolverError(f"{error} (and the continuation stopped at s = {done:g} after {spent} "
                                  f"iterations)", history=error.history, solver="newton") from error
            continue
        iterations += info["iterations"]
        spent += info["iterations"]
        steps += [f"continuation s = {s:g}"] + info["steps"]
        history += info["history"]
        step = (4.0 if done == 0 else step * step) if geometric else (1 / 16 if done < 0 else 2 * step)
        done = s
    info.update(iterations=iterations, steps=steps, history=history)
    return f, info


def _proximal(problem, f, solver_tol, maxit, progress, energy_tol, deadline=None, counted=0):
    """The proximal point method of the module docstring (redundant points, m_t = 0), from f.  ``counted``:
    iterations done before (for the progress messages)."""
    mu, iterations, history, steps = PROXIMAL_START, 0, [], []
    initial = problem.residual(problem.evaluate(f))
    while not problem.done(problem.evaluate(f), solver_tol, energy_tol):
        if iterations >= maxit:
            raise SolverError(f"semismooth Newton on the contact points (proximal point method) did not reach "
                              f"solver_tol = {solver_tol:g} in {maxit} iterations (relative KKT residual "
                              f"{history[-1]:.3e})", history=history, solver="newton")
        subproblem = problem.variant(W=problem.W + np.diag(mu * problem.diagonal),
                                     w0=problem.w0 + mu * problem.diagonal * f, redundant=False)
        steps.append(f"proximal mu = {mu:g}")
        try:
            # without energy at most PROXIMAL_BUDGET steps per subproblem; with energy the whole remaining budget
            # (the budget of 10 there made hp SIPG on Example 6.1 pick other forces: eta_h rose to 5e-3 at level 18)
            budget = maxit - iterations if problem.energy_merit else min(PROXIMAL_BUDGET, maxit - iterations)
            f, info = iterate(subproblem, f, solver_tol, budget, progress,
                              energy_tol, outer=problem, counted=counted + iterations, deadline=deadline,
                              unfinished=True)
        except TimeLimitError:
            raise
        except SolverError as error:  # its globalisation gave up: restart from the centre, each attempt counted
            iterations += max(len(error.history), 1)
            history += error.history
            mu *= PROXIMAL_INCREASE
            continue
        iterations += info["iterations"]
        history += info["history"]
        steps += info["steps"]
        solved = subproblem.done(subproblem.evaluate(f), solver_tol, energy_tol)
        mu = mu / PROXIMAL_DECREASE if solved else mu * PROXIMAL_INCREASE
    return f, _info(problem, problem.evaluate(f), solver_tol, iterations, history, initial, steps)
