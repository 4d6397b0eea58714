"""The solve() entry point and the Solution record."""

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from .checks import MEMORY_BUDGET
from .dg.discretization import Discretization
from .errors import warn
from .meshes import snapshot
from .solvers.fixed_point import FixedPointOptions, fixed_point
from .solvers.newton import NewtonOptions, newton
from .solvers.uzawa import UzawaOptions, uzawa
from .threads import limited_blas
from .transfer import WarmStart, initial_guess

__all__ = ["Solution", "solve", "finish", "SOLVERS", "DEFAULT_SOLVER_TOL"]

SOLVERS = {"newton": (newton, NewtonOptions), "uzawa": (uzawa, UzawaOptions),
           "fixed_point": (fixed_point, FixedPointOptions)}
DEFAULT_SOLVER_TOL = {name: options.solver_tol for name, (_, options) in SOLVERS.items()}


@dataclass
class Solution:
    """A discrete solution u_h of (3.1) (for m_t > 0 with j_tau(u_h, .) of (1.4)) and lam_tau of Lemma 3.1.

    ``mesh``: the solution's own copy of the mesh it was solved on (:func:`ngdgfric.meshes.snapshot`), so
    that refining that mesh afterwards (a hand-written adaptive loop) leaves the Solution valid;
    ``u``: GridFunction on the DG space; ``lam_tau``: GridFunction of the multiplier on Gamma_C;
    ``iterations``, ``history``: the nonlinear solver's iteration count and convergence history;
    ``timings``: seconds (assemble, solve, total); ``info``: solver diagnostics; ``state``: for an
    inexact Newton solve (option ``energy_tol``) that stopped before its tolerance, the
    :class:`~ngdgfric.solvers.newton.NewtonState` that :func:`finish` continues; None otherwise.
    ``max_order``: the largest polynomial degree p_T (p on a mesh of one degree); ``orders``: the degree of every
    element.  ``order`` is a deprecated alias of ``max_order``: on hp meshes it read as "the" order, but it was
    only the largest (DeprecationWarning).
    """

    problem: object
    mesh: object
    method: str
    max_order: int
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
    def orders(self):
        """The polynomial degree p_T of every element (an integer array in the mesh's element order; a copy)."""
        return np.array(self.discretization.orders, dtype=np.int64)

    @property
    def order(self):
        """Deprecated: the largest degree, :attr:`max_order` (see :attr:`orders` for the degree per element)."""
        warn("Solution.order is deprecated: it is the largest degree, Solution.max_order (the degree of "
             "every element: Solution.orders)", DeprecationWarning)
        return self.max_order

    @property
    def ndof(self):
        """Number of degrees of freedom of u_h."""
        return self.u.space.ndof


@limited_blas
def solve(problem, mesh, method="sipg", order=1, eta=None, solver="newton", solver_tol=None, initial=None,
          penalty_check="warn", max_ndof=None, max_bytes=MEMORY_BUDGET, **options):
    """Solve the DG discretisation (3.1) of the contact problem on ``mesh``.

    problem: a :class:`ContactProblem`; mesh: an NGSolve mesh with the problem's boundary names.  The
    solution lives on its own copy of ``mesh`` (``Solution.mesh``, :func:`ngdgfric.meshes.snapshot`), so
    ``mesh`` may be refined afterwards (a hand-written SOLVE -> ESTIMATE -> MARK -> REFINE loop) while the
    Solution stays valid and can start the next solve (``initial``).
    method: one of ``ngdgfric.dg.methods.METHODS`` (Section 3); order: polynomial degree p >= 1.
    eta: penalty parameter (default 30 mu, Section 6).
    solver: "newton" (default; the problem condensed onto the contact points and solved there by a
    globalised semismooth Newton method, :func:`ngdgfric.solvers.newton.newton`, fully coupled for
    m_t > 0), "uzawa" (the paper's method, :func:`ngdgfric.solvers.uzawa.uzawa`, m_t = 0 only) or
    "fixed_point" (on the friction bound for m_t > 0, :func:`ngdgfric.solvers.fixed_point.fixed_point`,
    option ``inner="newton"|"uzawa"``); all solve the same discrete problem.
    solver_tol: the solver's tolerance; None: ``DEFAULT_SOLVER_TOL[solver]`` (Newton: 1e-13 on the
    relative KKT residual at the contact points; Uzawa and the fixed point: 1e-8 on the relative
    max-norm change, as in Section 6, and for Uzawa also on the complementarity residual of (3.4)).
    The old name ``tol`` still works (DeprecationWarning).
    penalty_check: "warn" (default), "raise" or "ignore" when eta is below the method's coercivity
    threshold (:func:`ngdgfric.dg.methods.check_penalty`).
    initial: a Solution (or a :class:`~ngdgfric.transfer.WarmStart`) to start from, on this mesh or on
    another, e.g. coarser, mesh of the same domain (:func:`ngdgfric.transfer.initial_guess`).
    max_ndof: refuse (ValueError, before assembly) above this many DOFs; None: above an estimated
    ``max_bytes`` bytes of memory (default 8 GB, :func:`ngdgfric.checks.check_size`).  Data given as
    CoefficientFunctions are checked pointwise first (:func:`ngdgfric.checks.check_data`).
    options: the solver's options (:class:`~ngdgfric.solvers.newton.NewtonOptions`,
    :class:`~ngdgfric.solvers.uzawa.UzawaOptions`, :class:`~ngdgfric.solvers.fixed_point.FixedPointOptions`), e.g.
    ``maxit``, ``progress`` (callable(message)); unknown names and bad values raise ValueError before
    anything is assembled.
    """
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {sorted(SOLVERS)}, got {solver!r}")
    function, options_class = SOLVERS[solver]
    settings = options_class.from_keywords(solver_tol=_solver_tol(solver_tol, options), **options)
    start_from = None if initial is None else _warm_start(initial)
    start = time.perf_counter()
    disc = Discretization(problem, snapshot(mesh), method, order, eta, penalty_check, max_ndof, max_bytes)
    if settings.max_seconds is not None:  # the limit counts from here: what assembly took is the solver's no more
        left = settings.max_seconds - (time.perf_counter() - start)
        settings = dataclasses.replace(settings, max_seconds=max(left, 1e-9))
    u, lam_tau, info = function(disc, settings, None if start_from is None else initial_guess(start_from, disc))
    timings = dict(assemble=disc.timings["assemble"], setup=disc.timings["setup"],
                   solve=info["timings"]["total"], total=time.perf_counter() - start)
    return Solution(problem, disc.mesh, disc.method.name, disc.order, disc.eta, solver, u, lam_tau,
                    info["iterations"], info["history"], timings, disc, info, info.pop("state", None))


def _solver_tol(solver_tol, options):
    """``solver_tol``, or the value of the deprecated keyword ``tol`` (removed from ``options``)."""
    if "tol" not in options:
        return solver_tol
    warn("solve(tol=...) is deprecated: the solver's tolerance is solver_tol", DeprecationWarning)
    tol = options.pop("tol")
    if solver_tol is not None and tol is not None:
        raise ValueError(f"give solver_tol only (got solver_tol={solver_tol!r} and the deprecated tol={tol!r})")
    return tol if solver_tol is None else solver_tol


def _warm_start(initial):
    """``initial`` of :func:`solve` as a :class:`WarmStart`: the one place a Solution is converted."""
    if isinstance(initial, WarmStart):
        return initial
    if isinstance(initial, Solution):
        return WarmStart.from_solution(initial)
    raise ValueError(f"initial must be a Solution or a WarmStart, got {type(initial).__name__}")


@limited_blas
def finish(sol, solver_tol=None, energy_tol=None, maxit=100):
    """Continue an inexact Newton solve (``sol.state``, option ``energy_tol`` of :func:`solve`) to
    ``solver_tol`` (default ``DEFAULT_SOLVER_TOL["newton"]``) or to a smaller ``energy_tol``, with the same
    factorisation; returns the new :class:`Solution` (``sol`` itself if it was solved to its tolerance
    already).  ``iterations`` and ``history`` continue those of ``sol``; ``timings["solve"]`` adds this
    run's seconds."""
    if sol.state is None:
        return sol
    options = NewtonOptions.from_keywords(solver_tol=solver_tol, energy_tol=energy_tol, maxit=maxit)
    start = time.perf_counter()
    u, lam_tau, info = sol.state.run(options)
    seconds = time.perf_counter() - start
    timings = dict(sol.timings, solve=sol.timings["solve"] + seconds, total=sol.timings["total"] + seconds)
    return Solution(sol.problem, sol.mesh, sol.method, sol.max_order, sol.eta, sol.solver, u, lam_tau,
                    sol.iterations + info["iterations"], sol.history + info["history"], timings,
                    sol.discretization, info, info.pop("state", None))
