r"""The geometry of :math:`\Gamma_C` (and of any named boundary part): its edges in a fixed order, the contact Gauss
rule and points, the multiplier space, and multiplier values at the points.

All contact integrals use the same :math:`(p+1)`-point Gauss rule per edge: the discrete problem (3.1) is the one
with :math:`j_\tau` and :math:`j_n` evaluated by this rule.  The multiplier :math:`\lambda_\tau` of Lemma 3.1 lives
in a facet space of degree :math:`p` on :math:`\Gamma_C`; a degree-:math:`p` polynomial is determined by its
:math:`p+1` Gauss values, and the Gauss-rule :math:`L^2` projection onto it is interpolation at those points, so
every pointwise relation (:math:`|\lambda_\tau| \le 1`, :math:`\lambda_\tau u_\tau = |u_\tau|`, the projection
:math:`P_{[-1,1]}`) holds exactly at the Gauss points.  In 2D the tangent of the boundary is
:math:`t = (-n_y, n_x)`.
"""

import ngsolve as ngs
import numpy as np

from ..problem import pattern

__all__ = ["contact_rule", "contact_measure", "side_measure", "facet_space", "normal_tangent", "boundary_edges",
           "contact_edges", "contact_elements", "law_elements", "contact_points", "edge_jacobians",
           "evaluate_on_contact", "multiplier_space", "ContactGauss", "GaussValues"]


def contact_rule(order):
    """The (p+1)-point Gauss rule on edges (exact to degree 2p+1)."""
    return {ngs.SEGM: ngs.IntegrationRule(ngs.SEGM, 2 * order + 1)}


def contact_measure(problem, mesh, order):
    """ds on Gamma_C (skeleton form, as L2 spaces need) with the contact Gauss rule."""
    return side_measure(mesh, problem.where("contact"), order)


def side_measure(mesh, where, order):
    """ds on the sides selected by the region pattern ``where`` (skeleton form) with the contact Gauss rule."""
    return ngs.ds(skeleton=True, definedon=mesh.Boundaries(where), intrules=contact_rule(order))


def normal_tangent():
    """Outward unit normal n and tangent t = (-n_y, n_x) on the boundary."""
    n = ngs.specialcf.normal(2)
    return n, ngs.CF((-n[1], n[0]))


def boundary_edges(problem, mesh, part="contact"):
    """The edges of Gamma_C (or of another boundary ``part``: "dirichlet", "traction", "symmetry") in the order of
    :func:`contact_points` (edge k holds the Gauss points k q ... (k + 1) q - 1): a list of (boundary element, the
    element of the mesh whose edge it is)."""
    sides = set(problem.sides(part))
    return [(el, mesh[el.edges[0]].elements[0]) for el in mesh.Elements(ngs.BND) if el.mat in sides]


def contact_edges(problem, mesh):
    """The numbers of the edges on Gamma_C."""
    return [el.edges[0].nr for el, _ in boundary_edges(problem, mesh)]


def contact_elements(problem, mesh):
    """The numbers of the elements with an edge on Gamma_C."""
    return np.unique(np.array([element.nr for _, element in boundary_edges(problem, mesh)], dtype=np.int64))


def law_elements(problem, mesh):
    """The numbers of the elements with an edge where a contact law acts: on Gamma_C or on a side of a contact pair
    (their degrees set the contact Gauss rule, ``ngdgfric.Contact``)."""
    edges = boundary_edges(problem, mesh) + boundary_edges(problem, mesh, "pair")
    return np.unique(np.array([element.nr for _, element in edges], dtype=np.int64))


def contact_points(problem, mesh, order):
    """The Gauss points of all edges of Gamma_C, mapped, in a fixed order (for evaluation)."""
    return mesh.MapToAllElements(contact_rule(order), mesh.Boundaries(problem.where("contact")))


def edge_jacobians(points):
    """|dx/ds| of the edge mapping at mapped boundary points (the edge length on a straight edge; on a curved
    one the element mapping's, so that sum omega_q v(x_q) is the Gauss rule of the curved edge)."""
    return np.asarray(ngs.Norm(ngs.specialcf.JacobianMatrix(2, 1))(points)).ravel()


def evaluate_on_contact(cf, points, volume=True):
    """Values of ``cf`` at contact Gauss points; ``volume`` for volume (element) functions."""
    if len(points) == 0:  # no foundation (only contact pairs)
        return np.zeros(0) if cf.dim == 1 else np.zeros((0, cf.dim))
    values = (ngs.BoundaryFromVolumeCF(cf) if volume else cf)(points)
    return np.asarray(values).reshape(-1) if cf.dim == 1 else np.asarray(values)


def multiplier_space(problem, mesh, order):
    """Degree-p facet space on Gamma_C for the scalar multiplier lam_tau (the vector multiplier is lam_tau t)."""
    return facet_space(mesh, problem.where("contact"), order)


def facet_space(mesh, where, order):
    """Degree-p facet space on the sides selected by the region pattern ``where``."""
    full = ngs.FacetFESpace(mesh, order=order)
    return ngs.Compress(full, active_dofs=full.GetDofs(mesh.Boundaries(where)))


class ContactGauss:
    """The Gauss points of Gamma_C (or of the sides ``sides``) edge by edge, and multiplier values <-> coefficients.

    points: mapped points (for evaluation); xy: (edges, q, 2) coordinates; ends: (edges, 2, 2)
    edge end points; dofs: (edges, q) dofs of each edge in the facet space ``Q`` on those sides; sides: the name of
    each edge's side; omega: the Gauss weights times |dx/ds| (``edge_jacobians``), edge by edge; dS: the measure
    of those sides with the rule; q = p + 1.
    """

    def __init__(self, mesh, sides, order, Q):
        where = pattern(sides)
        self.points = mesh.MapToAllElements(contact_rule(order), mesh.Boundaries(where))
        self.q = order + 1
        self.dS = side_measure(mesh, where, order)
        self.xy = np.column_stack([np.asarray(ngs.x(self.points)).ravel(),
                                   np.asarray(ngs.y(self.points)).ravel()]).reshape(-1, self.q, 2)
        edges = [el for el in mesh.Elements(ngs.BND) if el.mat in set(sides)]
        weights = np.asarray(contact_rule(order)[ngs.SEGM].weights)
        self.omega = np.tile(weights, len(edges)) * edge_jacobians(self.points)
        ends = [[mesh[v].point for v in el.vertices] for el in edges]
        dofs = [list(Q.GetDofNrs(el)) for el in edges]
        self.sides = [el.mat for el in edges]
        self.ends = np.asarray(ends, dtype=float).reshape(-1, 2, 2)
        self.dofs = np.asarray(dofs, dtype=np.int64).reshape(-1, self.q)
        self.Q = Q
        # Vandermonde matrices: column k holds the values of every edge's k-th basis function
        probe = ngs.GridFunction(Q)
        self.vandermonde = np.empty((len(self.dofs), self.q, self.q))
        for k in range(self.q):
            probe.vec[:] = 0.0
            probe.vec.FV().NumPy()[self.dofs[:, k]] = 1.0
            self.vandermonde[:, :, k] = self.values(probe)

    def values(self, lam_tau):
        """Values of a multiplier GridFunction at the Gauss points, shape (edges, q)."""
        return np.asarray(lam_tau(self.points)).reshape(-1, self.q)

    def set_values(self, lam_tau, values):
        """Set the multiplier GridFunction to the degree-p polynomials with these Gauss values."""
        coefficients = np.linalg.solve(self.vandermonde, np.asarray(values).reshape(-1, self.q, 1))[..., 0]
        lam_tau.vec.FV().NumPy()[self.dofs.ravel()] = coefficients.ravel()

    def snapshot(self, lam_tau):
        """The multiplier's Gauss values with the edge geometry, independent of the mesh."""
        return GaussValues(self.xy, self.ends, self.values(lam_tau))


class GaussValues:
    """A piecewise degree-p function on Gamma_C given by its values at the Gauss points of each edge."""

    def __init__(self, xy, ends, values):
        self.xy, self.ends, self.values = np.asarray(xy), np.asarray(ends), np.asarray(values)
        self.q = self.values.shape[1]

    def edge_parameters(self, xy):
        """For points xy (n, 2) on Gamma_C: the edge containing each and the parameter s in [0, 1]."""
        a, b = self.ends[:, 0], self.ends[:, 1]
        d = b - a
        s = np.einsum("nek,ek->ne", xy[:, None, :] - a[None], d) / np.sum(d * d, axis=1)
        foot = a[None] + s[..., None] * d[None]
        distance = np.linalg.norm(xy[:, None, :] - foot, axis=2) + 1e-12 * (np.abs(s - 0.5) > 0.5 + 1e-9)
        edge = np.argmin(distance, axis=1)
        return edge, np.clip(s[np.arange(len(xy)), edge], 0.0, 1.0)

    def __call__(self, xy):
        """Values at points xy (n, 2) on Gamma_C (Lagrange interpolation through each edge's Gauss nodes)."""
        xy = np.asarray(xy).reshape(-1, 2)
        if len(xy) == 0:
            return np.zeros(0)
        edge, s = self.edge_parameters(xy)
        a = self.ends[edge, 0]
        d = self.ends[edge, 1] - a
        nodes = np.einsum("nqk,nk->nq", self.xy[edge] - a[:, None], d) / np.sum(d * d, axis=1)[:, None]
        result = np.zeros(len(xy))
        for j in range(self.q):
            basis = np.ones(len(xy))
            for m in range(self.q):
                if m != j:
                    basis *= (s - nodes[:, m]) / (nodes[:, j] - nodes[:, m])
            result += basis * self.values[edge, j]
        return result
