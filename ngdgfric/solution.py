"""The solve() entry point and the Solution record."""

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from .checks import MEMORY_BUDGET
from .contact import Contact
from .dg.discretization import Discretization
from .errors import warn
from .meshes import snapshot
from .solvers.fixed_point import FixedPointOptions, fixed_point
from .solvers.newton import NewtonOptions, newton
from .solvers.uzawa import UzawaOptions, uzawa
from .threads import limited_blas
from .transfer import WarmStart, initial_guess, starting_point

__all__ = ["Solution", "solve", "finish", "SOLVERS", "DEFAULT_SOLVER_TOL"]

SOLVERS = {"newton": (newton, NewtonOptions), "uzawa": (uzawa, UzawaOptions),
           "fixed_point": (fixed_point, FixedPointOptions)}
DEFAULT_SOLVER_TOL = {name: options.solver_tol for name, (_, options) in SOLVERS.items()}


@dataclass(kw_only=True)
class Solution:
    r"""A discrete solution :math:`u_h` of (3.1) and the multiplier :math:`\lambda_\tau` of Lemma 3.1.

    For :math:`m_t > 0`, :math:`u_h` solves (3.1) with the friction functional :math:`j_\tau(u_h, \cdot)` of
    (1.4).  :func:`ngdgfric.solve` and :func:`ngdgfric.finish` make it; the constructor's arguments are listed
    here because they are its fields, not for building one by hand.

    Parameters
    ----------
    problem : ContactProblem
        The problem solved (:class:`ngdgfric.ContactProblem`).
    mesh : ngsolve.Mesh
        The solution's own copy of the mesh it was solved on (``ngdgfric.meshes.snapshot``), so that
        refining that mesh afterwards (a hand-written adaptive loop) leaves the Solution valid.
    method : str
        The name of the method, e.g. ``"sipg"`` (:data:`ngdgfric.METHODS`).
    max_order : int
        The largest polynomial degree :math:`p_T` (:math:`p` on a mesh of one degree).
    eta : float or EdgeCoefficient
        The penalty parameter used: the number given or the method's default (an ``EdgeCoefficient``,
        one value per edge, for a varying material).
    solver : str
        The contact solver: ``"newton"``, ``"uzawa"`` or ``"fixed_point"``.
    u : ngsolve.GridFunction
        The displacement :math:`u_h` on the DG space (:math:`H^1` for the conforming baseline).
    lam_tau : ngsolve.GridFunction
        The multiplier :math:`\lambda_\tau` on :math:`\Gamma_C`.
    iterations : int
        The nonlinear solver's iteration count.
    history : list of float
        The nonlinear solver's convergence history, one entry per iteration.
    timings : dict
        Seconds: ``"assemble"``, ``"setup"``, ``"solve"``, ``"total"``.
    discretization : Discretization
        The discretisation solved (:class:`ngdgfric.Discretization`: spaces, matrices, the material).
    contact : Contact
        Its contact data (:class:`ngdgfric.Contact`: the multiplier space, the contact Gauss points, the
        traces).
    info : dict, optional
        The solver's diagnostics (e.g. ``"factorizations"``, ``"least_squares_solves"``; ``"changed_points"``: the
        contact points whose state -- no contact, stick, slip -- differs between the start, a warm start or zero, and
        the solution, and ``"start_states"``, ``ngdgfric.Contact.point_states`` at the start).  Default: empty.
    state : object, optional
        For an inexact Newton solve (option ``energy_tol``) that stopped before its tolerance, the
        ``NewtonState`` (:mod:`ngdgfric.solvers.newton`) that :func:`ngdgfric.finish` continues.  Default
        ``None``: solved to its tolerance.

    Attributes
    ----------
    orders
        The degree :math:`p_T` of every element, an integer array in the mesh's element order (a copy).
    ndof : int
        The number of degrees of freedom of :math:`u_h`.
    order : int
        Deprecated alias of ``max_order`` (DeprecationWarning): on hp meshes it read as "the" order, but it
        was only the largest.

    See Also
    --------
    ngdgfric.solve : Makes a Solution.
    ngdgfric.estimate : Its error estimator.
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
    contact: Contact = field(repr=False)
    info: dict = field(default_factory=dict, repr=False)
    state: object = field(default=None, repr=False)

    @property
    def orders(self):
        """The polynomial degree :math:`p_T` of every element (an integer array in the mesh's element order; a copy)."""
        return np.array(self.discretization.orders, dtype=np.int64)

    @property
    def order(self):
        """The largest degree, ``max_order`` (deprecated; ``orders`` has the degree per element)."""
        warn("Solution.order is deprecated: it is the largest degree, Solution.max_order (the degree of "
             "every element: Solution.orders)", DeprecationWarning)
        return self.max_order

    @property
    def ndof(self):
        """Number of degrees of freedom of :math:`u_h`."""
        return self.u.space.ndof

    def __repr__(self):
        """One line a user can read: the problem, the method and degrees, the DOFs and the solver's work."""
        low, high = int(self.orders.min()), self.max_order
        degrees = f"p = {high}" if low == high else f"p = {low}..{high}"
        return (f"Solution({self.problem.name!r}, {self.method} {degrees}, {self.ndof} DOFs, {self.solver} "
                f"{self.iterations} iterations)")


@limited_blas
def solve(problem, mesh, method="sipg", order=1, eta=None, solver="newton", solver_tol=None, initial=None,
          penalty_check="warn", max_ndof=None, max_bytes=MEMORY_BUDGET, **options):
    r"""Solve the DG discretisation (3.1) of the contact problem on ``mesh``.

    The solution lives on its own copy of ``mesh`` (``Solution.mesh``), so ``mesh`` may be refined afterwards
    (a hand-written SOLVE, ESTIMATE, MARK, REFINE loop) while the Solution stays valid and can start the next
    solve (``initial``).  All three solvers solve the same discrete problem.

    Parameters
    ----------
    problem : ContactProblem
        The contact problem (:class:`ngdgfric.ContactProblem`).
    mesh : ngsolve.Mesh
        A mesh of the problem's domain with the problem's boundary names.
    method : str, optional
        One of :data:`ngdgfric.METHODS` (Section 3): ``"sipg"``, ``"nipg"``, ``"bassi"``, ``"brezzi"``, ``"ldg"``
        or ``"cg"`` (the conforming baseline).  Default ``"sipg"``.
    order : int, optional
        The polynomial degree :math:`1 \le p \le 30` (NGSolve's assembly overflows from 33).  Default ``1``.
    eta : float or None, optional
        The penalty parameter.  Default ``None``: the method's own default (:data:`ngdgfric.METHODS`): ``sipg``
        :math:`30\mu`, ``nipg`` :math:`30\mu`, ``bassi`` :math:`6`, ``brezzi`` :math:`1`, ``ldg`` :math:`30\mu`,
        ``cg`` :math:`30\mu` (:math:`\mu` times a number for the edge penalties, the paper's :math:`30\mu` of
        Section 6; a pure number for the lifting penalties of Bassi et al. and Brezzi et al.).  sipg and cg raise
        theirs to 1.5 times the coercivity threshold where :math:`30\mu` is not above it (nearly incompressible
        material: ``SIPG_THRESHOLD`` of :mod:`ngdgfric.dg.methods`).
    solver : str, optional
        ``"newton"`` (default): the problem condensed onto the contact points and solved there by a
        globalised semismooth Newton method (:mod:`ngdgfric.solvers.newton`), fully coupled for :math:`m_t > 0`;
        ``"uzawa"``: the paper's method (:mod:`ngdgfric.solvers.uzawa`), :math:`m_t = 0` only;
        ``"fixed_point"``: a fixed point on the friction bound for :math:`m_t > 0`
        (:mod:`ngdgfric.solvers.fixed_point`, option ``inner="newton"`` or ``"uzawa"``).
    solver_tol : float or None, optional
        The solver's tolerance.  Default ``None``: ``DEFAULT_SOLVER_TOL[solver]``: for Newton ``1e-13`` on the
        relative KKT residual at the contact points; for Uzawa and the fixed point ``1e-8`` on the relative
        max-norm change, as in Section 6, and for Uzawa also on the complementarity residual of (3.4).  The old
        name ``tol`` still works (DeprecationWarning).
    initial : Solution or WarmStart or None, optional
        A :class:`ngdgfric.Solution` (or a :class:`ngdgfric.WarmStart`) to start from, on this mesh or on
        another, e.g. coarser, mesh of the same domain (interpolated, ``ngdgfric.transfer.initial_guess``).
        Default ``None``: start from zero.
    penalty_check : str, optional
        What to do when ``eta`` is below the method's coercivity threshold (``check_penalty`` of
        :mod:`ngdgfric.dg.methods`): ``"warn"`` (default, a :class:`ngdgfric.PenaltyWarning`), ``"raise"``
        (ValueError) or ``"ignore"``.
    max_ndof : int or None, optional
        Refuse (ValueError, before assembly) above this many DOFs.  Default ``None``: refuse above an estimated
        ``max_bytes`` of memory (``check_size`` of :mod:`ngdgfric.checks`).
    max_bytes : float, optional
        The memory budget in bytes when ``max_ndof`` is ``None``.  Default ``8e9`` (8 GB).
    **options
        The fields of the solver's options class as keywords: :class:`ngdgfric.NewtonOptions`,
        :class:`ngdgfric.UzawaOptions` or :class:`ngdgfric.FixedPointOptions`, e.g. ``maxit``, ``progress``
        (``callable(message)``).

    Returns
    -------
    Solution
        The discrete solution :math:`u_h`, the multiplier :math:`\lambda_\tau`, the solver's iterations,
        history, timings and diagnostics (:class:`ngdgfric.Solution`).

    Raises
    ------
    ValueError
        Before anything is assembled: an unknown solver, an unknown option name or a bad option value, too many
        DOFs; data given as CoefficientFunctions are checked pointwise first (``check_data`` of
        :mod:`ngdgfric.checks`; :class:`ngdgfric.DataError`, a ValueError).
    SolverError
        The solver failed (:class:`ngdgfric.SolverError`, with its convergence history); a
        :class:`ngdgfric.TimeLimitError` at the option ``max_seconds``, a :class:`ngdgfric.PardisoError` if MKL
        PARDISO fails.

    Warns
    -----
    PenaltyWarning
        ``eta`` below the method's coercivity threshold (``penalty_check="warn"``).
    LockingWarning
        The method locks at the problem's Poisson ratio (:class:`ngdgfric.LockingWarning`).
    SolverWarning
        The solver took a fallback that the result survived (:class:`ngdgfric.SolverWarning`).

    See Also
    --------
    ngdgfric.finish : Continue an inexact Newton solve.
    ngdgfric.estimate : The a posteriori error estimator of the solution.
    ngdgfric.adapt : Solve adaptively to a tolerance.

    Examples
    --------
    >>> problem = ndf.example_6_1()
    >>> mesh = ndf.uniform_mesh(problem, 0.5)
    >>> sol = ndf.solve(problem, mesh, method="sipg", order=1)
    >>> sol.ndof, sol.solver
    (48, 'newton')

    Another solver, with one of its options (:class:`ngdgfric.UzawaOptions`), from the solution above:

    >>> sol2 = ndf.solve(problem, mesh, order=2, solver="uzawa", maxit=5000, initial=sol)
    >>> print(sol2.ndof, sol2.history[-1] <= 1e-8)
    96 True
    """
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {sorted(SOLVERS)}, got {solver!r}")
    function, options_class = SOLVERS[solver]
    settings = options_class.from_keywords(solver_tol=_solver_tol(solver_tol, options), **options)
    start_from = None if initial is None else _warm_start(initial)
    start = time.perf_counter()
    disc = Discretization(problem, snapshot(mesh), method, order, eta, penalty_check, max_ndof, max_bytes)
    contact = Contact(disc)
    if settings.max_seconds is not None:  # the limit counts from here: what assembly took is the solver's no more
        left = settings.max_seconds - (time.perf_counter() - start)
        settings = dataclasses.replace(settings, max_seconds=max(left, 1e-9))
    guess = None if start_from is None else initial_guess(start_from, contact)
    u, lam_tau, info = function(disc, contact, settings, guess)
    _count_changes(contact, contact.point_states(*(starting_point(contact) if guess is None else guess)), u, lam_tau,
                   info)
    timings = dict(assemble=disc.timings["assemble"], setup=disc.timings["setup"],
                   solve=info["timings"]["total"], total=time.perf_counter() - start)
    return Solution(problem=problem, mesh=disc.mesh, method=disc.method.name, max_order=disc.order, eta=disc.eta,
                    solver=solver, u=u, lam_tau=lam_tau, iterations=info["iterations"], history=info["history"],
                    timings=timings, discretization=disc, contact=contact, info=info, state=info.pop("state", None))


def _count_changes(contact, start, u, lam_tau, info):
    """How far the start was (a warm start, or zero): ``info["start_states"]`` = ``start`` (the states of the laws
    at the starting point, ``Contact.point_states``) and ``info["changed_points"]``: the contact points whose state
    (no contact, stick, slip) differs at the solution (u, lam_tau)."""
    end = contact.point_states(u, lam_tau, info.get("pair_multiplier"))
    info.update(start_states=start, changed_points=int(np.sum(start != end)))


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
    """``initial`` of ``solve`` as a ``WarmStart``: the one place a Solution is converted."""
    if isinstance(initial, WarmStart):
        return initial
    if isinstance(initial, Solution):
        return WarmStart.from_solution(initial)
    raise ValueError(f"initial must be a Solution or a WarmStart, got {type(initial).__name__}")


@limited_blas
def finish(sol, solver_tol=None, energy_tol=None, maxit=100):
    """Continue an inexact Newton solve to its tolerance, with the same factorisation.

    An inexact solve (option ``energy_tol`` of :func:`ngdgfric.solve`) that stopped before its tolerance keeps
    its factorisation, condensed problem and forces in ``sol.state``; this continues it without factorising
    again.

    Parameters
    ----------
    sol : Solution
        The solution of an inexact Newton solve (:class:`ngdgfric.Solution`).
    solver_tol : float or None, optional
        The Newton tolerance to reach.  Default ``None``: ``DEFAULT_SOLVER_TOL["newton"]`` (``1e-13``).
    energy_tol : float or None, optional
        Stop instead at this (smaller) linearisation estimate.  Default ``None``: go on to ``solver_tol``.
    maxit : int, optional
        Newton iterations of this run.  Default ``100``.

    Returns
    -------
    Solution
        The new solution (``sol`` itself if it was solved to its tolerance already).  Its ``iterations`` and
        ``history`` continue those of ``sol``; ``timings["solve"]`` adds this run's seconds.

    Examples
    --------
    >>> problem = ndf.example_6_1()
    >>> sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.25), order=2, energy_tol=1.0)
    >>> sol.state is None
    False
    >>> ndf.finish(sol).state is None
    True
    """
    if sol.state is None:
        return sol
    options = NewtonOptions.from_keywords(solver_tol=solver_tol, energy_tol=energy_tol, maxit=maxit)
    start = time.perf_counter()
    u, lam_tau, info = sol.state.run(options)
    seconds = time.perf_counter() - start
    timings = dict(sol.timings, solve=sol.timings["solve"] + seconds, total=sol.timings["total"] + seconds)
    if "start_states" in sol.info:
        _count_changes(sol.contact, sol.info["start_states"], u, lam_tau, info)
    return dataclasses.replace(sol, u=u, lam_tau=lam_tau, iterations=sol.iterations + info["iterations"],
                               history=sol.history + info["history"], timings=timings, info=info,
                               state=info.pop("state", None))
