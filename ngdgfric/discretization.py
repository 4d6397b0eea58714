"""The discrete problem (3.1)/(3.3) on one mesh: spaces, the assembled linear DG part, contact forms."""

import copy
import dataclasses
import functools
import time
from numbers import Integral, Real

import ngsolve as ngs
import numpy as np

from .checks import check_data, check_size
from .contact import (
    ContactGauss,
    compliance,
    contact_measure,
    contact_points,
    friction_bound,
    multiplier_space,
    normal_tangent,
)
from .forms import dg_terms, edge_length, load_terms
from .liftings import lifting_terms
from .linalg import sparse_sum, threads
from .meshes import check_mesh
from .methods import check_penalty, get_method
from .problem import ContactProblem
from .traces import ContactTraces

__all__ = ["Discretization", "dg_space", "check_order", "order_function"]


def dg_space(mesh, order, dgjumps=True):
    """V_h: discontinuous vector polynomials of degree ``order`` (Section 2.1).

    ``order``: p, or an integer array with the degree p_T of every element (hp).
    ``dgjumps=False`` gives the same space and numbering without the facet couplings in the
    matrix pattern; mixed forms with the multiplier space need it (NGSolve 6.2.2608 crashes
    assembling a mixed skeleton form whose test space has ``dgjumps=True``).
    """
    if np.ndim(order) == 0:
        return ngs.L2(mesh, order=int(order), dgjumps=dgjumps) ** 2
    scalar = ngs.L2(mesh, order=int(np.max(order)), dgjumps=dgjumps)
    for nr, p in enumerate(order):  # only scalar L2 has SetOrder: build Q**2 from it
        scalar.SetOrder(ngs.NodeId(ngs.ELEMENT, nr), int(p))
    scalar.Update()
    return scalar**2


def check_order(order, mesh):
    """``order`` validated: an int p >= 1, or an integer array of p_T >= 1, one per element."""
    if np.ndim(order) == 0:
        if not isinstance(order, Integral) or isinstance(order, bool) or order < 1:
            raise ValueError(f"order must be an integer >= 1, got {order!r}")
        return int(order)
    orders = np.asarray(order)
    if orders.shape != (mesh.ne,) or not np.issubdtype(orders.dtype, np.integer) or orders.min() < 1:
        raise ValueError(f"order must be an integer >= 1 or an integer array of {mesh.ne} orders >= 1 "
                         f"(one per element), got shape {orders.shape}, dtype {orders.dtype}")
    return orders.astype(np.int64)


def order_function(mesh, order):
    """p_T as a piecewise constant GridFunction (``order`` itself if it is a number)."""
    if np.ndim(order) == 0:
        return order
    p = ngs.GridFunction(ngs.L2(mesh, order=0))
    p.vec.FV().NumPy()[:] = order
    return p


def _check_eta(eta):
    if isinstance(eta, ngs.CoefficientFunction):
        return eta
    if not isinstance(eta, Real) or isinstance(eta, bool) or not np.isfinite(eta) or eta <= 0:
        raise ValueError(f"eta must be a positive number, got {eta!r}")
    return float(eta)


class Discretization:
    """Everything of (3.3) that does not depend on the solution, built once per mesh.

    Attributes: ``V`` (DG space), ``Q`` (multiplier space on Gamma_C), ``A`` (matrix of B_h),
    ``F`` (load vector of (f, v)), ``compliance`` (nonlinear form of j_n on V), ``G`` (matrix of
    g(lam, v) = int c_tau l v.t ds, trial Q, test V; None for m_t > 0, where the friction bound
    depends on u: see :meth:`bound`, :meth:`frozen_bound`), ``M_inv`` (inverse Gauss-rule mass matrix
    of Q), ``h_e``, ``timings``; ``orders`` (p_T per element), ``order`` (the largest, which sets
    the contact Gauss rule, the multiplier degree and the lifting space), ``p`` (p_T as a number
    or GridFunction, for the penalty and the estimator weights).

    Before assembly: the mesh must fit the problem (:func:`ngdgfric.meshes.check_mesh`), the DOFs
    the size limit ``max_ndof`` and the data be valid pointwise (:mod:`ngdgfric.checks`).
    """

    def __init__(self, problem, mesh, method="sipg", order=1, eta=None, penalty_check="warn", max_ndof=None):
        if not isinstance(problem, ContactProblem):
            raise ValueError(f"problem must be a ContactProblem, got {problem!r}")
        check_mesh(problem, mesh)
        self.problem, self.mesh = problem, mesh
        self.method = get_method(method)
        order = check_order(order, mesh)
        self.orders = np.full(mesh.ne, order) if np.ndim(order) == 0 else order
        check_size(self.orders, max_ndof)
        check_data(problem, mesh, int(self.orders.max()))
        self.order = int(self.orders.max())
        self.p = self.order if np.ndim(order) == 0 or np.all(order == self.order) else order_function(mesh, order)
        lowest = int(self.orders.min())  # the lowest order has the highest SIPG threshold
        self.eta = _check_eta(self.method.default(problem, lowest) if eta is None else eta)
        check_penalty(problem, self.method, self.eta, lowest, penalty_check)
        self.timings = {}
        self._gauss = self._traces = None
        start = time.perf_counter()
        self.V = dg_space(mesh, order)
        self.Q = multiplier_space(problem, mesh, self.order)
        self.h_e = edge_length(mesh)
        self.dS = contact_measure(problem, mesh, self.order)
        u, v = self.V.TnT()
        with threads(self.V.ndof):
            a = ngs.BilinearForm(self.V)
            for term in dg_terms(problem, mesh, u, v, self.method, self.eta, self.p, self.h_e):
                a += term
            a.Assemble()
            lifts = lifting_terms(problem, mesh, self.V, self.order, self.method, self.eta)
            self.A = sparse_sum([(1.0, a.mat), *lifts]) if lifts else a.mat
            f = ngs.LinearForm(self.V)
            for term in load_terms(problem, mesh, v):
                f += term
            f.Assemble()
            self.F = f.vec
            self.timings["assemble"] = time.perf_counter() - start
            self.V_plain = dg_space(mesh, order, dgjumps=False)
            self.G = self._friction_matrix() if problem.m_t == 0 else None
        self.compliance = ngs.BilinearForm(self.V)
        self.compliance += self.compliance_form(u, v)
        self._contact_forms = {}
        self.timings["setup"] = time.perf_counter() - start

    @functools.cached_property
    def M_inv(self):
        """The inverse Gauss-rule mass matrix of the multiplier space (factorised when first used: only
        the multiplier updates of Uzawa and the fixed point need it)."""
        lam, q = self.Q.TnT()
        m = ngs.BilinearForm(self.Q)
        m += lam * q * self.dS
        with threads(self.V.ndof):
            m.Assemble()
            return m.mat.Inverse(inverse="sparsecholesky")

    @property
    def c_tau(self):
        return self.problem.c_tau if isinstance(self.problem.c_tau, ngs.CoefficientFunction) \
            else ngs.CF(self.problem.c_tau)

    @property
    def symmetric(self):
        """B_h is symmetric for every method but NIPG."""
        return self.method.symmetry == 1

    def compliance_form(self, u, v):
        """j_n(u, v) = int_{Gamma_C} c_n (u_n - g_a)_+^{m_n} v_n ds (Gauss rule), a symbolic integral."""
        n, _ = normal_tangent()
        return compliance(self.problem, u) * (v * n) * self.dS

    def bound(self, u):
        """The friction bound c_tau (u_n - g_a)_+^{m_t} of (1.9) at u (a CoefficientFunction of u)."""
        return friction_bound(self.problem, u)

    def frozen_bound(self, u):
        """This discretisation for the reduced law (m_t = 0) with the bound frozen at (a copy of) ``u``.

        c_tau becomes the CoefficientFunction c_tau (u_n - g_a)_+^{m_t} of the fixed u; spaces and
        matrices are shared, only ``G`` is assembled anew.
        """
        frozen = copy.copy(self)
        u_frozen = ngs.GridFunction(self.V)
        u_frozen.vec.data = u.vec
        frozen.problem = dataclasses.replace(self.problem, c_tau=self.bound(u_frozen), m_t=0.0)
        frozen._contact_forms, frozen._gauss, frozen._traces = {}, self.gauss, None
        with threads(self.V.ndof):
            frozen.G = frozen._friction_matrix()
        return frozen

    def _friction_matrix(self):
        """The matrix of g(lam, v) = int c_tau l v.t ds (m_t = 0)."""
        _, t = normal_tangent()
        lam, v = self.Q.TrialFunction(), self.V_plain.TestFunction()
        g = ngs.BilinearForm(trialspace=self.Q, testspace=self.V_plain)
        g += self.c_tau * lam * (v * t) * self.dS
        g.Assemble()
        return g.mat

    def residual(self, u, lam, out=None):
        """Residual of (3.3): A u + j_n(u, .) + g(l, .) - F, as a vector on V.

        For m_t > 0, g carries the bound at u: int c_tau (u_n - g_a)_+^{m_t} l v.t ds.
        """
        r = out if out is not None else self.F.CreateVector()
        if self.G is None:
            self._contact_form(lam).Apply(u.vec, r)
            r.data += self.A * u.vec - self.F
        else:
            self.compliance.Apply(u.vec, r)
            r.data += self.A * u.vec + self.G * lam.vec - self.F
        return r

    def _contact_form(self, lam):
        """j_n(u, v) + g(u; l, v) as a nonlinear form in u for the multiplier GridFunction ``lam`` (cached)."""
        if id(lam) not in self._contact_forms:
            _, t = normal_tangent()
            u, v = self.V.TnT()
            form = ngs.BilinearForm(self.V)
            form += self.compliance_form(u, v)
            form += self.bound(u) * lam * (v * t) * self.dS
            self._contact_forms[id(lam)] = (lam, form)
        return self._contact_forms[id(lam)][1]

    @property
    def gauss(self):
        """The :class:`ngdgfric.contact.ContactGauss` of this mesh (built on first use)."""
        if self._gauss is None:
            self._gauss = ContactGauss(self.problem, self.mesh, self.order, self.Q)
        return self._gauss

    @property
    def traces(self):
        """The :class:`ngdgfric.traces.ContactTraces` of this discretisation (built on first use)."""
        if self._traces is None:
            self._traces = ContactTraces(self)
        return self._traces

    def contact_points(self):
        """Mapped Gauss points on Gamma_C (see :func:`ngdgfric.contact.contact_points`)."""
        return contact_points(self.problem, self.mesh, self.order)

    def contact_groups(self, extra=None):
        """For each edge on Gamma_C, the V-dofs of its element (+ ``extra(edge)`` dofs)."""
        groups = []
        for el in self.mesh.Elements(ngs.BND):
            if el.mat != self.problem.contact:
                continue
            edge = el.edges[0]
            volume = self.mesh[edge].elements[0]
            dofs = list(self.V.GetDofNrs(volume))
            if extra is not None:
                dofs += list(extra(el))
            groups.append(dofs)
        return groups
