r"""The hp decision: refine a marked element in p where :math:`u_h` is smooth there, in h where it is not.

Smoothness is judged by the predicted-versus-observed error reduction of Melenk and Wohlmuth
(J. M. Melenk, B. I. Wohlmuth, "On residual-based a posteriori error estimation in hp-FEM",
Adv. Comput. Math. 15 (2001) 311-331, Section 4): every element carries a prediction :math:`\eta_{pred}^2`
of its indicator, made when it was last changed under the hypothesis that :math:`u` is smooth (analytic)
there:

* refined in h: :math:`\eta_{pred}^2 = \gamma_h n^{-(p+1)} \eta_T^2` for each of its :math:`n` descendants.
  A marked element is bisected twice (``refine`` of :mod:`ngdgfric.meshes`): its four grandchildren are
  similar to it with :math:`h/2` and the same orientation, and for a smooth :math:`u` each carries
  :math:`(1/2)^{2p} / 4` of the error, Melenk-Wohlmuth's prediction for red refinement.  (After a single
  bisection the children are rotated by 45 degrees, and for an anisotropic :math:`u` the error need not fall
  at all: one bisection cannot tell smooth from singular.)  Closure elements bisected once get :math:`n = 2`;
* :math:`p \to p + 1`: :math:`\eta_{pred}^2 = \gamma_p \eta_T^2` (exponential decay in :math:`p`);
* unchanged: :math:`\eta_{pred}^2 = \gamma_n \eta_{pred}^2`,

with Melenk-Wohlmuth's :math:`\gamma_h = 4`, :math:`\gamma_p = 0.4`, :math:`\gamma_n = 1`.

A marked element whose indicator :math:`\eta_T^2` is at most its prediction is *smooth*: the prediction
made for an analytic :math:`u` came true, so it is refined in p; otherwise (near corner singularities,
where contact starts, where stick turns into slip) the error fell more slowly than a smooth :math:`u`
allows, and it is bisected.  The initial prediction is 0: the first step is an h step, after
which the observed reduction decides.  Elements at ``max_order`` are bisected.
"""

from dataclasses import dataclass

import numpy as np

from .dg.dofs import dg_ndof
from .meshes import refine, triangle_corners

__all__ = ["HPState", "smooth", "refinement_parents", "hp_refine", "containing"]


@dataclass
class HPState:
    """Per-element orders p_T and predicted squared indicators eta_pred^2 of the current mesh."""

    orders: np.ndarray
    predicted: np.ndarray

    @classmethod
    def uniform(cls, mesh, order):
        return cls(np.full(mesh.ne, int(order), dtype=np.int64), np.zeros(mesh.ne))

    @property
    def ndof(self):
        """dim V_h = sum_T (p_T + 1)(p_T + 2) (two components)."""
        return dg_ndof(self.orders)

    def shared(self, elements):
        """This state with the degrees of ``elements`` (numbers) raised to the largest among them: the elements along
        which a friction law acts share one degree (``AdaptiveLoop`` of :mod:`ngdgfric.levels`), so that the contact
        Gauss rule of that degree (``ngdgfric.Contact``) puts no more points on an edge than its element has trace
        values: the sticking forces are unique, and the semismooth Newton iteration needs no proximal point method
        (its iterations per level: :ref:`decisions-hp`)."""
        orders = self.orders.copy()
        if len(elements):
            orders[elements] = orders[elements].max()
        return HPState(orders, self.predicted)


def smooth(indicators, predicted):
    """True where the squared indicator did not exceed its prediction for a smooth u."""
    return np.asarray(indicators) <= np.asarray(predicted)


def refinement_parents(mesh, ne_old):
    """For every element of a mesh just refined by ``Refine``: its ancestor among the ``ne_old``
    elements of the mesh before (elements keep their number, a bisected one for one descendant,
    the others are appended), and the number of descendants of every old element.

    Netgen's parent array (``parentsurfaceelements``, -1 for an element not created by bisection)
    is followed up the chain in whole-array steps, as many as the deepest chain (two for
    ``Refine()``, more with the closure); no loop over elements."""
    parent = np.arange(mesh.ne)
    parents = np.asarray(mesh.ngmesh.parentsurfaceelements, dtype=np.int64).reshape(-1)[:mesh.ne]
    parent[ne_old:] = parents[ne_old:]
    while np.any(parent >= ne_old):
        parent = np.where(parent >= ne_old, parent[parent], parent)
    return parent, np.bincount(parent, minlength=ne_old)


def containing(mesh, points):
    """True for the elements that contain one of ``points`` (an (n, 2) array; closed triangles, so a point on an edge
    or at a vertex is in all its elements)."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if not len(points):
        return np.zeros(mesh.ne, dtype=bool)
    corners = triangle_corners(mesh)
    a = corners[:, 0]
    frame = np.stack([corners[:, 1] - a, corners[:, 2] - a], axis=2)  # columns b - a, c - a
    local = np.linalg.solve(frame[:, None], (points[None, :, :] - a[:, None, :])[..., None])[..., 0]
    barycentric = np.concatenate([local, 1 - local.sum(axis=2, keepdims=True)], axis=2)
    return (barycentric >= -1e-10).all(axis=2).any(axis=1)


def hp_refine(mesh, state, indicators, marked, max_order, gamma_h=4.0, gamma_p=0.4, gamma_n=1.0, singular=None,
              layers=0):
    r"""Refine the marked elements in h or p, as the observed error reduction says.

    The hp decision of :mod:`ngdgfric.hp`: a marked element whose indicator came out at most its prediction for
    a smooth :math:`u` is raised in degree, any other is bisected.  The mesh is bisected in place (marked h
    elements twice, plus closure); :math:`p_T` is raised by one on the other marked elements.

    Parameters
    ----------
    mesh : ngsolve.Mesh
        The current mesh, refined in place.
    state : HPState
        The degrees :math:`p_T` and predicted indicators :math:`\eta_{pred}^2` of the current mesh
        (``ngdgfric.hp.HPState``; ``HPState.uniform(mesh, order)`` for a first mesh of one degree).
    indicators : array_like
        :math:`\eta_T^2` of the current mesh, one per element (``Estimate.eta_T_squared`` of
        :func:`ngdgfric.estimate`).
    marked : array_like of bool
        Doerfler's set, one entry per element (:func:`ngdgfric.dorfler_mark`).
    max_order : int
        The largest degree, at least the current largest; elements at ``max_order`` are bisected.
    gamma_h : float, optional
        The factor :math:`\gamma_h` of the prediction after bisection.  Default ``4.0``.
    gamma_p : float, optional
        The factor :math:`\gamma_p` of the prediction after raising the degree.  Default ``0.4``.
    gamma_n : float, optional
        The factor :math:`\gamma_n` of the prediction of an unchanged element.  Default ``1.0``.
    singular : array_like or None, optional
        Points where :math:`u` may be singular, an :math:`(n, 2)` array: the domain's corners (``Geometry.corners``
        of :mod:`ngdgfric.domain`) and the ends of the contact and stick zones (``transitions`` of
        :mod:`ngdgfric.contact`).  A marked h element containing one of them is refined towards it by
        ``layers`` more geometric layers.  Default ``None``: no grading.
    layers : int, optional
        Geometric layers towards ``singular`` in the same step: the element's descendants containing the
        point are bisected twice more, ``layers`` times (:math:`h` halves per layer), so that one level does
        what ``layers + 1`` levels of single steps would.  Default ``0``.

    Returns
    -------
    HPState
        The degrees and predictions of the refined mesh (``ngdgfric.hp.HPState``).

    Raises
    ------
    ValueError
        ``indicators``, ``marked`` and the state's orders without one entry per element, or ``max_order``
        not an integer at least the current largest degree.

    See Also
    --------
    ngdgfric.adapt : The adaptive loop that calls it with ``hp=True``.
    """
    indicators = np.asarray(indicators, dtype=float)
    marked = np.asarray(marked, dtype=bool)
    if not (indicators.shape == marked.shape == state.orders.shape == (mesh.ne,)):
        raise ValueError(f"indicators, marked and orders must have one entry per element ({mesh.ne})")
    if not (isinstance(max_order, (int, np.integer)) and max_order >= state.orders.max()):
        raise ValueError(f"max_order must be an integer >= the current largest order "
                         f"{state.orders.max()}, got {max_order!r}")
    in_p = marked & smooth(indicators, state.predicted) & (state.orders < max_order)
    in_h = marked & ~in_p
    orders = state.orders + in_p
    predicted = np.where(in_p, gamma_p * indicators, gamma_n * state.predicted)
    ne_old = mesh.ne
    if in_h.any():
        graded = in_h & containing(mesh, singular) if layers and singular is not None else None
        refine(mesh, in_h, bisections=2)
        for _ in range(layers if graded is not None and graded.any() else 0):
            parent, _ = refinement_parents(mesh, ne_old)
            refine(mesh, graded[parent] & containing(mesh, singular), bisections=2)
    parent, descendants = refinement_parents(mesh, ne_old)
    descendant = gamma_h * descendants ** -(state.orders + 1.0) * indicators
    predicted = np.where(descendants > 1, descendant, predicted)
    return HPState(orders[parent], predicted[parent])
