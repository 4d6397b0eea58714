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

The contact pairs (:class:`~ngdgfric.ContactPair`) have no form on :math:`\Gamma_C`: their terms are written at
their points with the rows of :math:`B` (``ContactTraces.pair_part`` of :mod:`ngdgfric.contact.traces`),
:math:`B^T f` with the forces :math:`f = (N(B_n u), \omega c_\tau \lambda_\tau)` of the laws
(``law_forces`` of :mod:`ngdgfric.contact.laws`) and the Jacobian :math:`B_n^T \operatorname{diag} N'(B_n u) B_n`
(``PairTerms``), whose blocks couple the two bodies.
"""

import time

import ngsolve as ngs
import numpy as np

from ..contact.boundary import evaluate_on_contact
from ..contact.forms import compliance_form, friction_force, penetration
from ..contact.laws import law_forces, pressure_rate_values
from ..problem import exponents
from ..sparse import BlockSum, direct_inverse
from ..threads import threads

__all__ = ["ContactOperator", "PairTerms", "ReusedFactorization", "multiplier_update", "newton_step",
           "relative_change"]


class PairTerms:
    """The contact pairs' terms of F(u) at their points (module docstring): ``traces`` the pairs' points
    (``ContactTraces.pair_part``), ``lam_tau`` the multiplier there (an array, which Uzawa updates in place)."""

    def __init__(self, traces, lam_tau):
        self.traces, self.lam_tau, self.M = traces, lam_tau, traces.M
        normal = traces.rows < traces.M
        rows, cols, values = traces.rows[normal], traces.cols[normal], traces.values[normal]
        entries = [np.flatnonzero(rows == k) for k in range(traces.M)]  # the entries of B_n's row k
        self.groups = [cols[e] for e in entries]
        first = np.concatenate([np.repeat(e, len(e)) for e in entries] + [np.zeros(0, dtype=np.int64)])
        second = np.concatenate([np.tile(e, len(e)) for e in entries] + [np.zeros(0, dtype=np.int64)])
        # B_n^T D B_n = sum_k D_k b_k b_k^T: the entry pairs (first, second) of each row k
        self._point, self._rows, self._cols = rows[first], cols[first], cols[second]
        self._products = values[first] * values[second]

    def traces_at(self, vec):
        """w = B u at the pairs' points for a coefficient vector (numpy array)."""
        return self.traces.apply(vec)

    def forces(self, vec):
        """The forces f of the laws at u (``vec``) with the multiplier ``lam_tau``: (N(w_n), omega c_tau lam_tau)."""
        return law_forces(self.traces, self.traces_at(vec), self.lam_tau)

    def friction_load(self, lam_tau):
        """B_t^T (omega c_tau lam_tau) for multiplier values ``lam_tau`` at the points, a numpy array on V_h (the
        friction forces' load, without the projection onto [-1, 1])."""
        return self.traces.apply_transpose(np.concatenate([np.zeros(self.M),
                                                           self.traces.omega * self.traces.c_tau * lam_tau]))

    def residual(self, vec):
        """B^T f(u), a numpy array on V_h."""
        return self.traces.apply_transpose(self.forces(vec))

    def _gaps(self, vec):
        return self.traces_at(vec)[:self.M] - self.traces.g_a

    def state(self, vec, linear):
        """What the Jacobian depends on: the penetrating points (and for m_n > 1, ``linear`` False, the gaps)."""
        gap = self._gaps(vec)
        return gap > 0 if linear else np.concatenate([gap > 0, gap * (gap > 0)])

    def jacobian(self, vec):
        """B_n^T diag N'(w_n) B_n as COO triplets (rows, cols, values)."""
        rate = pressure_rate_values(self._gaps(vec), self.traces.omega * self.traces.c_n,
                                    np.broadcast_to(self.traces.m_n, (self.M,)))
        return self._rows, self._cols, rate[self._point] * self._products


class ContactOperator:
    """F(u) and its Jacobian for the GridFunction ``u`` with the friction term g(lam_tau, v) of a fixed multiplier:
    B_h(u, v) + j_n(u, v) + g(lam_tau, v) - (f, v), the friction bound ``bound`` independent of u (Uzawa: c_tau),
    and the contact pairs' terms ``pairs`` (a ``PairTerms``, or None: no pairs).
    """

    def __init__(self, disc, contact, u, bound, lam_tau, pairs=None):
        self.disc = disc
        self.u = u
        self.pairs = pairs
        self.linear_compliance = all(m == 1 for m in exponents(disc.problem.m_n)) and \
            (pairs is None or bool(np.all(np.asarray(pairs.traces.m_n) == 1)))
        trial, test = disc.V.TnT()
        self.form = ngs.BilinearForm(disc.V)
        self.form += compliance_form(disc.problem, contact.dS, trial, test)
        self.form += friction_force(bound, lam_tau, test, contact.dS)
        self.sum = BlockSum(disc.A, contact.groups() + ([] if pairs is None else pairs.groups))
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
        if self.pairs is not None:
            r.FV().NumPy()[:] += self.pairs.residual(vec.FV().NumPy())
        return r

    def state(self):
        """What the Jacobian at u depends on: the penetrating Gauss points (and for m_n > 1 the penetrations)."""
        gap = evaluate_on_contact(self._gap, self.points)
        state = gap > 0 if self.linear_compliance else np.concatenate([gap > 0, gap * (gap > 0)])
        if self.pairs is None:
            return state
        return np.concatenate([state, self.pairs.state(self.u.vec.FV().NumPy(), self.linear_compliance)])

    def jacobian(self):
        """A + K(u) as a sparse matrix (updated in place; valid until the next call)."""
        with threads(self.disc.V.ndof):
            self.form.AssembleLinearization(self.u.vec)
        J = self.sum.update(self.form.mat)
        return J if self.pairs is None else self.sum.add(*self.pairs.jacobian(self.u.vec.FV().NumPy()))


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
