"""The hp decision: refine a marked element in p where u_h is smooth there, in h where it is not.

Smoothness is judged by the predicted-versus-observed error reduction of Melenk and Wohlmuth
(J. M. Melenk, B. I. Wohlmuth, "On residual-based a posteriori error estimation in hp-FEM",
Adv. Comput. Math. 15 (2001) 311-331, Section 4): every element carries a prediction eta_pred^2
of its indicator, made when it was last changed under the hypothesis that u is smooth (analytic)
there:

* refined in h:        eta_pred^2 = gamma_h n^-(p+1) eta_T^2 for each of its n descendants.  A
                       marked element is bisected twice (:func:`ngdgfric.meshes.refine`): its four
                       grandchildren are similar to it with h/2 and the same orientation, and for
                       a smooth u each carries (1/2)^2p / 4 of the error, Melenk-Wohlmuth's
                       prediction for red refinement.  (After a single bisection the children are
                       rotated by 45 degrees, and for an anisotropic u the error need not fall at
                       all: one bisection cannot tell smooth from singular.)  Closure elements
                       bisected once get n = 2;
* p -> p + 1:          eta_pred^2 = gamma_p eta_T^2 (exponential decay in p);
* unchanged:           eta_pred^2 = gamma_n eta_pred^2,

with Melenk-Wohlmuth's gamma_h = 4, gamma_p = 0.4, gamma_n = 1.

A marked element whose indicator eta_T^2 is at most its prediction is *smooth*: the prediction
made for an analytic u came true, so it is refined in p; otherwise (near corner singularities,
where contact starts, where stick turns into slip) the error fell more slowly than a smooth u
allows, and it is bisected.  The initial prediction is 0: the first step is an h step, after
which the observed reduction decides.  Elements at ``max_order`` are bisected.
"""

from dataclasses import dataclass

import numpy as np

from .dg.spaces import dg_ndof
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
    """Refine the marked elements in h or p (module docstring); returns the new :class:`HPState`.

    ``indicators``: eta_T^2 of the current mesh; ``marked``: Doerfler's set.  The mesh is bisected
    in place (marked h elements twice + closure); p_T is raised by one on the other marked elements.
    ``singular``, ``layers``: a marked h element containing one of the points ``singular`` (where u may be
    singular: :attr:`ngdgfric.domain.Geometry.corners`, and the ends of the contact and stick zones,
    :func:`ngdgfric.contact.transitions`) is refined towards it by ``layers`` more geometric layers in the same
    step (its descendants containing the point bisected twice more, ``layers`` times: h halves per layer), so that
    one level does what ``layers + 1`` levels of single steps would.
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
