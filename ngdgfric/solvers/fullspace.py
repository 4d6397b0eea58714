r"""The contact solver for many contact points: semismooth Newton on the whole system, no Delassus operator.

The condensed solver (:mod:`ngdgfric.solvers.newton`) forms the dense :math:`2M \times 2M` Delassus operator
:math:`W = B A^{-1} B^T` and solves dense Newton systems with one row per active point: memory :math:`32 M^2`
bytes and time of order :math:`M^3`, so a long contact side at high order (:math:`M = 10{,}000` points: 3.2 GB for
:math:`W` alone) is out of its reach.  Here the unknowns are :math:`u` and the contact forces :math:`f` together,
(3.3)-(3.4) written as

.. math::

    A u + B^T f = F, \qquad G(B u, f) = 0

(the laws at the points, :mod:`ngdgfric.solvers.reduced`), and each Newton step solves the sparse saddle-point
system

.. math::

    \begin{pmatrix} A & B_a^T \\ B_a & -C \end{pmatrix}
    \begin{pmatrix} \delta u \\ \delta f_a \end{pmatrix}
    = \begin{pmatrix} -(A u + B^T f - F) + B_i^T G_i \\ b_a \end{pmatrix},

where the rows of the *active* points are kept (a penetrating point's normal row with :math:`C = 1 / N'(w_n)`, a
sticking point's tangential row with :math:`C = 0`, up to ``STICK_REGULARIZATION``) and those of the others are
eliminated (:math:`\delta f_i = -G_i`: no force without penetration, :math:`f_t = \pm\beta` when slipping), their
rows of :math:`B` set to zero in the same pattern.  The pattern never changes: PARDISO analyses it once
(``Factorization`` of :mod:`ngdgfric.solvers.pardiso`).  The active set changes in every row on the first step
from zero and by 1-20 rows per step after that (the ends of the contact and stick zones, where PDAS moves one
point at a time), so a step factorises again only after a large change; otherwise it corrects the last
factorisation for the changed rows by the Sherman-Morrison-Woodbury formula (``FullSpace._solve``: two solves per
changed row, once), which costs a fraction of a factorisation (a factorisation took 5 solves at 105,042 unknowns,
4.8 at 410,082).  While the active set stays, a step is iterative refinement of the nonlinear system.  With the
linear compliance law (:math:`m_n = 1`) and :math:`m_t = 0` the laws are piecewise linear and the iteration is the
primal-dual active set method (Hintermueller, Ito & Kunisch, SIAM J. Optim. 13, 2003): it ends one step after the
active set is right.

Scope: a symmetric :math:`B_h` (every method but NIPG) and the reduced friction law :math:`m_t = 0`, with
:math:`m_n \ge 1`; anything else goes to the condensed solver.  :math:`r_q = \mathrm{R\_FACTOR} / d_q` in the
stick/slip decision (any :math:`r > 0` gives the same solutions) with :math:`d_q = \sum_j B_{qj}^2 / A_{jj}`, the
Jacobi approximation of :math:`W_{qq}`, and :math:`r` divided by 10 whenever an active set comes back (a cycle);
the stopping test is the condensed solver's with :math:`d_q` in place of :math:`W_{qq}` (``kkt_residual``) and
the margin ``JACOBI_MARGIN``.  There is no globalisation: if the iteration has not converged within ``maxit``
steps, or its active set has settled and refinement stalls above ``solver_tol``, a :class:`~ngdgfric.SolverError`
says so (then ``formulation="auto"`` hands the problem to the condensed solver).  The solutions agree with the
condensed solver's to :math:`10^{-12}` on the examples, all symmetric methods, hp levels with redundant points,
stiff and nonlinear compliance (``tests/test_fullspace.py``).  The cross-over with the condensed solver,
``FULL_SPACE_POINTS``, and the costs: the results page *Many contact points: contact solve against linear solve
on a long contact side*.
"""

import time

import numpy as np

from ..contact.laws import law_forces
from ..errors import SolverError, check_deadline, deadline
from ..threads import threads
from ..transfer import starting_point
from .condensation import augmented_matrix
from .pardiso import Factorization
from .reduced import multiplier_of, pair_forces, point_state, trace_scale
from .selection import select

__all__ = ["FullSpace", "FullSpaceState", "applicable", "kkt_residual", "FULL_SPACE_POINTS"]

R_FACTOR = 0.1
"""r_q = R_FACTOR / d_q: the Jacobi diagonal d_q stands in for W_qq, which it underestimates; a factor below 1 keeps
the stick/slip decision from cycling (the decisions page of the docs, full-space Newton)."""
STICK_REGULARIZATION = 1e-8
"""C = STICK_REGULARIZATION d_q on a sticking row instead of 0: the Newton matrix stays nonsingular where the rows of
B of an element are dependent (redundant points: an element with two edges on Gamma_C, or p_T < p on hp meshes),
and as the residual G_t = -r w_t is not regularised, the iteration still drives w_t to 0 (an inexact Newton step
that picks a small step in the kernel, as the condensed solver's 1e-8 on its sticking diagonal)."""
WOODBURY_ROWS, WOODBURY_RANK = 32, 256
"""A Newton step factorises again when more than WOODBURY_ROWS trace rows would need new solves, or the rows changed
since the factorisation pass WOODBURY_RANK (``FullSpace._solve``)."""
JACOBI_MARGIN = 100.0
"""The stopping test is d_q |G_q| <= solver_tol D / JACOBI_MARGIN: d_q underestimates W_qq (see R_FACTOR), and the
margin makes the condensed solver's test W_qq |G_q| <= solver_tol D hold too, so that both solvers return the same
solution to round-off (the decisions page of the docs, full-space Newton)."""
FULL_SPACE_POINTS = 1000
"""The number of contact points M from which ``formulation="auto"`` of :func:`ngdgfric.solvers.newton.newton` takes
this solver (the cross-over measured in results/solver_benchmark.md)."""


def applicable(symmetric, traces):
    """Whether the full-space iteration covers the problem: B_h symmetric, m_t = 0 everywhere, m_n >= 1."""
    return bool(symmetric and np.all(np.asarray(traces.m_t) == 0) and np.all(np.asarray(traces.m_n) >= 1))


def kkt_residual(scale, s, g_a):
    """max_q d_q |G_q| / D of the :class:`~ngdgfric.solvers.reduced.PointState` s: each point's residual force times
    the displacement it causes there (d_q ~ W_qq), relative to the largest trace D
    (:func:`~ngdgfric.solvers.reduced.trace_scale`, as :meth:`ngdgfric.solvers.reduced.ReducedContact.residual`)."""
    return float(np.max(scale * np.abs(s.G), initial=0.0)) / trace_scale(s, g_a)


class FullSpace:
    """The Newton matrices of one discretisation (``A``, ``F``, :class:`~ngdgfric.contact.traces.ContactTraces`
    ``traces``) in one PARDISO pattern, and the iteration of the module docstring (:meth:`run`)."""

    def __init__(self, A, F, traces):
        start = time.perf_counter()
        self.traces, self.n, self.M = traces, A.height, traces.M
        self.A, self._F = A, F.FV().NumPy().copy()
        m = 2 * self.M
        # K = [[A, B^T], [B, 0]], upper triangle, in the condensed solver's CSR (each row of A followed by its entries
        # of B^T, then the trace rows with their diagonal alone); its values change here, its pattern does not
        self.indptr, self.indices, self.values = augmented_matrix(A, traces, symmetric=True)
        rows = np.repeat(np.arange(self.n + m), np.diff(self.indptr))
        self._B_slot = np.flatnonzero((rows < self.n) & (self.indices >= self.n))
        self._B_row, self._B_value = self.indices[self._B_slot] - self.n, self.values[self._B_slot].copy()
        self._C_slot = self.indptr[self.n:-1]
        self.values[self._C_slot] = -1.0
        on_diagonal = (rows == self.indices) & (rows < self.n)
        diagonal_A = np.zeros(self.n)
        diagonal_A[rows[on_diagonal]] = self.values[on_diagonal]
        self.scale = np.bincount(traces.rows, weights=traces.values**2 / diagonal_A[traces.cols], minlength=m)
        self.scale = np.maximum(self.scale, 1e-14 * np.max(self.scale, initial=1.0))  # d_q, the Jacobi W_qq
        self.r = R_FACTOR / self.scale[self.M:]
        self.factorization = Factorization(self.indptr, self.indices, self.values)
        self._active = self._C = None  # the active set and C of the current factorisation
        self._columns = {}  # K^-1 e_j and K^-1 (B_j^T, 0) per trace row j (:meth:`_solve`)
        order = np.argsort(traces.rows, kind="stable")  # B by rows
        self._row_start = np.searchsorted(traces.rows[order], np.arange(m + 1))
        self._row_cols, self._row_values = traces.cols[order], traces.values[order]
        self.setup_seconds = time.perf_counter() - start

    def load(self, F):
        """Take the load vector F (an array) instead of the one given to the constructor."""
        self._F = np.array(F, dtype=float)

    def _A_times(self, u):
        """A u (numpy in and out)."""
        vec = self.A.CreateColVector()
        out = self.A.CreateColVector()
        vec.FV().NumPy()[:] = u
        with threads(len(u)):
            out.data = self.A * vec
        return out.FV().NumPy().copy()

    def laws(self, u, f):
        """(the :class:`~ngdgfric.solvers.reduced.PointState` at (u, f), the active rows, C): the laws at the traces
        B u (:func:`~ngdgfric.solvers.reduced.point_state`) and the Newton matrix's trace block (module docstring)."""
        M, s = self.M, point_state(self.traces, f, self.traces.apply(u), self.r)
        normal_active = s.penetrating & (s.dN > 0)
        active = np.concatenate([normal_active, s.stick])
        C = np.concatenate([np.where(normal_active, 1.0 / np.where(normal_active, s.dN, 1.0), 1.0),
                            np.where(s.stick, STICK_REGULARIZATION * self.scale[M:], 1.0)])
        return s, active, C

    def equilibrium(self, u, f):
        """(A u + B^T f - F, whether its norm is at most 1e-10 (|F| + |B^T f|)): the linear equations' residual."""
        forces = self.traces.apply_transpose(f)
        residual = self._A_times(u) + forces - self._F
        size = np.linalg.norm(self._F) + np.linalg.norm(forces)
        return residual, bool(np.linalg.norm(residual) <= 1e-10 * size)

    def step(self, s, active, C, residual):
        """The Newton step (du, df) of the module docstring from the point state s (:meth:`_solve`)."""
        M = self.M
        rhs_u = -residual + self.traces.apply_transpose(np.where(active, 0.0, s.G))
        normal = np.where(active[:M], s.G[:M] / np.where(active[:M], s.dN, 1.0), s.G[:M])
        tangential = np.where(active[M:], -s.w[M:], s.G[M:])
        x = self._solve(np.concatenate([rhs_u, normal, tangential]), active, C)
        du, df = x[:self.n], x[self.n:]
        return du, np.where(active, df, -s.G)

    def _factor(self, active, C):
        self.values[self._B_slot] = np.where(active[self._B_row], self._B_value, 0.0)
        self.values[self._C_slot] = -C
        self.factorization.factor(self.values)
        self._active, self._C, self._columns = active.copy(), C.copy(), {}

    def _solve(self, b, active, C):
        """K(active, C)^-1 b from the factorisation of an earlier K(active_s, C_s) and the Sherman-Morrison-Woodbury
        formula: the trace rows J where (active, C) differ change K by U Q U^T, U = [e_j (j in J), sigma_j (B_j^T, 0)
        (j in J toggled, sigma_j = +1 switched on, -1 off)], Q = [[diag(C_s - C)_J, I], [I, 0]];
        K_s^-1 e_j and K_s^-1 (B_j^T, 0) are kept per row, so a row costs two solves once.  A new factorisation
        when more than WOODBURY_ROWS rows would need new solves or J passes WOODBURY_RANK rows.  (The active set
        settles after one or two steps and then changes by 1-20 rows per step, at the ends of the contact and stick
        zones: a factorisation costs 5 solves at 105,042 unknowns.)"""
        changed = np.zeros(0, dtype=np.int64) if self._active is None else \
            np.flatnonzero((active != self._active) | (C != self._C))
        missing = [j for j in changed if j not in self._columns]
        if self._active is None or len(missing) > WOODBURY_ROWS or len(changed) > WOODBURY_RANK:
            self._factor(active, C)
            return self.factorization.solve(b)
        if missing:
            block = np.zeros((self.n + 2 * self.M, 2 * len(missing)))
            for k, j in enumerate(missing):
                block[self.n + j, 2 * k] = 1.0
                row = slice(self._row_start[j], self._row_start[j + 1])
                block[self._row_cols[row], 2 * k + 1] = self._row_values[row]
            solved = self.factorization.solve(block)  # Fortran order: its columns are contiguous
            for k, j in enumerate(missing):
                self._columns[j] = (solved[:, 2 * k], solved[:, 2 * k + 1])
        y = self.factorization.solve(b)
        if not changed.size:
            return y
        toggled = changed[active[changed] != self._active[changed]]
        sign = np.where(active[toggled], 1.0, -1.0)
        columns = [self._columns[j][0] for j in changed] + [self._columns[j][1] for j in toggled]
        k, t = len(changed), len(toggled)
        Q = np.zeros((k + t, k + t))  # sigma_j moved from U into Q
        Q[np.arange(k), np.arange(k)] = self._C[changed] - C[changed]
        position = np.searchsorted(changed, toggled)
        Q[position, k + np.arange(t)] = Q[k + np.arange(t), position] = sign

        def transpose_U(v):  # U^T v with the signs in Q
            rows = [self._row_values[self._row_start[j]:self._row_start[j + 1]]
                    @ v[self._row_cols[self._row_start[j]:self._row_start[j + 1]]] for j in toggled]
            return np.concatenate([v[self.n + changed], np.asarray(rows, dtype=float).reshape(t)])

        capacitance = np.eye(k + t) + Q @ np.column_stack([transpose_U(z) for z in columns])
        coefficients = np.linalg.solve(capacitance, Q @ transpose_U(y))
        for c, z in zip(coefficients, columns, strict=True):  # y - Z c without forming Z (n x (k + t))
            y -= c * z
        return y

    def run(self, u, f, solver_tol, maxit, progress=None, max_seconds=None):
        """Newton from (u, f) (numpy arrays); returns (u, f, info) with ``iterations``, ``factorizations``,
        ``history`` (KKT residuals), ``residual``, ``converged``."""
        until = deadline(max_seconds)
        history, stalled, seen, previous = [], 0, {}, None
        for iteration in range(maxit + 1):
            state, active, C = self.laws(u, f)
            balance, balanced = self.equilibrium(u, f)
            residual = kkt_residual(self.scale, state, self.traces.g_a) if balanced else np.inf
            history.append(residual)
            if progress is not None:
                progress(f"full-space newton {iteration}: KKT residual {residual:.3e}, "
                         f"{int(active.sum())} active rows")
            same = previous is not None and np.array_equal(active, previous)
            previous = active
            key = active.tobytes()
            if not same and key in seen:  # the active set cycles: a more cautious stick/slip decision
                self.r *= 0.1
                seen.clear()
            seen[key] = iteration
            if residual <= solver_tol / JACOBI_MARGIN:
                break
            if same and balanced and len(history) > 1 and residual > 0.5 * history[-2]:
                stalled += 1  # the active set is right and refinement no longer helps: round-off
                if stalled >= 2 and residual <= solver_tol:
                    break  # the condensed solver's test without the margin
                if stalled >= 2:
                    raise SolverError(f"full-space semismooth Newton stalled at the KKT residual {residual:.2e} "
                                      f"(solver_tol {solver_tol:.1e}) with its active set settled", solver="newton")
            if iteration == maxit:
                raise SolverError(f"full-space semismooth Newton: no convergence in {maxit} iterations (KKT residual "
                                  f"{residual:.2e}, the last ones {', '.join(f'{h:.1e}' for h in history[-4:])})",
                                  solver="newton")
            check_deadline(until, "newton", history, f"after {iteration} full-space iterations")
            du, df = self.step(state, active, C, balance)
            u, f = u + du, f + df
        return u, f, dict(iterations=iteration, factorizations=self.factorization.factorizations, history=history,
                          residual=history[-1], converged=history[-1] <= solver_tol,
                          penetrating=int(state.penetrating.sum()), stick=int(state.stick.sum()))

    def finish(self, u, f):
        """(f, lam_tau at the points, eta_lin) at (u, f): the forces of :func:`~ngdgfric.solvers.selection.select`,
        the multiplier (:func:`~ngdgfric.solvers.reduced.multiplier_of`) and (sum_q d_q G_q^2)^(1/2)
        (:meth:`ngdgfric.solvers.reduced.ReducedContact.linearization` with the Jacobi d_q in place of W_qq)."""
        s, _, _ = self.laws(u, f)
        selected = select(self.traces, f, s)
        if selected is not f:  # redundant points: the laws at the forces selected
            f, (s, _, _) = selected, self.laws(u, selected)
        return f, multiplier_of(s, self.r), float(np.sqrt(np.sum(self.scale * s.G * s.G)))


class FullSpaceState:
    """One discretisation's :class:`FullSpace` (one PARDISO pattern) with the current (u, f): the full-space twin of
    ``NewtonState`` of :mod:`ngdgfric.solvers.newton` (``start_from``, ``reload``, ``run``), so that the proximal
    steps of :mod:`ngdgfric.solvers.floating` run around either; a context manager that frees PARDISO's memory at
    its end.  ``A``: the matrix of the linear part (default
    ``disc.A``; A + eps M_f for bodies held by contact only)."""

    def __init__(self, disc, contact, traces, A=None):
        start = time.perf_counter()
        self.disc, self.contact, self.traces = disc, contact, traces
        self.solver = FullSpace(disc.A if A is None else A, disc.F, traces)
        self.u, self.f = np.zeros(disc.V.ndof), np.zeros(2 * traces.M)
        self.setup_seconds = time.perf_counter() - start

    def start_from(self, u, lam_tau):
        """(u, f) from GridFunctions u on ``disc.V`` and lam_tau on ``contact.Q``: u, and the forces of the laws at u
        with lam_tau."""
        self.u = u.vec.FV().NumPy().copy()
        self.f = law_forces(self.traces, self.traces.apply(self.u), self.contact.multiplier_values(lam_tau))

    def reload(self, F):
        """Take the load vector F (an array) instead of disc.F; (u, f) kept as the start."""
        self.solver.load(F)

    def run(self, options):
        """Newton from the current (u, f) with the ``NewtonOptions`` ``options``: (u, lam_tau, info) with the keys of
        the condensed solver's info (``linear_solver`` "pardiso (full space)", ``state`` None: an inexact solve is not
        resumed, so ``energy_tol`` is not taken here), and ``factorizations`` and ``factor_bytes`` (PARDISO's peak
        memory)."""
        start, setup = time.perf_counter(), self.setup_seconds
        self.setup_seconds = 0.0  # a later run (a proximal step) does not set up again
        left = None if options.max_seconds is None else max(options.max_seconds - setup, 1e-9)
        self.u, self.f, info = self.solver.run(self.u, self.f, options.solver_tol, options.maxit, options.progress,
                                               left)
        self.f, multiplier, linearization = self.solver.finish(self.u, self.f)
        u, lam_tau = starting_point(self.contact)
        u.vec.FV().NumPy()[:] = self.u
        info.update(pair_multiplier=self.contact.set_multiplier(lam_tau, multiplier),
                    pair_forces=pair_forces(self.traces, self.f), factor_bytes=self.solver.factorization.memory_bytes,
                    initial_residual=info["history"][0], steps=["full space"] * info["iterations"],
                    linearization=linearization, contact_points=self.traces.M, linear_solver="pardiso (full space)",
                    refinements=0, consistency_steps=0, least_squares_solves=0, clamped_points=0, state=None)
        newton = time.perf_counter() - start
        info["timings"] = dict(condense=setup, newton=newton, recover=0.0, total=setup + newton)
        return u, lam_tau, info

    def __enter__(self):
        return self

    def __exit__(self, *exception):
        """Free PARDISO's memory: the state is done with (the solution is returned, or the solve failed)."""
        self.solver.factorization.release()
