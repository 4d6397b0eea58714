r"""Dirichlet data no polynomial reproduces: a lifting of what the potential misses, and its energy.

The equilibrated bound (:mod:`ngdgfric.equilibration`) tests the variational inequality with a displacement that
equals :math:`u_D` on :math:`\Gamma_D`.  The potential :math:`s` interpolates :math:`u_D` exactly at the vertices of
:math:`\Gamma_D` (``set_dirichlet_vertices``) and approximates it in between; what it misses on a Dirichlet edge
:math:`e = AB`, :math:`d = u_D - s` with :math:`d(A) = d(B) = 0`, is lifted into the triangle :math:`T` of the edge
(vertex :math:`a` opposite :math:`e`) by

.. math::

    \ell(x(\tau, r)) = (1 - r)\, d(A + \tau (B - A)), \qquad x(\tau, r) = (1 - r)(A + \tau (B - A)) + r a,

which vanishes on the two other edges of :math:`T` (they are mapped to :math:`A` and :math:`B`, where :math:`d = 0`)
and outside :math:`T`: :math:`s + \ell` is continuous and equals :math:`u_D` on :math:`\Gamma_D`.  Its gradient
does not depend on :math:`r`: with :math:`D = \det(B - A, a - A)` and :math:`v^\perp = (v_y, -v_x)`, component by
component :math:`\nabla \ell_c = (d_c' (a - A - \tau (B - A))^\perp + d_c (B - A)^\perp) / D`,
and :math:`|\det \partial x / \partial(\tau, r)| = (1 - r) |D|`, so

.. math::

    \|C^{1/2} \varepsilon(\ell)\|_T^2 = \frac{|D|}{2} \int_0^1 2 \mu |\varepsilon(\ell)|^2 + \lambda
    (\operatorname{tr} \varepsilon(\ell))^2 \, d\tau,

a one-dimensional integral along the edge.  :math:`d' = \partial_\tau d` is taken from a Chebyshev interpolant of
:math:`d` of degree ``DEGREE`` along the edge (any CoefficientFunction :math:`u_D`, no symbolic derivative needed).
"""

import ngsolve as ngs
import numpy as np
from numpy.polynomial import chebyshev

from .bounds import coefficient
from .contact.boundary import boundary_edges

__all__ = ["dirichlet_vertex_values", "set_dirichlet_vertices", "lifting_energies", "DEGREE"]

DEGREE = 24  # Chebyshev interpolant of u_D - s along a Dirichlet edge (u_D - s is smooth there by assumption)


def _edge_points(problem, mesh, parameters):
    """Mapped points at ``parameters`` in [0, 1] on every Dirichlet edge, in the order of
    ``boundary_edges(problem, mesh, "dirichlet")``."""
    rule = ngs.IntegrationRule([(float(t),) for t in parameters], [0.0] * len(parameters))
    return mesh.MapToAllElements({ngs.SEGM: rule}, mesh.Boundaries(problem.where("dirichlet")))


def _values(cf, points, count, volume=False):
    """Values of a (vector) CoefficientFunction at mapped boundary points, shape (edges, count, dim)."""
    values = np.asarray((ngs.BoundaryFromVolumeCF(cf) if volume else cf)(points))
    return values.reshape(-1, count, cf.dim)


def dirichlet_vertex_values(problem, mesh):
    """({vertex number: u_D there}, the largest disagreement of u_D between the Dirichlet edges that meet at a vertex
    relative to the largest |u_D| at a vertex: 0 for data continuous along Gamma_D)."""
    edges = boundary_edges(problem, mesh, "dirichlet")
    if not edges:
        return {}, 0.0
    points = _edge_points(problem, mesh, (0.0, 1.0))
    ends = _values(coefficient(problem.u_D), points, 2)
    xy = np.column_stack([np.asarray(ngs.x(points)).ravel(), np.asarray(ngs.y(points)).ravel()]).reshape(-1, 2, 2)
    values, spread = {}, 0.0
    for (element, _), at, value in zip(edges, xy, ends, strict=True):
        for vertex in mesh[element].vertices:
            here = value[np.argmin(np.linalg.norm(at - np.array(mesh[vertex].point), axis=1))]
            if vertex.nr in values:
                spread = max(spread, float(np.max(np.abs(values[vertex.nr] - here))))
            values[vertex.nr] = here
    scale = max(max(float(np.max(np.abs(v))) for v in values.values()), 1e-300)
    return values, spread / scale


def set_dirichlet_vertices(problem, mesh, s):
    """Set the vertex values of the continuous GridFunction ``s`` on Gamma_D to u_D there, exactly."""
    for vertex, value in dirichlet_vertex_values(problem, mesh)[0].items():
        s.vec.FV().NumPy()[list(s.space.GetDofNrs(ngs.NodeId(ngs.VERTEX, vertex)))] = value


def lifting_energies(problem, mesh, s, mu, lam):
    """Upper bounds of ||C^1/2 eps(l)||_T^2 of the lifting of u_D - s (module docstring) for every element (zero
    where T has no Dirichlet edge), a numpy array in element order.  ``mu``, ``lam``: per element, the largest Lame
    parameters on it (exact for constant ones).  An element with two Dirichlet edges (a corner of Gamma_D) gets
    (L_1 + L_2)^2, the triangle inequality for the sum of the two edges' liftings."""
    roots = np.zeros(mesh.ne)
    edges = boundary_edges(problem, mesh, "dirichlet")
    if not edges:
        return roots
    nodes = 0.5 - 0.5 * np.cos(np.pi * (np.arange(DEGREE + 1) + 0.5) / (DEGREE + 1))  # Chebyshev, on [0, 1]
    gauss, weights = np.polynomial.legendre.leggauss(DEGREE)
    gauss, weights = (gauss + 1) / 2, weights / 2
    points = _edge_points(problem, mesh, np.concatenate([nodes, gauss]))
    count = len(nodes) + len(gauss)
    misses = _values(coefficient(problem.u_D), points, count) - _values(s, points, count, volume=True)
    xy = np.column_stack([np.asarray(ngs.x(points)).ravel(), np.asarray(ngs.y(points)).ravel()]).reshape(-1, count, 2)
    for k, (element, volume) in enumerate(edges):
        A, B = (np.array(mesh[v].point) for v in mesh[element].vertices)
        a = next(np.array(mesh[v].point) for v in mesh[volume].vertices if v not in mesh[element].vertices)
        tangent = B - A
        tau = (xy[k] - A) @ tangent / (tangent @ tangent)  # the rule's points may run from B to A
        fit = chebyshev.chebfit(2 * tau[:len(nodes)] - 1, misses[k, :len(nodes)], DEGREE)
        at = tau[len(nodes):]
        d, slope = misses[k, len(nodes):], 2 * chebyshev.chebval(2 * at - 1, chebyshev.chebder(fit)).T
        other = a - A - at[:, None] * tangent
        D = tangent[0] * (a - A)[1] - tangent[1] * (a - A)[0]
        # grad l (rows: components) = (d' other^perp + d tangent^perp) / D, v^perp = (v_y, -v_x)
        grad = (slope[:, :, None] * np.stack([other[:, 1], -other[:, 0]], axis=1)[:, None, :]
                + d[:, :, None] * np.array([tangent[1], -tangent[0]])[None, None, :]) / D
        strain = 0.5 * (grad + grad.transpose(0, 2, 1))
        density = (2 * mu[volume.nr] * np.sum(strain**2, axis=(1, 2))
                   + lam[volume.nr] * np.trace(strain, axis1=1, axis2=2) ** 2)
        roots[volume.nr] += (abs(D) / 2 * np.sum(weights * density)) ** 0.5
    return roots**2
