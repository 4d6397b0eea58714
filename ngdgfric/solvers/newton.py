r"""The default contact solver: condense onto :math:`\Gamma_C`, semismooth Newton on the points, recover :math:`u`.

The nonlinearity of (3.3)-(3.4) lives at the :math:`M` Gauss points of :math:`\Gamma_C`.  The solver

1. builds the traces :math:`B` at those points (``ContactTraces`` of :mod:`ngdgfric.contact.traces`) and
   condenses the linear part onto them: :math:`W = B A^{-1} B^T` and :math:`w_0 = B A^{-1} F`, by one partial
   factorisation (``Condensation`` of :mod:`ngdgfric.solvers.condensation`);
2. solves the contact laws at the points for the forces :math:`f` with a globalised semismooth Newton
   method on the dense :math:`2M \times 2M` problem (``ReducedContact`` of :mod:`ngdgfric.solvers.reduced`,
   ``solve`` of :mod:`ngdgfric.solvers.semismooth`: energy descent for the symmetric methods with
   :math:`m_t = 0`, a merit function with Levenberg-Marquardt safeguards for NIPG and :math:`m_t > 0`, both
   inside a proximal point method where :math:`W` is singular and :math:`m_t = 0` (redundant points on hp
   meshes); stopping test on the KKT residual of Lemma 3.1);
3. recovers :math:`u = A^{-1} (F - B^T f)` by one substitution, and the multiplier
   :math:`\lambda_\tau = f_t / \beta` (:math:`\beta = c_\tau (u_n - g_a)_+^{m_t} \omega`;
   :math:`\lambda_\tau = \operatorname{sign}(u_\tau)` where :math:`\beta = 0`).  The traces of the computed
   :math:`u` differ from :math:`w_0 - W f` by the solve's round-off times :math:`\operatorname{cond}(A)`, which a
   stiff compliance (:math:`c_n = 10^{10}`: :math:`N' = \omega c_n \approx 10^8`) turns into a visible KKT
   residual; then :math:`w_0` is shifted by that difference, the points are re-solved (one Newton step) and
   :math:`u` moved with the forces, :math:`u \leftarrow u - A^{-1} B^T \delta f` (iterative refinement of the
   nonlinear system: the round-off of that substitution is relative to the small :math:`\delta f`), at most
   ``MAX_CONSISTENCY`` = 3 times, so that the laws hold at the traces of the returned :math:`u`.

Each Newton step costs a dense solve with one row per penetrating or sticking point
(milliseconds on small meshes, 0.4 s with 3500 rows), so on large hp meshes the iteration count
matters; the whole solve costs about one sparse factorisation (the results page *Solver benchmark*).

**Inexact solves** (``energy_tol``, used by the adaptive loop): the iteration also stops once the
linearisation estimate :math:`\eta_{lin} = (\sum_q W_{qq} G_q^2)^{1/2}`, the KKT residual of the laws measured
in the energy units of :math:`|\!|\!| \cdot |\!|\!|_h` (``ReducedContact.linearization`` of
:mod:`ngdgfric.solvers.reduced`), is at most ``energy_tol``.  The returned ``state`` (``NewtonState``: the
factorisation, the condensed problem and the forces) continues such a solve to the full tolerance without
factorising again (:func:`ngdgfric.finish`).
"""

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..checks import callback, choice, optional, positive_integer, positive_number
from ..contact.traces import ContactTraces
from ..errors import SolverError, SolverWarning, TimeLimitError, deadline, warn
from ..transfer import starting_point
from . import pardiso, semismooth
from .condensation import LINEAR_SOLVERS, Condensation
from .floating import FloatingSolve
from .fullspace import FULL_SPACE_POINTS, FullSpaceState, applicable
from .options import SolverOptions
from .reduced import ReducedContact, pair_forces
from .selection import select

__all__ = ["newton", "NewtonOptions", "NewtonState"]

FORMULATIONS = ("auto", "condensed", "full-space")
MAX_CONSISTENCY = 3  # re-solves after a recovery whose traces violate the laws (stiff compliance)
FALLBACK_BYTES = 2e9  # formulation "auto": the condensed solver takes over a failed full-space solve if W fits in this


@dataclass(frozen=True)
class NewtonOptions(SolverOptions):
    r"""The options of the Newton solver (the keywords of ``solve(solver="newton")``, :func:`ngdgfric.solve`).

    The solver of :mod:`ngdgfric.solvers.newton`, the default: the problem condensed onto the contact points
    and solved there by a globalised semismooth Newton method.

    Parameters
    ----------
    solver_tol : float, optional
        The relative KKT residual :math:`\max_q W_{qq} |G_q| / \max_q |w_q|` at the contact points at which the
        iteration stops (:mod:`ngdgfric.solvers.reduced`; round-off sets its floor).  Default ``1e-13``.
    maxit : int, optional
        Newton iterations.  Default ``100``.
    progress : callable or None, optional
        ``progress(message)`` is called after each iteration with a line such as
        ``"newton 3: KKT residual 1.2e-09"``.  Default ``None``: no messages.
    linear_solver : str, optional
        ``"auto"`` (default: MKL PARDISO if installed, else NGSolve), ``"pardiso"`` or ``"ngsolve"``
        (the factorisation of :mod:`ngdgfric.solvers.condensation`).
    energy_tol : float or None, optional
        Also stop once the linearisation estimate :math:`\eta_{lin} \le` ``energy_tol`` (see
        :mod:`ngdgfric.solvers.newton`); then ``Solution.state`` can continue the solve
        (:func:`ngdgfric.finish`).  Default ``None``: no such stop.
    max_seconds : float or None, optional
        Stop with :class:`ngdgfric.TimeLimitError` (a :class:`ngdgfric.SolverError`) once the solve has run this
        long (checked between iterations; the factorisation itself is not interrupted).  Default ``None``: no
        limit.
    formulation : str, optional
        ``"auto"`` (default): the full space from ``FULL_SPACE_POINTS`` = 1000 contact points
        (:mod:`ngdgfric.solvers.fullspace`) where it applies, else condensed; if the full-space iteration fails
        and :math:`W` fits in ``FALLBACK_BYTES`` = 2e9 bytes, the condensed solver takes over and
        ``info["fallback"]`` says why.  ``"condensed"``: the Delassus operator (see
        :mod:`ngdgfric.solvers.newton`).  ``"full-space"``: :mod:`ngdgfric.solvers.fullspace` (symmetric methods,
        :math:`m_t = 0`, MKL PARDISO, no ``energy_tol``).

    Raises
    ------
    ValueError
        A value out of its range, named with the value.

    See Also
    --------
    ngdgfric.UzawaOptions, ngdgfric.FixedPointOptions : The options of the other solvers.

    Examples
    --------
    >>> ndf.NewtonOptions(maxit=20).solver_tol
    1e-13
    """

    solver = "newton"
    checks = dict(solver_tol=positive_number, maxit=positive_integer, progress=callback,
                  linear_solver=choice(*LINEAR_SOLVERS), energy_tol=optional(positive_number),
                  max_seconds=optional(positive_number), formulation=choice(*FORMULATIONS))

    solver_tol: float = 1e-13
    maxit: int = 100
    progress: Callable[[str], None] | None = None
    linear_solver: str = "auto"
    energy_tol: float | None = None
    max_seconds: float | None = None
    formulation: str = "auto"


class NewtonState:
    """One discretisation's condensed problem (``Condensation``, one
    factorisation) and ``ReducedContact``, with the current forces f.

    ``contact``: the :class:`~ngdgfric.Contact` of ``disc``; ``traces``: the ``ContactTraces`` of the
    problem solved (``contact.traces``, or those of a fixed-point step's problem)."""

    def __init__(self, disc, contact, traces, linear_solver="auto", A=None):
        start = time.perf_counter()
        self.disc, self.contact, self.traces = disc, contact, traces
        self.condensation = Condensation(disc.A if A is None else A, disc.F, traces, disc.symmetric, linear_solver)
        self.reduced = ReducedContact.condensed(self.condensation, traces, disc.symmetric, checked=True)
        self.f = None
        self.condense_seconds = time.perf_counter() - start

    def reload(self, F):
        """Take the load vector F (an array) instead of disc.F: w0 for it (one substitution), f kept as the start
        (the proximal steps of :mod:`ngdgfric.solvers.floating`)."""
        w0 = self.condensation.reload(F)
        self.reduced.shift(w0 - self.reduced.w0)

    def start_from(self, u, lam_tau):
        """f from GridFunctions u on ``disc.V`` and lam_tau on ``contact.Q``: the forces of the laws at u, with
        lam_tau."""
        w = self.traces.apply(u.vec.FV().NumPy())
        self.f = self.reduced.forces(w, self.contact.multiplier_values(lam_tau))

    def run(self, options):
        """Newton from the current f (zero if none) with the ``NewtonOptions`` ``options``, then recover
        u; returns (u, lam_tau, info) (see ``newton``).  The steps: solve the laws at the points, recover u
        (and make the laws hold at its traces), the GridFunctions, the diagnostics."""
        start = time.perf_counter()
        least_squares = self.reduced.diagnostics["least_squares_solves"]
        until = deadline(None if options.max_seconds is None else options.max_seconds - self.condense_seconds)
        f, info, seconds = self._solve_points(options, until)
        f, u_vec, consistency = self._recover(f, info, options, seconds, until)
        self.f = f = select(self.traces, f, self.reduced.evaluate(f))
        u, lam_tau = self._grid_functions(u_vec, f)
        self._diagnose(info, seconds, consistency, self.reduced.diagnostics["least_squares_solves"] - least_squares)
        info["timings"]["total"] = self.condense_seconds + time.perf_counter() - start
        self.condense_seconds = 0.0  # a resumed run does not condense again
        return u, lam_tau, info

    def _solve_points(self, options, until):
        """Step 1: the semismooth Newton iteration on the points from the current f; (f, info, seconds)."""
        start = time.perf_counter()
        f, info = semismooth.solve(self.reduced, self.f, options.solver_tol, options.maxit, options.progress,
                                   options.energy_tol, until)
        return f, info, dict(newton=time.perf_counter() - start)

    def _recover(self, f, info, options, seconds, until):
        """Step 2: u = A^-1 (F - B^T f), then ``_make_consistent``; returns (f, u as an array, re-solves)."""
        start = time.perf_counter()
        u_vec = self.condensation.displacement(f)
        seconds["recover"] = time.perf_counter() - start
        return self._make_consistent(f, u_vec, info, options, seconds, until)

    def _grid_functions(self, u_vec, f):
        """Step 3: u and lam_tau = f_t / beta (``multiplier``) as
        GridFunctions on ``disc.V``, ``contact.Q``."""
        u, lam_tau = starting_point(self.contact)
        u.vec.FV().NumPy()[:] = u_vec
        self.pair_multiplier = self.contact.set_multiplier(lam_tau, self.reduced.multiplier(f))
        return u, lam_tau

    def _diagnose(self, info, seconds, consistency, least_squares):
        """Step 4: the solve's diagnostics into ``info`` (see ``newton``); a
        ``SolverWarning`` if ``least_squares`` Newton systems of this run were singular."""
        info.update(pair_forces=pair_forces(self.traces, self.f), pair_multiplier=self.pair_multiplier)
        info.update(contact_points=self.traces.M, linear_solver=self.condensation.linear_solver, factorizations=1,
                    refinements=self.condensation.refinements, consistency_steps=consistency,
                    least_squares_solves=least_squares, clamped_points=self.reduced.diagnostics["clamped_points"],
                    state=None if info["converged"] else self, timings=dict(condense=self.condense_seconds, **seconds))
        if least_squares:
            warn(f"semismooth Newton on the contact points: {least_squares} Newton systems were singular and were "
                 "solved by least squares (each such direction was still checked by the globalisation, and the "
                 "stopping test by the KKT residual; the forces at the points may not be unique)", SolverWarning)

    def _make_consistent(self, f, u_vec, info, options, seconds, until):
        """The traces of the computed u differ from w0 - W f by the solve's round-off amplified by cond(A),
        which a stiff compliance (c_n up to 1e10) turns into a KKT residual: shift w0 so that w(f) are the
        traces of u, re-solve the points and move u with the forces, u -= A^-1 B^T df (Newton steps on
        the whole nonlinear system, whose round-off is relative to the steps), at most ``MAX_CONSISTENCY``
        times, until the deadline ``until``.  ``info`` and ``seconds`` (newton, recover) are updated; returns
        (f, u_vec, re-solves)."""
        reduced, traces = self.reduced, self.traces
        for consistency in range(MAX_CONSISTENCY + 1):
            reduced.shift(traces.apply(u_vec) - reduced.traces(f))
            if consistency == MAX_CONSISTENCY or reduced.done(reduced.evaluate(f), options.solver_tol,
                                                              options.energy_tol):
                break
            start_newton = time.perf_counter()
            f_new, more = semismooth.solve(reduced, f, options.solver_tol, options.maxit,
                                           energy_tol=options.energy_tol, deadline=until)
            for key in ("iterations", "history", "steps"):
                info[key] += more[key]
            info.update(linearization=more["linearization"], converged=more["converged"])
            start_recover = time.perf_counter()
            seconds["newton"] += start_recover - start_newton
            u_vec = u_vec + self.condensation.correction(f_new - f)
            f = f_new
            seconds["recover"] += time.perf_counter() - start_recover
        return f, u_vec, consistency


def newton(disc, contact, options=None, initial=None, problem=None):
    """Solve (3.3)-(3.4) on ``disc`` and its :class:`~ngdgfric.Contact` ``contact`` (module docstring) with
    the ``NewtonOptions`` ``options`` (default: the defaults); returns (u, lam_tau, info).

    initial: None or a pair of GridFunctions (u, lam_tau) on ``disc.V``, ``contact.Q`` (a warm start: the
    forces of the laws at u, with lam_tau).  problem: the problem whose contact law is solved (default
    ``disc.problem``; the fixed point passes its frozen-bound problem, ``ngdgfric.contact.forms.frozen_bound``).
    info: ``iterations``, ``history`` (relative KKT residual after each iteration), ``steps``,
    ``initial_residual``, ``residual``, ``linearization`` (eta_lin at the end), ``converged`` (solver_tol
    met), ``state`` (None when converged), ``contact_points`` (M), ``penetrating``, ``stick`` (points at
    the end), ``linear_solver``, ``refinements``, ``least_squares_solves`` (singular Newton systems, solved by
    least squares: a ``SolverWarning``), ``clamped_points`` (diagonal entries of W raised
    to a floor, ``ReducedContact``), ``timings`` (condense, newton, recover,
    total s).
    Raises :class:`ngdgfric.SolverError` if neither test is met within ``options.maxit``.
    """
    options = NewtonOptions() if options is None else options
    traces = contact.traces if problem is None else ContactTraces(contact, problem)
    fallback = None
    floating = FloatingSolve.of(disc) if disc.problem.pairs else None
    A = None if floating is None else floating.A
    if _full_space(disc, traces, options):
        try:
            with FullSpaceState(disc, contact, traces, A) as state:
                return _run(state, floating, options, initial)
        except TimeLimitError:
            raise
        except SolverError as error:  # "auto" only: the condensed solver, where W fits, takes over
            if options.formulation == "full-space" or 32.0 * traces.M**2 > FALLBACK_BYTES:
                raise
            fallback = f"the full space failed ({error}); solved condensed"
    u, lam_tau, info = _run(NewtonState(disc, contact, traces, options.linear_solver, A=A), floating, options, initial)
    if fallback is not None:
        info["fallback"] = fallback
    return u, lam_tau, info


def _run(state, floating, options, initial):
    """(u, lam_tau, info) of a ``NewtonState`` or a ``FullSpaceState`` (:mod:`ngdgfric.solvers.fullspace`) from
    ``initial``: one run, or the proximal steps of the ``FloatingSolve`` ``floating`` around it."""
    if initial is not None:
        state.start_from(*initial)
    if floating is None:
        return state.run(options)
    u_start = np.zeros(state.disc.V.ndof) if initial is None else initial[0].vec.FV().NumPy().copy()
    return floating.run(state, options, u_start)


def _full_space(disc, traces, options):
    """Whether ``newton`` takes the full-space iteration (``options.formulation``); ValueError for "full-space"
    where it does not apply."""
    if options.formulation == "condensed":
        return False
    reasons = [reason for reason, missing in (
        ("B_h is not symmetric (NIPG)" if applicable(True, traces) else "it needs a symmetric B_h and m_t = 0",
         not applicable(disc.symmetric, traces)),
        ("energy_tol needs the resumable condensed solve", options.energy_tol is not None),
        ("it needs MKL PARDISO (pip install mkl)", not pardiso.available() or options.linear_solver == "ngsolve"))
        if missing]
    if options.formulation == "full-space":
        if reasons:
            raise ValueError(f"formulation='full-space' does not apply here: {'; '.join(reasons)}")
        return True
    return not reasons and traces.M >= FULL_SPACE_POINTS
