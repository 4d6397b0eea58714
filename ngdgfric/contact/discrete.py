r"""The contact part of the discrete problem on one mesh, built beside the
:class:`~ngdgfric.dg.discretization.Discretization` (which keeps the DG spaces and the matrices of :math:`B_h`).

:class:`~ngdgfric.Contact` holds what every contact computation of a mesh shares: the multiplier space :math:`Q` on
:math:`\Gamma_C`, the contact measure with its Gauss rule, the Gauss points, the traces :math:`B` at those points
and the multiplier's mass matrix.  :func:`ngdgfric.solve` builds one per mesh and passes it, with the
discretisation, to the solvers; a :class:`~ngdgfric.Solution` keeps it as ``contact``.
"""

import functools

import ngsolve as ngs
import numpy as np

from ..threads import threads
from .boundary import ContactGauss, boundary_edges, contact_measure, contact_points, law_elements, multiplier_space
from .pair_traces import SideTraces, pair_rows
from .pairing import pair_points
from .traces import ContactTraces

__all__ = ["Contact", "STICK_MARGIN"]

STICK_MARGIN = 1e-8
r"""A point sticks where :math:`|\lambda_\tau| < 1 -` STICK_MARGIN (``Contact.point_states``): the multiplier of a
slipping point is :math:`\pm 1` to round-off."""


class Contact:
    r"""The contact data of one mesh: the multiplier space, Gauss points and traces of :math:`\Gamma_C`.

    Parameters
    ----------
    disc : Discretization
        The discretisation whose space :math:`V_h` the traces act on (:class:`ngdgfric.Discretization`).

    Attributes
    ----------
    problem
        The problem of ``disc``.
    mesh
        The mesh of ``disc``.
    V
        :math:`V_h` (``disc.V``).
    V_plain
        The test space of the mixed contact forms (``disc.V_plain``).
    orders
        :math:`p_T` per element, an integer array.
    conforming
        Whether :math:`V_h` is the conforming baseline's (continuous traces on :math:`\Gamma_C`).
    order
        The degree of the multiplier space and of the contact Gauss rule (``order + 1`` points per edge):
        the largest :math:`p_T` of the elements with an edge where a contact law acts (``law_elements`` of
        :mod:`ngdgfric.contact.boundary`; the Gauss rule is exact for their traces' products, and where they share
        one degree, as on the meshes of :func:`ngdgfric.adapt`, no edge has more points than trace values), one
        less for the conforming baseline, whose traces on :math:`\Gamma_C` are continuous (``order + 1`` points per
        edge would make them linearly dependent and the Delassus operator singular).
    Q
        The multiplier space on :math:`\Gamma_C` (``multiplier_space`` of :mod:`ngdgfric.contact.boundary`).
    dS
        The contact measure, with the contact Gauss rule.

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> disc = ndf.Discretization(problem, ndf.uniform_mesh(problem, 0.5), order=2)
    >>> contact = ndf.Contact(disc)
    >>> contact.Q.ndof, contact.traces.M
    (6, 6)
    """

    def __init__(self, disc):
        self.problem, self.mesh = disc.problem, disc.mesh
        self.V, self.V_plain, self.orders = disc.V, disc.V_plain, disc.orders
        self.conforming = disc.method.conforming
        self.degree = disc.order
        elements = law_elements(self.problem, self.mesh)
        top = int(np.max(disc.orders[elements])) if elements.size else disc.order
        self.order = top - 1 if self.conforming else top
        self.Q = multiplier_space(self.problem, self.mesh, self.order)
        self.dS = contact_measure(self.problem, self.mesh, self.order)

    @functools.cached_property
    def M_inv(self):
        """The inverse Gauss-rule mass matrix of the multiplier space.

        Factorised when first used; only the multiplier updates of Uzawa and the fixed point need it.
        """
        lam_tau, q = self.Q.TnT()
        m = ngs.BilinearForm(self.Q)
        m += lam_tau * q * self.dS
        with threads(self.V.ndof):
            m.Assemble()
            return m.mat.Inverse(inverse="sparsecholesky")

    @functools.cached_property
    def gauss(self):
        """The ``ContactGauss`` of :mod:`ngdgfric.contact.boundary` of this mesh (built on first use)."""
        return ContactGauss(self.mesh, self.problem.sides("contact"), self.order, self.Q)

    @functools.cached_property
    def pairs(self):
        r"""The contact pairs of the problem on this mesh, built on first use.

        A list of ``(pair, PairPoints, rows of B)`` (:mod:`ngdgfric.contact.pairing`,
        :mod:`ngdgfric.contact.pair_traces`: ``pair_rows``, normal rows ``0 .. m - 1`` and tangential rows
        ``m .. 2 m - 1`` for the pair's m points), with ``order + 1`` points per piece of the common refinement (as
        on the foundation's edges: the conforming baseline's continuous traces take one point fewer, else their rows
        repeat each other); the traces of each side at ``degree + 1`` nodes per edge (exact for its polynomials)."""
        found = []
        for pair in self.problem.pairs:
            points = pair_points(self.mesh, pair, self.order + 1, self.reach(pair))
            side, other = (SideTraces(self.V_plain, self.mesh, name, self.degree + 1)
                           for name in (pair.side, pair.other))
            found.append((pair, points, pair_rows(points, side, other)))
        return found

    def reach(self, pair):
        """The distance within which the sides of ``pair`` face each other: its ``reach``, by default a tenth of the
        geometry's diameter."""
        return 0.1 * self.problem.geometry.diameter() if pair.reach is None else pair.reach

    @functools.cached_property
    def traces(self):
        """The ``ContactTraces`` of :mod:`ngdgfric.contact.traces` of this mesh and its problem (built on first use)."""
        return ContactTraces(self, self.problem)

    def multiplier_values(self, lam_tau):
        """The multiplier at every contact point (``traces`` order): lam_tau's values at the foundation's Gauss
        points, then 0 at the pairs' points (a warm start carries the foundation's multiplier only)."""
        extra = sum(points.M for _, points, _ in self.pairs)
        return np.concatenate([self.gauss.values(lam_tau).ravel(), np.zeros(extra)])

    def set_multiplier(self, lam_tau, values):
        """Set the GridFunction lam_tau on ``Q`` from the multiplier at every contact point (``traces`` order);
        returns the values at the pairs' points (which lam_tau, living on the foundation's sides, does not hold)."""
        foundation = self.gauss.dofs.size
        self.gauss.set_values(lam_tau, np.asarray(values)[:foundation].reshape(-1, self.gauss.q))
        return np.asarray(values)[foundation:].copy()

    def point_states(self, u, lam_tau, pair_multiplier=None):
        r"""The state of the laws at every contact point (``traces`` order) for a displacement GridFunction ``u`` on
        ``V`` and a multiplier ``lam_tau`` on ``Q`` (``pair_multiplier``: the values at the pairs' points, which
        lam_tau does not hold; default 0): 0 without contact (:math:`u_n \le g_a`), 1 sticking (in contact,
        :math:`c_\tau > 0` and :math:`|\lambda_\tau| < 1 - 10^{-8}`), 2 slipping (in contact otherwise, frictionless
        points included).  ``changed_points`` compares two such states."""
        traces = self.traces
        w = traces.apply(u.vec.FV().NumPy())
        lam = self.multiplier_values(lam_tau)
        if pair_multiplier is not None and len(pair_multiplier):
            lam[traces.M - len(pair_multiplier):] = pair_multiplier
        touching = w[:traces.M] > traces.g_a
        sticking = touching & (np.asarray(traces.c_tau) > 0) & (np.abs(lam) < 1 - STICK_MARGIN)
        return np.where(touching, np.where(sticking, 1, 2), 0)

    def points(self):
        r"""Mapped Gauss points on :math:`\Gamma_C` (``contact_points`` of :mod:`ngdgfric.contact.boundary`)."""
        return contact_points(self.problem, self.mesh, self.order)

    def groups(self):
        r"""For each edge on :math:`\Gamma_C`, the DOFs of :math:`V_h` of its element."""
        return [list(self.V.GetDofNrs(element)) for _, element in boundary_edges(self.problem, self.mesh)]
