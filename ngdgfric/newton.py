"""The default contact solver: condense onto Gamma_C, semismooth Newton on the points, recover u.

The nonlinearity of (3.3)-(3.4) lives at the M Gauss points of Gamma_C.  The solver

1. builds the traces B at those points (:class:`ngdgfric.traces.ContactTraces`) and condenses
   the linear part onto them: W = B A^-1 B^T and w0 = B A^-1 F, by one partial factorisation
   (:class:`ngdgfric.condensation.Condensation`);
2. solves the contact laws at the points for the forces f with a globalised semismooth Newton
   method on the dense 2M x 2M problem (:class:`ngdgfric.reduced.ReducedContact`,
   :func:`ngdgfric.semismooth.solve`: energy descent for the symmetric methods with m_t = 0, inside a
   proximal point method where W is singular (redundant points on hp meshes), a merit function with
   Levenberg-Marquardt safeguards for NIPG and m_t > 0; stopping test on the KKT residual of Lemma 3.1);
3. recovers u = A^-1 (F - B^T f) by one substitution, and the multiplier l = f_t / beta
   (beta = c_tau (u_n - g_a)_+^{m_t} omega; l = sign(u_tau) where beta = 0).  The traces of the
   computed u differ from w0 - W f by the solve's round-off times cond(A), which a stiff compliance
   (c_n = 1e10: N' = omega c_n ~ 1e8) turns into a visible KKT residual; then w0 is shifted by that
   difference, the points are re-solved (one Newton step) and u moved with the forces,
   u -= A^-1 B^T df (iterative refinement of the nonlinear system: the round-off of that
   substitution is relative to the small df), at most ``MAX_CONSISTENCY`` times, so that the laws
   hold at the traces of the returned u.

Each Newton step costs a dense solve with one row per penetrating or sticking point
(milliseconds on small meshes, 0.4 s with 3500 rows), so on large hp meshes the iteration count
matters; the whole solve costs about one sparse factorisation (results/solver_benchmark.md).

**Inexact solves** (``energy_tol``, used by the adaptive loop): the iteration also stops once the
linearisation estimate eta_lin = (sum_q W_qq G_q^2)^(1/2), the KKT residual of the laws measured in
the energy units of |||.|||_h (:meth:`ngdgfric.reduced.ReducedContact.linearization`), is at most
``energy_tol``.  The returned ``state`` (:class:`NewtonState`: the factorisation, the condensed
problem and the forces) continues such a solve to the full tolerance without factorising again
(:func:`ngdgfric.solution.finish`).
"""

import time

import ngsolve as ngs

from . import semismooth
from .condensation import LINEAR_SOLVERS, Condensation
from .options import callback, choice, positive_integer, positive_number, validate
from .reduced import ReducedContact
from .traces import ContactTraces

__all__ = ["newton", "NewtonState", "OPTIONS"]

MAX_CONSISTENCY = 3  # re-solves after a recovery whose traces violate the laws (stiff compliance)
OPTIONS = dict(tol=positive_number, maxit=positive_integer, progress=callback, linear_solver=choice(*LINEAR_SOLVERS),
               energy_tol=positive_number)


class NewtonState:
    """One discretisation's condensed problem (:class:`~ngdgfric.condensation.Condensation`, one
    factorisation) and :class:`~ngdgfric.reduced.ReducedContact`, with the current forces f."""

    def __init__(self, disc, linear_solver="auto", problem=None):
        start = time.perf_counter()
        self.disc = disc
        self.traces = traces = disc.traces if problem is None else ContactTraces(disc, problem)
        self.condensation = Condensation(disc.A, disc.F, traces, disc.symmetric, linear_solver)
        self.reduced = ReducedContact(self.condensation.W, self.condensation.w0, traces.omega, traces.g_a,
                                      traces.c_n, traces.c_tau, traces.m_n, traces.m_t, disc.symmetric,
                                      traces.redundant)
        self.f = None
        self.condense_seconds = time.perf_counter() - start

    def start_from(self, initial):
        """f from (u, lam) GridFunctions on ``disc.V``, ``disc.Q``: the forces of the laws at u, with l."""
        w = self.traces.apply(initial[0].vec.FV().NumPy())
        self.f = self.reduced.forces(w, self.disc.gauss.values(initial[1]).ravel())

    def run(self, tol=1e-13, maxit=100, progress=None, energy_tol=None):
        """Newton from the current f (zero if none) to ``tol`` (or ``energy_tol``), recover u; (u, lam, info)."""
        start = time.perf_counter()
        reduced, condensation, traces = self.reduced, self.condensation, self.traces
        f, info = semismooth.solve(reduced, self.f, tol, maxit, progress, energy_tol)
        newton_seconds = time.perf_counter() - start
        start_recover = time.perf_counter()
        u_vec = condensation.displacement(f)
        recover_seconds = time.perf_counter() - start_recover
        for consistency in range(MAX_CONSISTENCY + 1):
            # the traces of the computed u differ from w0 - W f by the solve's round-off amplified by
            # cond(A), which a stiff compliance (c_n up to 1e10) turns into a KKT residual: shift w0 so that
            # w(f) are the traces of u, re-solve the points and move u with the forces, u -= A^-1 B^T df
            # (Newton steps on the whole nonlinear system, whose round-off is relative to the steps)
            reduced.shift(traces.apply(u_vec) - reduced.traces(f))
            if consistency == MAX_CONSISTENCY or reduced.done(reduced.evaluate(f), tol, energy_tol):
                break
            start_newton = time.perf_counter()
            f_new, more = semismooth.solve(reduced, f, tol, maxit, energy_tol=energy_tol)
            for key in ("iterations", "history", "steps"):
                info[key] += more[key]
            info.update(linearization=more["linearization"], converged=more["converged"])
            start_recover = time.perf_counter()
            newton_seconds += start_recover - start_newton
            u_vec = u_vec + condensation.correction(f_new - f)
            f = f_new
            recover_seconds += time.perf_counter() - start_recover
        self.f = f
        disc = self.disc
        u, lam = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
        u.vec.FV().NumPy()[:] = u_vec
        disc.gauss.set_values(lam, reduced.multiplier(f).reshape(-1, disc.gauss.q))
        info.update(contact_points=traces.M, linear_solver=condensation.linear_solver, factorizations=1,
                    refinements=condensation.refinements, consistency_steps=consistency,
                    state=None if info["converged"] else self,
                    timings=dict(condense=self.condense_seconds, newton=newton_seconds, recover=recover_seconds,
                                 total=self.condense_seconds + time.perf_counter() - start))
        self.condense_seconds = 0.0  # a resumed run does not condense again
        return u, lam, info


def newton(disc, tol=1e-13, maxit=100, initial=None, progress=None, linear_solver="auto", energy_tol=None,
           problem=None):
    """Solve (3.3)-(3.4) on ``disc`` (module docstring); returns (u, lam, info).

    tol: relative KKT residual max_q W_qq |G_q| / max_q |w_q| at the contact points (:mod:`ngdgfric.reduced`;
    round-off sets its floor).  maxit: Newton iterations.  initial: optional (u, lam) GridFunctions
    on ``disc.V``, ``disc.Q`` (a warm start: the forces of the laws at u, with l).
    progress: None, or callable(message) called after each iteration with a line such as
    "newton 3: KKT residual 1.2e-09".
    linear_solver: "auto" (MKL PARDISO if installed, else NGSolve), "pardiso" or "ngsolve"
    (:class:`ngdgfric.condensation.Condensation`).
    energy_tol: also stop once the linearisation estimate eta_lin <= energy_tol (module docstring);
    then ``info["state"]`` can continue the solve (:class:`NewtonState`).
    info: ``iterations``, ``history`` (relative KKT residual after each iteration), ``steps``,
    ``initial_residual``, ``residual``, ``linearization`` (eta_lin at the end), ``converged`` (tol met),
    ``state`` (None when converged), ``contact_points`` (M), ``penetrating``, ``stick`` (points at
    the end), ``linear_solver``, ``refinements``, ``timings`` (condense, newton, recover, total s).
    Raises :class:`ngdgfric.SolverError` if neither test is met within ``maxit``.
    """
    validate(OPTIONS, "newton", tol=tol, maxit=maxit, progress=progress, linear_solver=linear_solver,
             energy_tol=energy_tol)
    state = NewtonState(disc, linear_solver, problem)
    if initial is not None:
        state.start_from(initial)
    return state.run(tol, maxit, progress, energy_tol)
