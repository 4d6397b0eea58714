r"""Displacement traces at the contact Gauss points, and the point data of the contact laws.

Every contact term of (3.1) is a sum over the Gauss points :math:`x_q` of :math:`\Gamma_C` (:math:`p + 1` per
edge, the rule of :mod:`ngdgfric.contact`), :math:`q = 1, \dots, M`, with weights :math:`\omega_q` (Gauss weight
times :math:`|dx/ds|` of the edge's mapping: the edge length on straight edges, ``edge_jacobians``):

.. math::

    j_n(u, v) + g(\lambda_\tau, v) = \sum_q f_{n,q}\, v_n(x_q) + f_{t,q}\, v_t(x_q) = v^T B^T f,

    f_{n,q} = \omega_q c_n (u_n - g_a)_+^{m_n}(x_q), \qquad
    f_{t,q} = \omega_q c_\tau (u_n - g_a)_+^{m_t}(x_q)\, \lambda_\tau(x_q),

where :math:`B` (:math:`2M \times N`) is the trace matrix, :math:`(B u)_q = u_n(x_q)` and
:math:`(B u)_{M+q} = u_t(x_q)`, and :math:`f` the contact forces at the points.  :math:`B` is built from the
Gauss-rule mass matrices :math:`\int (u \cdot n) \mu \, ds` and :math:`\int (u \cdot t) \mu \, ds` with :math:`\mu`
in the multiplier space :math:`Q` (degree :math:`p` per edge): for edge :math:`e` with Vandermonde matrix
:math:`V_e` (values of :math:`Q`'s basis at its points) and weights :math:`D_e = \operatorname{diag}(\omega)`,
those matrices are :math:`B_e^T D_e V_e`, so :math:`B_e = D_e^{-1} V_e^{-T} (\text{mass matrix})_e^T`.
"""

import copy

import ngsolve as ngs
import numpy as np

from ..problem import PerSide
from ..threads import threads
from .boundary import boundary_edges, evaluate_on_contact, normal_tangent

__all__ = ["ContactTraces", "trace_rows"]


def _point_values(value, points):
    """A datum (a number, or a CoefficientFunction that may contain volume GridFunctions) at the
    mapped contact points, as an array."""
    if isinstance(value, ngs.CoefficientFunction):
        return evaluate_on_contact(value, points) * np.ones(len(points))
    return np.full(len(points), float(value))


class ContactTraces:
    """B, the weights and the data of the contact laws at the M Gauss points of Gamma_C.

    ``contact``: a :class:`~ngdgfric.Contact`; ``problem``: the problem whose contact
    law is evaluated at the points (``contact.problem``, or the problem of a fixed-point step,
    :func:`ngdgfric.contact.forms.frozen_bound`, which differs from it in c_tau and m_t only).
    Attributes: ``rows``, ``cols``, ``values`` (B as COO triplets, shape ``(2 M, ndof)``),
    ``omega``, ``g_a``, ``c_n``, ``c_tau`` (arrays of length M, in the point order of
    ``contact.gauss``: edge by edge), ``m_n``, ``m_t`` (numbers, or arrays of length M where the contact sides have
    their own), and ``redundant``: True if some element's
    traces at its points are linearly dependent (an element with two edges on Gamma_C, or on hp
    meshes an element of degree p_T < p, whose trace is fixed by fewer than p + 1 values); then
    the forces at those points are not unique (u is); for the conforming baseline see :meth:`_redundant`.
    """

    def __init__(self, contact, problem):
        gauss = contact.gauss
        self.ndof = contact.V.ndof
        self.M = gauss.dofs.size
        self.omega = gauss.omega
        self.g_a = _point_values(problem.g_a, gauss.points)
        self.c_n = _point_values(problem.c_n, gauss.points)
        self.c_tau = _point_values(problem.c_tau, gauss.points)
        self.m_n, self.m_t = (np.repeat(m.at(gauss.sides), gauss.q) if isinstance(m, PerSide) else float(m)
                              for m in (problem.m_n, problem.m_t))
        self.rows, self.cols, self.values = trace_rows(gauss, contact.V_plain, self.ndof, normal_tangent())
        self.redundant = self._redundant(contact)
        self.foundation = self.M
        if contact.pairs:
            self._add_pairs(contact.pairs)

    def _add_pairs(self, pairs):
        """Append the points of the contact pairs (``Contact.pairs``) after the foundation's: normal rows
        ``foundation .. M - 1``, tangential rows ``M + foundation .. 2 M - 1``; the law's data there are the pairs'
        (``g_a``: the geometric gap plus the pair's offset)."""
        total = self.M + sum(points.M for _, points, _ in pairs)
        parts = [(np.where(self.rows >= self.M, self.rows + total - self.M, self.rows), self.cols, self.values)]
        data = {name: [np.broadcast_to(getattr(self, name), (self.M,))] for name in
                ("omega", "g_a", "c_n", "c_tau", "m_n", "m_t")}
        offset = self.M
        for pair, points, (rows, cols, values) in pairs:
            parts.append((np.where(rows < points.M, offset + rows, total + offset - points.M + rows), cols, values))
            offset += points.M
            data["omega"].append(points.weight)
            data["g_a"].append(points.gap)
            for name in ("c_n", "c_tau", "m_n", "m_t"):
                data[name].append(np.full(points.M, getattr(pair, name)))
        self.rows, self.cols, self.values = (np.concatenate(arrays) for arrays in zip(*parts, strict=True))
        for name, arrays in data.items():
            setattr(self, name, np.concatenate(arrays).astype(float))
        self.M = total
        self.redundant = True  # more points than trace values on an edge cut into pieces

    def _redundant(self, contact):
        """Whether the rows of B belonging to some element are linearly dependent.  For the conforming baseline
        (continuous traces of degree p on every edge of Gamma_C, p points per edge) the points of an open chain of
        edges are independent; a closed one (a hole's whole boundary) can have a kernel (p = 1: alternating signs
        on an even number of edges)."""
        gauss = contact.gauss
        edges = boundary_edges(contact.problem, contact.mesh)
        element_of_edge = [element.nr for _, element in edges]
        vertices = {v.nr for el, _ in edges for v in el.vertices}
        if contact.conforming:
            return len(vertices) <= len(element_of_edge)
        element_of_edge = np.asarray(element_of_edge, dtype=np.int64)
        if len(np.unique(element_of_edge)) < len(element_of_edge):
            return True  # an element with two edges on Gamma_C
        orders = contact.orders[element_of_edge]
        return bool(np.any(orders + 1 < gauss.q))

    def pair_part(self):
        """The pairs' points alone (those after the foundation's, in their order) as a ``ContactTraces`` of
        ``M - foundation`` points (normal rows first, then tangential; ``foundation`` 0): the points where
        Uzawa (:mod:`ngdgfric.solvers.uzawa`) writes the pairs' terms."""
        part, start, M = copy.copy(self), self.foundation, self.M
        keep = self.rows % M >= start
        rows = self.rows[keep]
        part.rows = np.where(rows < M, rows - start, rows - 2 * start)
        part.cols, part.values = self.cols[keep], self.values[keep]
        for name in ("omega", "g_a", "c_n", "c_tau", "m_n", "m_t"):
            value = getattr(self, name)
            setattr(part, name, value[start:] if np.ndim(value) else value)
        part.M, part.foundation = M - start, 0
        return part

    def apply(self, vec):
        """B u for a coefficient vector (numpy array) u."""
        return np.bincount(self.rows, weights=self.values * vec[self.cols], minlength=2 * self.M)

    def apply_transpose(self, f):
        """B^T f for forces f (numpy array of length 2 M)."""
        return np.bincount(self.cols, weights=self.values * f[self.rows], minlength=self.ndof)


def _mass_matrix(gauss, V_plain, ndof, direction):
    """(V dof, Q dof, value) of int (u . direction) mu ds over the sides of ``gauss`` (its Gauss rule), mu in its
    facet space."""
    mu, v = gauss.Q.TrialFunction(), V_plain.TestFunction()
    form = ngs.BilinearForm(trialspace=gauss.Q, testspace=V_plain)
    form += mu * (v * direction) * gauss.dS
    with threads(ndof):
        form.Assemble()
    values, cols, rowptr = form.mat.CSR()
    rowptr = np.array(rowptr, dtype=np.int64)
    rows = np.repeat(np.arange(form.mat.height, dtype=np.int64), np.diff(rowptr))
    values = np.array(values)
    nonzero = values != 0
    return rows[nonzero], np.array(cols, dtype=np.int64)[nonzero], values[nonzero]


def trace_rows(gauss, V_plain, ndof, directions):
    """The traces v . d_c of V_h at the Gauss points of a ``ContactGauss`` (:mod:`ngdgfric.contact.boundary`) as COO
    triplets (rows, cols, values), row c M + e q + i for direction c, edge e and point i (M = edges x q):
    B_e = D_e^-1 V_e^-T (mass matrix)_e^T of the module docstring, entries below 1e-13 of the largest dropped."""
    q, edges = gauss.q, len(gauss.dofs)
    M = edges * q
    edge_of = np.empty(gauss.Q.ndof, dtype=np.int64)
    index_of = np.empty(gauss.Q.ndof, dtype=np.int64)
    edge_of[gauss.dofs.ravel()] = np.repeat(np.arange(edges), q)
    index_of[gauss.dofs.ravel()] = np.tile(np.arange(q), edges)
    inverse_t = np.linalg.inv(gauss.vandermonde).transpose(0, 2, 1)
    rows, cols, values = [], [], []
    for component, direction in enumerate(directions):
        v_dof, q_dof, entry = _mass_matrix(gauss, V_plain, ndof, direction)
        e, k = edge_of[q_dof], index_of[q_dof]
        for i in range(q):
            rows.append(component * M + e * q + i)
            cols.append(v_dof)
            values.append(inverse_t[e, i, k] * entry / gauss.omega[e * q + i])
    rows, cols, values = np.concatenate(rows), np.concatenate(cols), np.concatenate(values)
    keys, where = np.unique(rows * ndof + cols, return_inverse=True)
    summed = np.bincount(where, weights=values)
    keep = np.abs(summed) > 1e-13 * np.max(np.abs(summed), initial=0.0)
    return keys[keep] // ndof, keys[keep] % ndof, summed[keep]
