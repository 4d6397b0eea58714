r"""Forces and zones on both sides of each contact pair (two bodies): a ``ContactSide`` (:mod:`ngdgfric.contact.forces`)
for the pair's side and one for the other side.

**Forces.**  With :math:`f` the forces at the pair's points (:mod:`ngdgfric.contact.pair_state`) and :math:`e_i^b`
the constant vector :math:`e_i` on body :math:`b` (0 on the other bodies), the force of the pair on body
:math:`b` is

.. math::

    F_b \cdot e_i = -f^T B e_i^b,

the pair's part of (3.3) at :math:`v = e_i^b`, as for the foundation (:mod:`ngdgfric.contact.forces`).  It is
measured on each side through that side's own traces (the rows of :math:`B` on the pair's side give
:math:`B e_i^1 = (n_i, t_i)`, those on the other side :math:`B e_i^2 = -(n_i, t_i)`), so the two resultants are
two measurements: action equals reaction to round-off.  ``normal`` (:math:`\sum f_n`, a compression) and
``tangential`` (:math:`-\sum f_t`) are those of the pair's frame :math:`n, t`, on both sides (the other side's own
frame is :math:`-n, -t` on a flat interface).

**Zones.**  Contact, stick and slip at the points (``zone_masks`` of :mod:`ngdgfric.contact.forces`, with
:math:`[u_h]` in place of :math:`u_h`) and their Gauss cells (``PairPoints.cell``): on the pair's side the cells
themselves, walked along its tangent :math:`t`; on the other side the closest points :math:`\pi` of the cell ends,
walked along the other side's own tangent, each cell's length the distance between the images of its ends (a
chord: exact on straight sides).
"""

import numpy as np

from .curves import SideCurves
from .forces import LAM_TOL, SLIP_TOL, constant_vectors, contact_sides, side_of, walk, zone_masks
from .pair_state import pair_state

__all__ = ["pair_sides", "all_sides"]


def _walk_order(curves, edge, s):
    """The order of points (``edge``, parameter ``s`` of ``curves``) along the side's tangent, and for each point
    whether its edge is walked from s = 1 to s = 0."""
    ends = curves.ends
    _, vertex = np.unique(np.round(ends.reshape(-1, 2), 12), axis=0, return_inverse=True)
    count = len(ends)
    along = curves.frame(np.arange(count), np.full(count, 0.5))[2]
    walked = walk(vertex.reshape(-1, 2).tolist(), ends[:, 1] - ends[:, 0], along)
    position = np.empty(count, dtype=np.int64)
    reversed_ = np.zeros(count, dtype=bool)
    for k, (e, reverse) in enumerate(walked):
        position[e], reversed_[e] = k, reverse
    flip = reversed_[edge]
    return np.lexsort((np.where(flip, -s, s), position[edge])), flip


def _in_cell(point, ends):
    """Where each point lies between its cell ends (m, 2, 2), 0 to 1 (0.5 for a cell of length 0)."""
    chord = ends[:, 1] - ends[:, 0]
    length = np.sum(chord * chord, axis=1)
    return np.where(length > 0, np.sum((point - ends[:, 0]) * chord, axis=1) / np.where(length > 0, length, 1.0), 0.5)


def _pair_side(mesh, pair, points):
    """(order, cell ends (m, 2, 2), position in the cell, weights) of the pair's side in walk order."""
    curves = SideCurves(mesh, pair.side)
    order, flip = _walk_order(curves, points.edge, points.s)
    ends = np.stack([curves.at(points.edge, points.cell[:, 0]), curves.at(points.edge, points.cell[:, 1])], axis=1)
    ends = np.where(flip[:, None, None], ends[:, ::-1], ends)[order]
    return order, ends, _in_cell(points.xy[order], ends), points.weight[order]


def _other_side(mesh, pair, points, pair_ends):
    """The same for the other side: the closest points of the cell ends (``pair_ends``, (m, 2, 2)), each cell
    turned along the other side's tangent, its chord as the weight."""
    other = SideCurves(mesh, pair.other)
    order, _ = _walk_order(other, points.other_edge, points.other_s)
    images = other.at(*other.closest(pair_ends.reshape(-1, 2))[:2]).reshape(-1, 2, 2)[order]
    along = other.frame(points.other_edge, points.other_s)[2][order]
    turn = np.sum((images[:, 1] - images[:, 0]) * along, axis=1) < 0
    ends = np.where(turn[:, None, None], images[:, ::-1], images)
    return order, ends, _in_cell(points.other_xy[order], ends), np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)


def pair_sides(sol, lam_tol=LAM_TOL, slip_tol=SLIP_TOL, body_constants=None):
    r"""Both sides of every contact pair of a solution: forces, pressure and zones (module docstring).

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve` of a problem with contact pairs.
    lam_tol, slip_tol : float, optional
        As in :func:`ngdgfric.force_balance` (the zones of :mod:`ngdgfric.contact.forces`).
    body_constants : list of numpy.ndarray or None, optional
        Per body of ``sol.problem.geometry.bodies``, ``constant_vectors(V, regions of the body)``
        (:mod:`ngdgfric.contact.forces`).  Default ``None``: computed.

    Returns
    -------
    dict
        ``{side label: ContactSide}``, for each pair its side and then its other side (``partner`` names the
        other); ``force`` is the force of the other body on the side's body, ``points`` index the pair's arrays of
        :func:`ngdgfric.contact.pair_state`, ``pressure`` is :math:`f_n / \omega` at the points.
    """
    geometry, contact = sol.problem.geometry, sol.contact
    if body_constants is None:
        body_constants = [constant_vectors(sol.discretization.V, geometry.body_regions(k))
                          for k in range(len(geometry.bodies))]
    traces = contact.traces
    M, start = traces.M, traces.foundation
    sides = {}
    for (pair, points, _), state in zip(contact.pairs, pair_state(sol), strict=True):
        rows = np.r_[start:start + points.M, M + start:M + start + points.M]
        f = np.r_[state["f_n"], state["f_t"]]
        masks = zone_masks(state["penetration"], state["bound"], state["lam_tau"], state["jump_n"],
                           state["jump_tau"], lam_tol, slip_tol)
        order, ends, position, weights = _pair_side(sol.mesh, pair, points)
        measured = [(pair.side, pair.other, order, ends, position, weights, points.xy)]
        measured.append((pair.other, pair.side, *_other_side(sol.mesh, pair, points, ends[np.argsort(order)]),
                         points.other_xy))
        for label, partner, order, ends, position, weights, xy in measured:
            e = body_constants[geometry.body_of_side(label)]
            force = -np.array([f @ traces.apply(e_i)[rows] for e_i in e])
            sides[label] = side_of(
                label, order, weights, ends, position, masks=tuple(mask[order] for mask in masks), partner=partner,
                normal=float(state["f_n"].sum()) + 0.0, tangential=float(-state["f_t"].sum()) + 0.0, force=force + 0.0,
                xy=xy[order], pressure=state["pressure"][order], lam_tau=state["lam_tau"][order])
        start += points.M
    return sides


def all_sides(sol, lam_tol=LAM_TOL, slip_tol=SLIP_TOL):
    """``{side: ContactSide}`` of the foundation's contact sides (``contact_sides`` of
    :mod:`ngdgfric.contact.forces`) and of both sides of every contact pair (:func:`pair_sides`), for plots."""
    sides = contact_sides(sol, lam_tol, slip_tol)
    return {**sides, **pair_sides(sol, lam_tol, slip_tol)} if sol.problem.pairs else sides
