r"""The contact operator on the full sparse system, with factorisation reuse (Uzawa's inner problem).

Uzawa's inner problem (:mod:`ngdgfric.solvers.uzawa`) is the equation

.. math::

    F(u)(v) = B_h(u, v) + j_n(u, v) + \int_{\Gamma_C} c_\tau \lambda_\tau v_\tau \, ds - (f, v) = 0

(Gauss rule) for a fixed multiplier :math:`\lambda_\tau`, solved by Newton's method on the compliance term.  The
Jacobian of :math:`F` is :math:`A + K_n(u)`, with :math:`K_n` nonzero only in the blocks of the contact elements
(``BlockSum`` of :mod:`ngdgfric.sparse`); it changes only when the set of penetrating Gauss points (or, for
:math:`m_n > 1`, the penetrations) change, and the last factorisation is reused until then.  This path works on
the whole sparse system with NGSolve's factorisations, independently of the condensation used by the default
solver (:mod:`ngdgfric.solvers.newton`).
"""

import time

import ngsolve as ngs
import numpy as np

from ..contact.boundary import evaluate_on_contact
from ..contact.forms import compliance_form, friction_force, penetration
from ..problem import exponents
from ..sparse import BlockSum, direct_inverse
from ..threads import threads

__all__ = ["ContactOperator", "ReusedFactorization", "multiplier_update", "newton_step", "relative_change"]


class ContactOperator:
    """F(u) and its Jacobian for the GridFunction ``u`` with the friction term g(lam_tau, v) of a fixed multiplier:
    B_h(u, v) + j_n(u, v) + g(lam_tau, v) - (f, v), the friction bound ``bound`` independent of u (Uzawa: c_tau).
    """

    def __init__(self, disc, contact, u, bound, lam_tau):
        self.disc = disc
        self.u = u
        self.linear_compliance = all(m == 1 for m in exponents(disc.problem.m_n))
        trial, test = disc.V.TnT()
        self.form = ngs.BilinearForm(disc.V)
        self.form += compliance_form(disc.problem, contact.dS, trial, test)
        self.form += friction_force(bound, lam_tau, test, contact.dS)
        self.sum = BlockSum(disc.A, contact.groups())
        self.points = contact.points()
        self._gap = penetration(disc.problem, u)
        self._out = disc.F.CreateVector()

    def residual(self, vec=None):
        """F(u) as a vector (for the GridFunction ``u`` of the constructor, or ``vec``)."""
        vec = self.u.vec if vec is None else vec
        r = self._out
        with threads(len(vec)):
            self.form.Apply(vec, r)
            r.data += self.disc.A * vec - self.disc.F
        return r

    def state(self):
        """What the Jacobian at u depends on: the penetrating Gauss points (and for m_n > 1 the penetrations)."""
        gap = evaluate_on_contact(self._gap, self.points)
        return gap > 0 if self.linear_compliance else np.concatenate([gap > 0, gap * (gap > 0)])

    def jacobian(self):
        """A + K(u) as a sparse matrix (updated in place; valid until the next call)."""
        with threads(self.disc.V.ndof):
            self.form.AssembleLinearization(self.u.vec)
        return self.sum.update(self.form.mat)


class ReusedFactorization:
    """Solves J x = b for a sequence of Jacobians J identified by a ``state``: the last factorisation
    (Cholesky if ``symmetric``, i.e. symmetric positive definite, else UMFPACK) is reused while the
    state does not change.  ``jacobian``: a callable returning the current J as a sparse matrix
    (assembled only when the state changed, e.g. :meth:`ContactOperator.jacobian`).

    Attributes: ``counts`` (factorizations, solves) and ``times`` (seconds in factor, solve, jacobian)."""

    def __init__(self, jacobian, symmetric):
        self.jacobian, self.symmetric = jacobian, symmetric
        self._inverse = self._state = None
        self.counts = dict(factorizations=0, solves=0)
        self.times = dict(factor=0.0, solve=0.0, jacobian=0.0)  # seconds spent in each part

    def solve(self, state, b, x):
        """x = J^-1 b with J the Jacobian of ``state`` (assembled and factorised only if ``state`` changed)."""
        if self._state is None or not np.array_equal(state, self._state):
            start = time.perf_counter()
            J = self.jacobian()
            self.times["jacobian"] += time.perf_counter() - start
            start = time.perf_counter()
            self._inverse = None  # free the old factor first: reusing its memory is much faster
            with threads(J.height):
                self._inverse = direct_inverse(J, self.symmetric)
            self.times["factor"] += time.perf_counter() - start
            self._state = state
            self.counts["factorizations"] += 1
        start = time.perf_counter()
        with threads(len(b)):
            x.data = self._inverse * b
        self.times["solve"] += time.perf_counter() - start
        self.counts["solves"] += 1


def multiplier_update(contact, lam_tau, value):
    """A callable performing lam_tau <- ``value`` (a CoefficientFunction) at the Gauss points, in place.

    The Gauss-rule L2 projection onto the degree-p multiplier space is interpolation at the
    Gauss points, so the new lam_tau equals ``value`` there exactly.
    """
    form = ngs.LinearForm(contact.Q)
    form += value * contact.Q.TestFunction() * contact.dS

    def update():
        with threads(contact.V.ndof):
            form.Assemble()
        lam_tau.vec.data = contact.M_inv * form.vec

    return update


def newton_step(op, linear_solver, du):
    """du = J(u)^-1 F(u) for the operator's u, with the :class:`ReusedFactorization` ``linear_solver`` of
    ``op.jacobian``; returns the state of J."""
    r = op.residual()
    state = op.state()
    linear_solver.solve(state, r, du)
    return state


def relative_change(du, u):
    """||du||_inf / ||u||_inf of two coefficient vectors (||du||_inf if u = 0)."""
    size = np.max(np.abs(du.FV().NumPy()), initial=0.0)
    scale = np.max(np.abs(u.FV().NumPy()), initial=0.0)
    return size / scale if scale > 0 else size
