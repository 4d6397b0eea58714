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

    def scaled_blocks(self):
        """The contact-block entries J_ij / sqrt(A_ii A_jj) of the last :meth:`jacobian`."""
        return self.sum.scaled_blocks()


class ReusedFactorization:
    """Solves J x = b for a sequence of Jacobians J that differ only in the contact blocks.

    The factorisation of the last factorised J_0 is kept.  If the new J has the same ``state``
    (same sets), it is J_0 and one back-substitution solves.  Otherwise J - J_0 lives in the
    contact blocks; if it is small there, max |J - J_0|_ij / sqrt(A_ii A_jj) <= ``reuse_tol``
    (typical: the penetrating set changed and c_n is soft against the elastic stiffness
    (2 mu + lam) / h), GMRES preconditioned by J_0 solves in a few steps (tolerance
    ``krylov_tol``, at most ``krylov_steps``) and J_0 is kept.  Else, or if GMRES needs more
    steps, J is factorised: Cholesky if ``symmetric`` (positive definite), else UMFPACK.
    ``reuse_tol = 0`` factorises every new J.
    """

    def __init__(self, symmetric, reuse_tol=1e-2, krylov_steps=10, krylov_tol=1e-10):
        self.symmetric = symmetric
        self.reuse_tol, self.krylov_steps, self.krylov_tol = reuse_tol, krylov_steps, krylov_tol
        self._inverse = self._state = self._blocks = None
        self.counts = dict(factorizations=0, solves=0, krylov=0)
        self.times = dict(factor=0.0, solve=0.0, jacobian=0.0)  # seconds spent in each part

    def forget(self):
        """Factorise at the next solve even if the state is unchanged."""
        self._state = None

    def factorize(self, J, state, blocks):
        start = time.perf_counter()
        self._inverse = None  # free the old factor first: reusing its memory is much faster
        with threads(J.height):
            self._inverse = direct_inverse(J, self.symmetric)
        self.times["factor"] += time.perf_counter() - start
        self._state, self._blocks = state, blocks
        self.counts["factorizations"] += 1

    def solve(self, op, state, b, x):
        """x = J^-1 b with J = ``op.jacobian()`` (assembled only if needed); ``state`` identifies J."""
        if self._inverse is None or self._state is None or not np.array_equal(state, self._state):
            start = time.perf_counter()
            J = op.jacobian()
            blocks = op.scaled_blocks()
            self.times["jacobian"] += time.perf_counter() - start
            if self._state is not None and np.max(np.abs(blocks - self._blocks), initial=0.0) <= self.reuse_tol:
                start = time.perf_counter()
                x[:] = 0.0
                with threads(J.height):
                    solver = ngs.krylovspace.GMResSolver(J, self._inverse, maxiter=self.krylov_steps,
                                                         tol=self.krylov_tol, printrates=False)
                    solver.Solve(rhs=b, sol=x)
                self.counts["krylov"] += solver.iterations
                self.counts["solves"] += solver.iterations
                self.times["solve"] += time.perf_counter() - start
                if solver.iterations < self.krylov_steps:
                    return
            self.factorize(J, state, blocks)
        start = time.perf_counter()
        with threads(len(b)):
            x.data = self._inverse * b
        self.counts["solves"] += 1
        self.times["solve"] += time.perf_counter() - start


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
