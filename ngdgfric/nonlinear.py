"""The contact operator shared by the Uzawa and Newton solvers, and factorisation reuse.

Both solvers work with an operator of the form

    F(u)(v) = B_h(u, v) + j_n(u, v) + int_{Gamma_C} psi(u) v_tau ds - (f, v)

(Gauss rule), where the friction force density psi is chosen by the solver: psi = c_tau l
(Uzawa's inner problem for a given multiplier l), or the stick/slip forces of a semismooth
Newton step (:mod:`ngdgfric.newton`), which for m_t > 0 contain the state-dependent bound
c_tau (u_n - g_a)_+^{m_t}.  The Jacobian of F is A + K(u), with K nonzero only in the blocks of
the contact elements.
"""

import time

import ngsolve as ngs
import numpy as np

from .contact import evaluate_on_contact, normal_tangent, penetration
from .linalg import BlockSum, direct_inverse, threads
from .lowrank import LowRankUpdate

__all__ = ["ContactOperator", "ReusedFactorization", "multiplier_update", "newton_step", "relative_change"]


class ContactOperator:
    """F(u) and its Jacobian for the GridFunction ``u`` and a friction force density ``psi(u)``.

    ``psi``: callable mapping the displacement (a trial function) to the tangential friction force
    density, affine in it; ``switches``: callable returning the boolean array of the solver's
    frozen decisions at the Gauss points (or None), which together with the penetrating set and
    ``coefficients`` (CoefficientFunctions whose values there enter the Jacobian) determine the
    Jacobian (used to detect an unchanged matrix).
    """

    def __init__(self, disc, u, psi, switches=None, coefficients=()):
        self.disc = disc
        self.u = u
        self.linear_compliance = disc.problem.m_n == 1
        _, t = normal_tangent()
        trial, test = disc.V.TnT()
        self.form = ngs.BilinearForm(disc.V)
        self.form += disc.compliance_form(trial, test)
        self.form += psi(trial) * (test * t) * disc.dS
        self.sum = BlockSum(disc.A, disc.contact_groups())
        self.points = disc.contact_points()
        self._gap = penetration(disc.problem, u)
        self._switches, self._coefficients = switches, list(coefficients)
        self._out = disc.F.CreateVector()

    def residual(self, vec=None):
        """F(u) as a vector (for the GridFunction ``u`` of the constructor, or ``vec``)."""
        vec = self.u.vec if vec is None else vec
        r = self._out
        with threads(len(vec)):
            self.form.Apply(vec, r)
            r.data += self.disc.A * vec - self.disc.F
        return r

    def sets(self):
        """The penetrating Gauss points and the switches (boolean array)."""
        gap = evaluate_on_contact(self._gap, self.points)
        return np.concatenate([gap > 0] + ([] if self._switches is None else [self._switches()]))

    def state(self):
        """What the Jacobian at u depends on: :meth:`sets`, the coefficients, and for m_n > 1 the penetrations."""
        values = [evaluate_on_contact(cf, self.points) for cf in self._coefficients]
        if not self.linear_compliance:
            gap = evaluate_on_contact(self._gap, self.points)
            values.append(gap * (gap > 0))
        return np.concatenate([self.sets()] + values)

    def jacobian(self):
        """A + K(u) as a sparse matrix (updated in place; valid until the next call)."""
        with threads(self.disc.V.ndof):
            self.form.AssembleLinearization(self.u.vec)
        return self.sum.update(self.form.mat)


class ReusedFactorization:
    """Solves J x = b for a sequence of Jacobians J that differ only in the contact blocks.

    The factorisation of the last factorised J_0 is kept (Cholesky if ``symmetric``, i.e.
    symmetric positive definite, else UMFPACK).  If the new J has the same ``state`` (same sets),
    it is J_0 and one back-substitution solves.  Otherwise, with ``low_rank``, J - J_0 is
    applied as a low-rank correction (:class:`ngdgfric.lowrank.LowRankUpdate`, singular values
    above ``tol`` in the diagonal scaling, the rest removed by at most ``refinement_steps`` steps
    of iterative refinement to the relative residual ``refinement_tol``) whenever its new columns
    cost fewer back-substitutions than one factorisation takes (both times measured as we go);
    else, or if the refinement stalls, J is factorised.
    """

    def __init__(self, symmetric, low_rank=True, tol=1e-2, refinement_steps=10, refinement_tol=1e-10,
                 max_memory=1e9):
        self.symmetric, self.low_rank, self.tol = symmetric, low_rank, tol
        self.refinement_steps, self.refinement_tol, self.max_memory = refinement_steps, refinement_tol, max_memory
        self._inverse = self._update = self._state = self._current = None
        self._seconds = dict(factor=np.inf, backsub=0.0)
        self.counts = dict(factorizations=0, solves=0, columns=0, refinements=0)
        self.times = dict(factor=0.0, solve=0.0, jacobian=0.0, low_rank=0.0)  # seconds spent in each part

    def forget(self):
        """Factorise at the next solve even if the state is unchanged."""
        self._state = self._current = None

    def factorize(self, op, J, state, blocks):
        start = time.perf_counter()
        self._inverse = self._update = None  # free the old factor first: reusing its memory is much faster
        with threads(J.height):
            self._inverse = direct_inverse(J, self.symmetric)
        self._update = LowRankUpdate(self._inverse, op.sum.dofs, op.sum.root_diagonal, blocks, op.disc.F, self.tol)
        self._seconds["factor"] = time.perf_counter() - start
        self.times["factor"] += self._seconds["factor"]
        self._state = self._current = state
        self.counts["factorizations"] += 1

    def solve(self, op, state, b, x):
        """x = J^-1 b with J = ``op.jacobian()`` (assembled only if needed); ``state`` identifies J."""
        if self._current is None or not np.array_equal(state, self._current):
            start = time.perf_counter()
            J = op.jacobian()
            blocks = op.sum.scaled_blocks()
            self.times["jacobian"] += time.perf_counter() - start
            if not self._use_update(blocks, len(b)):
                self.factorize(op, J, state, blocks)
            self._current = state
        if not self._solve(op.sum.J, b, x):
            self.factorize(op, op.sum.J, self._current, op.sum.scaled_blocks())
            self._solve(op.sum.J, b, x)

    def _use_update(self, blocks, n):
        """Prepare the low-rank correction for J if that is cheaper than factorising it."""
        if not self.low_rank or self._state is None:
            return False
        start = time.perf_counter()
        new = self._update.columns_needed(blocks)
        affordable = (new * self._seconds["backsub"] < self._seconds["factor"]
                      and (self._update.rank + new) * n * 8 <= self.max_memory)
        if affordable:
            self._update.prepare(blocks)
            self.counts["columns"] += new
            self.counts["solves"] += new
        self.times["low_rank"] += time.perf_counter() - start
        return affordable

    def _solve(self, J, b, x):
        """Solve by the (corrected) factorisation, refined with J; False if the refinement stalls."""
        start = time.perf_counter()
        self._update.apply(b, x)
        self._seconds["backsub"] = time.perf_counter() - start
        self.counts["solves"] += 1
        converged = np.array_equal(self._current, self._state)
        if not converged:
            r, dx = b.CreateVector(), b.CreateVector()
            size = np.linalg.norm(b.FV().NumPy())
            for _ in range(self.refinement_steps):
                with threads(len(b)):
                    r.data = b - J * x
                if np.linalg.norm(r.FV().NumPy()) <= self.refinement_tol * size:
                    converged = True
                    break
                self._update.apply(r, dx)
                x.data += dx
                self.counts["solves"] += 1
                self.counts["refinements"] += 1
        self.times["solve"] += time.perf_counter() - start
        return converged


def multiplier_update(disc, lam, value):
    """A callable performing lam <- ``value`` (a CoefficientFunction) at the Gauss points, in place.

    The Gauss-rule L2 projection onto the degree-p multiplier space is interpolation at the
    Gauss points, so the new lam equals ``value`` there exactly.
    """
    form = ngs.LinearForm(disc.Q)
    form += value * disc.Q.TestFunction() * disc.dS

    def update():
        with threads(disc.V.ndof):
            form.Assemble()
        lam.vec.data = disc.M_inv * form.vec

    return update


def newton_step(op, linear_solver, du):
    """du = J(u)^-1 F_l(u) for the operator's u; returns (state of J, ||F_l(u)||_2)."""
    r = op.residual()
    state = op.state()
    norm = float(np.linalg.norm(r.FV().NumPy()))
    linear_solver.solve(op, state, r, du)
    return state, norm


def relative_change(du, u):
    """||du||_inf / ||u||_inf of two coefficient vectors (||du||_inf if u = 0)."""
    size = np.max(np.abs(du.FV().NumPy()), initial=0.0)
    scale = np.max(np.abs(u.FV().NumPy()), initial=0.0)
    return size / scale if scale > 0 else size
