r"""Warm starts: a solution on one mesh as the initial guess on another (from coarser to finer).

A :class:`ngdgfric.WarmStart` is what a solve can start from: :math:`u_h`, the mesh it lives on and the
multiplier as mesh-independent Gauss values (``ngdgfric.contact.boundary.GaussValues``); ``initial_guess`` turns it
into the pair :math:`(u_h, \lambda_\tau)` on a discretisation's spaces, and ``starting_point`` makes the
solvers' own copies of such a pair.
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .contact.boundary import GaussValues
from .contact.laws import project_unit_values
from .dg.discretization import dg_space
from .dg.dofs import element_dofs
from .meshes import same_mesh

__all__ = ["WarmStart", "initial_guess", "starting_point", "multiplier_snapshot", "copy_orders", "discontinuous",
           "interpolate"]

INSIDE = 1
"""The extra quadrature degree of ``interpolate``: ``GridFunction.Set`` projects with a Gauss rule of degree
2 p_T, and NGSolve's rule of degree 2 (p_T = 1) has its three points on the edges' midpoints, where the point search
of a GridFunction of another mesh object finds either neighbour (a discontinuous u_h projected onto a copy of its own
mesh came out wrong on 92 of 128 elements); from degree 3 on every point lies inside the triangle (barycentric
coordinates >= 0.09 at degree 3, >= 1e-4 up to degree 24)."""


def interpolate(target, source):
    """Set the GridFunction ``target`` to ``source`` (a GridFunction of another mesh, or of the same one, or any
    CoefficientFunction) by NGSolve's element-wise L2 projection with a Gauss rule whose points lie inside the
    elements (``INSIDE``): exact, to round-off, where ``target``'s mesh refines ``source``'s (or is a copy of it)
    and ``target``'s space contains ``source`` element by element."""
    target.Set(source, bonus_intorder=INSIDE)


def _local(p, q):
    """Positions, in an element's block of order p, of the basis functions of total degree <= q."""
    i, j = np.array([(i, j) for i in range(q + 1) for j in range(q + 1 - i)]).T
    return i * (p + 1) - i * (i - 1) // 2 + j


def copy_orders(source, source_orders, target, target_orders):
    """target = source for GridFunctions of two variable-order ``L2**2`` spaces on one mesh, by copying
    coefficients: exact where p_T(target) >= p_T(source), else the element-wise L2 projection.

    NGSolve's L2 triangle basis is hierarchical and L2-orthogonal (Dubiner): the element's functions
    are ordered by (i, j), i = 0..p, j = 0..p - i, the same functions for every p, and an element's
    coefficients are contiguous, elements in order, one component after the other; so the
    functions of degree <= min(p, p') carry over and truncation is the projection onto lower p.
    The same as ``target.Set(source)`` with a quadrature exact for both degrees (tested; ``Set``'s
    default rule of degree 2 p_T is not exact onto lower orders), without the quadrature: ``Set``
    took 0.11 s for 512 elements into p = 8, 18 % of a solve on that mesh.
    """
    source_orders = np.asarray(source_orders, dtype=np.int64)
    target_orders = np.asarray(target_orders, dtype=np.int64)
    blocks = []
    for orders, gf in ((source_orders, source), (target_orders, target)):
        first = np.concatenate([[0], np.cumsum(element_dofs(orders) // 2)])  # one component
        if 2 * first[-1] != len(gf.vec):
            raise ValueError(f"a space with {len(gf.vec)} DOFs does not have the orders given ({2 * first[-1]} DOFs)")
        blocks.append(first)
    values, out = source.vec.FV().NumPy(), np.zeros(len(target.vec))
    pairs = np.stack([source_orders, target_orders], axis=1)
    for ps, pt in np.unique(pairs, axis=0):
        elements = np.flatnonzero((source_orders == ps) & (target_orders == pt))
        q = min(ps, pt)
        from_ = blocks[0][elements][:, None] + _local(ps, q)[None, :]
        to = blocks[1][elements][:, None] + _local(pt, q)[None, :]
        for component in range(2):
            out[to + component * blocks[1][-1]] = values[from_ + component * blocks[0][-1]]
    target.vec.FV().NumPy()[:] = out


def discontinuous(sol):
    """(u, degrees): the displacement of a Solution as a GridFunction of a variable-order ``L2**2`` space on its
    mesh (what ``copy_orders`` takes) and the degree of every element: ``sol.u`` itself for the DG methods;
    for the conforming baseline u_h set into L2 of each element's largest degree
    (``Discretization.degrees``: exact on straight elements)."""
    disc = sol.discretization
    degrees = disc.degrees
    if not disc.method.conforming:
        return sol.u, degrees
    u = ngs.GridFunction(dg_space(sol.mesh, degrees, dgjumps=False))
    u.Set(sol.u)
    return u, degrees


def multiplier_snapshot(sol):
    """The multiplier of a Solution as mesh-independent Gauss values (``GaussValues``)."""
    return sol.contact.gauss.snapshot(sol.lam_tau)


@dataclass(frozen=True)
class WarmStart:
    r"""What a solve can start from (``initial`` of :func:`ngdgfric.solve`).

    :func:`ngdgfric.solve` makes one of a :class:`ngdgfric.Solution` given as ``initial``
    (``WarmStart.from_solution``); on another mesh, ``ngdgfric.transfer.initial_guess`` interpolates it.

    Parameters
    ----------
    u : ngsolve.GridFunction
        The displacement, a GridFunction of an ``L2**2`` space on ``mesh``.
    mesh : ngsolve.Mesh
        The mesh of ``u`` (it may have been refined since, for ``u`` in an autoupdating space, as in the
        adaptive loop).
    multiplier : GaussValues
        :math:`\lambda_\tau` as Gauss values on :math:`\Gamma_C` (``multiplier_snapshot``), independent of the
        mesh.
    lam_tau : ngsolve.GridFunction or None, optional
        The multiplier GridFunction itself; with it, a start on the same mesh and spaces is copied exactly.
        Default ``None``.
    """

    u: object
    mesh: object
    multiplier: GaussValues
    lam_tau: object = None

    @classmethod
    def from_solution(cls, sol):
        """The warm start of a :class:`ngdgfric.Solution`."""
        return cls(sol.u, sol.mesh, multiplier_snapshot(sol), sol.lam_tau)


def starting_point(contact, initial=None):
    """New GridFunctions (u, lam_tau) on V_h and the multiplier space of the :class:`~ngdgfric.Contact`
    ``contact``: zero, or copies of the pair ``initial`` (the iterates a solver changes in place; the caller's pair
    is left alone)."""
    u, lam_tau = ngs.GridFunction(contact.V), ngs.GridFunction(contact.Q)
    if initial is not None:
        u.vec.data, lam_tau.vec.data = initial[0].vec, initial[1].vec
    return u, lam_tau


def _on_mesh(u, mesh):
    """The GridFunction ``u`` of a uniform-order L2**2 space as the same coefficients on ``mesh``, a mesh with
    the same elements in the same order (u itself if its space has variable orders)."""
    space = ngs.L2(mesh, order=u.space.globalorder) ** 2
    if space.ndof != u.space.ndof:
        return u
    copy = ngs.GridFunction(space)
    copy.vec.data = u.vec
    return copy


def initial_guess(start, contact):
    """(u, lam_tau): GridFunctions on V_h and the multiplier space of the :class:`~ngdgfric.Contact`
    ``contact``, from the ``WarmStart`` ``start``.

    On the same mesh (``ngdgfric.meshes.same_mesh``: the same object or a snapshot of it) and spaces (and
    with ``start.lam_tau``) the vectors are copied.  Otherwise u is interpolated (exact for nested meshes and
    equal or higher order; from a snapshot of the same mesh without the point search that a GridFunction of
    another mesh object needs, 7 times slower at 1e5 DOFs) and lam_tau is the old multiplier, a piecewise
    polynomial on the old edges of Gamma_C, evaluated at the new Gauss points.
    """
    same = same_mesh(start.mesh, contact.mesh)
    if same and start.lam_tau is not None and start.u.space.ndof == contact.V.ndof \
            and start.lam_tau.space.ndof == contact.Q.ndof:
        return starting_point(contact, (start.u, start.lam_tau))
    u, lam_tau = starting_point(contact)
    interpolate(u, _on_mesh(start.u, contact.mesh) if same else start.u)
    gauss = contact.gauss
    gauss.set_values(lam_tau, project_unit_values(start.multiplier(gauss.xy.reshape(-1, 2))).reshape(-1, gauss.q))
    return u, lam_tau
