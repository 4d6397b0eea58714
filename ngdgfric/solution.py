"""The solve() entry point and the Solution record."""

import time
from dataclasses import dataclass, field

from . import fixed_point, newton, uzawa
from .discretization import Discretization
from .options import validate
from .transfer import initial_guess

__all__ = ["Solution", "solve", "finish", "SOLVERS", "DEFAULT_TOL"]

SOLVERS = {"newton": (newton.newton, newton.OPTIONS), "uzawa": (uzawa.uzawa, uzawa.OPTIONS),
           "fixed_point": (fixed_point.fixed_point, fixed_point.OPTIONS)}
DEFAULT_TOL = {"newton": 1e-13, "uzawa": 1e-8, "fixed_point": 1e-8}


@dataclass
class Solution:
    """A discrete solution u_h of (3.1) (for m_t > 0 with j_tau(u_h, .) of (1.4)) and lam_tau = l t of Lemma 3.1.

    ``u``: GridFunction on the DG space; ``lam_tau``: GridFunction of l on Gamma_C;
    ``iterations``, ``history``: the nonlinear solver's iteration count and convergence history;
    ``timings``: seconds (assemble, solve, total); ``info``: solver diagnostics; ``state``: for an
    inexact Newton solve (option ``energy_tol``) that stopped before its tolerance, the
    :class:`~ngdgfric.newton.NewtonState` that :func:`finish` continues; None otherwise.
    """

    problem: object
    mesh: object
    method: str
    order: int
    eta: object
    solver: str
    u: object
    lam_tau: object
    iterations: int
    history: list
    timings: dict
    discretization: Discretization = field(repr=False)
    info: dict = field(default_factory=dict, repr=False)
    state: object = field(default=None, repr=False)

    @property
    def ndof(self):
        """Number of degrees of freedom of u_h."""
        return self.u.space.ndof


def solve(problem, mesh, method="sipg", order=1, eta=None, solver="newton", tol=None, initial=None,
          penalty_check="warn", max_ndof=None, **options):
    """Solve the DG discretisation (3.1) of the contact problem on ``mesh``.

    problem: a :class:`ContactProblem`; mesh: an NGSolve mesh with the problem's boundary names.
    method: one of ``ngdgfric.methods.METHODS`` (Section 3); order: polynomial degree p >= 1.
    eta: penalty parameter (default 30 mu, Section 6).
    solver: "newton" (default; the problem condensed onto the contact points and solved there by a
    globalised semismooth Newton method, :func:`ngdgfric.newton.newton`, fully coupled for
    m_t > 0), "uzawa" (the paper's method, :func:`ngdgfric.uzawa.uzawa`, m_t = 0 only) or
    "fixed_point" (on the friction bound for m_t > 0, :func:`ngdgfric.fixed_point.fixed_point`,
    option ``inner="newton"|"uzawa"``); all solve the same discrete problem.
    tol: the solver's tolerance; None: ``DEFAULT_TOL[solver]`` (Newton: 1e-13 on the relative KKT
    residual at the contact points; Uzawa and the fixed point: 1e-8 on the relative max-norm
    change, as in Section 6, and for Uzawa also on the complementarity residual of (3.4)).
    penalty_check: "warn" (default), "raise" or "ignore" when eta is below the method's coercivity
    threshold (:func:`ngdgfric.methods.check_penalty`).
    initial: a Solution to start from (on this mesh, or on another, e.g. coarser, mesh of the
    same domain: see :func:`ngdgfric.transfer.initial_guess`).
    max_ndof: refuse (ValueError, before assembly) above this many DOFs; None: above an estimated
    8 GB (:func:`ngdgfric.checks.check_size`).  Data given as CoefficientFunctions are checked
    pointwise first (:func:`ngdgfric.checks.check_data`).
    options: passed to the solver (``maxit``, ``progress``; ``linear_solver`` for Newton; ``rho``
    for Uzawa; ``inner`` and the inner solver's options for the fixed point); unknown names and
    bad values raise ValueError before anything is assembled.
    """
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {sorted(SOLVERS)}, got {solver!r}")
    function, spec = SOLVERS[solver]
    tol = DEFAULT_TOL[solver] if tol is None else tol
    validate(spec, solver, tol=tol, **options)
    start = time.perf_counter()
    disc = Discretization(problem, mesh, method, order, eta, penalty_check, max_ndof)
    start_guess = None if initial is None else initial_guess(initial, disc)
    u, lam, info = function(disc, tol=tol, initial=start_guess, **options)
    timings = dict(assemble=disc.timings["assemble"], setup=disc.timings["setup"],
                   solve=info["timings"]["total"], total=time.perf_counter() - start)
    return Solution(problem, mesh, disc.method.name, disc.order, disc.eta, solver, u, lam,
                    info["iterations"], info["history"], timings, disc, info, info.pop("state", None))


def finish(sol, tol=None, energy_tol=None, maxit=100):
    """Continue an inexact Newton solve (``sol.state``, option ``energy_tol`` of :func:`solve`) to ``tol``
    (default ``DEFAULT_TOL["newton"]``) or to a smaller ``energy_tol``, with the same factorisation;
    returns the new :class:`Solution` (``sol`` itself if it was solved to its tolerance already).
    ``iterations`` and ``history`` continue those of ``sol``; ``timings["solve"]`` adds this run's seconds."""
    if sol.state is None:
        return sol
    tol = DEFAULT_TOL["newton"] if tol is None else tol
    validate(newton.OPTIONS, "newton", tol=tol, energy_tol=energy_tol, maxit=maxit)
    start = time.perf_counter()
    u, lam, info = sol.state.run(tol, maxit, energy_tol=energy_tol)
    seconds = time.perf_counter() - start
    timings = dict(sol.timings, solve=sol.timings["solve"] + seconds, total=sol.timings["total"] + seconds)
    return Solution(sol.problem, sol.mesh, sol.method, sol.order, sol.eta, sol.solver, u, lam,
                    sol.iterations + info["iterations"], sol.history + info["history"], timings,
                    sol.discretization, info, info.pop("state", None))


