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

All this needs :math:`u_D` continuous along :math:`\Gamma_D`: a jump is not the trace of an :math:`H^1`
displacement, and no lifting of finite energy exists.  ``dirichlet_jumps`` looks for jumps where two Dirichlet
edges meet and inside every edge, by sampling and halving: a difference of :math:`u_D` that departs from the
differences beside it by the same amount however short the interval is a jump; where :math:`u_D` is continuous (also
at a kink, a steep layer or a cusp) the departure goes to zero with the interval.
"""

from typing import NamedTuple

import ngsolve as ngs
import numpy as np
from numpy.polynomial import chebyshev

from .bounds import coefficient
from .contact.boundary import boundary_edges

__all__ = ["dirichlet_vertex_values", "dirichlet_jumps", "Jump", "set_dirichlet_vertices", "lifting_energies",
           "DEGREE", "SAMPLES", "BISECTIONS", "SETTLE", "MAX_INTERVALS"]

DEGREE = 24  # Chebyshev interpolant of u_D - s along a Dirichlet edge (u_D - s is smooth there by assumption)
SAMPLES = 32  # intervals per Dirichlet edge on which dirichlet_jumps samples u_D
BISECTIONS = 40  # halvings of a sampling interval, down to 2^-45 of the edge (some 30-100 ulps of a coordinate)
SETTLE = 20  # the last halvings over which a jump's departure stays within 10 %
MAX_INTERVALS = 200_000  # intervals followed at once (those departing most), for u_D oscillating very fast


class Jump(NamedTuple):
    """A jump of u_D on Gamma_D (:func:`dirichlet_jumps`)."""

    size: float  #: the jump relative to the largest |u_D| sampled on Gamma_D (largest component)
    point: tuple  #: (x, y) where it jumps
    where: str  #: "inside the Dirichlet side 'a'" or "where the Dirichlet sides 'a' and 'b' meet"


def _edge_points(problem, mesh, parameters, edge=None):
    """Mapped points on the Dirichlet edges (numbered in the order of ``boundary_edges(problem, mesh, "dirichlet")``):
    at ``parameters`` in [0, 1] on every edge, edge by edge, or, given ``edge``, point i at ``parameters[i]`` on
    edge ``edge[i]``."""
    one = mesh.MapToAllElements({ngs.SEGM: ngs.IntegrationRule([(0.0,)], [0.0])},
                                mesh.Boundaries(problem.where("dirichlet")))
    if edge is None:
        edge, parameters = np.repeat(np.arange(len(one)), len(parameters)), np.tile(parameters, len(one))
    points = one[np.asarray(edge, dtype=int)]
    points["x"] = parameters
    return points


def _values(cf, points, count, volume=False):
    """Values of a (vector) CoefficientFunction at mapped boundary points, shape (edges, count, dim)."""
    values = np.asarray((ngs.BoundaryFromVolumeCF(cf) if volume else cf)(points))
    return values.reshape(-1, count, cf.dim)


def _coordinates(points, count):
    """(x, y) of mapped points, shape (edges, count, 2)."""
    return np.column_stack([np.asarray(ngs.x(points)).ravel(), np.asarray(ngs.y(points)).ravel()]).reshape(-1,
                                                                                                          count, 2)


def _ends(mesh, edges, xy):
    """For every Dirichlet edge, its two vertex numbers in the order of the first and last of ``xy``."""
    ends = []
    for (element, _), at in zip(edges, xy, strict=True):
        vertices = mesh[element].vertices
        ends.append([min(vertices, key=lambda v, p=p: np.linalg.norm(p - np.array(mesh[v].point))).nr
                     for p in (at[0], at[-1])])
    return ends


def dirichlet_vertex_values(problem, mesh):
    """{vertex number: u_D there} for the vertices of Gamma_D (where two Dirichlet edges disagree, the value of the
    later one; :func:`dirichlet_jumps` reports the disagreement)."""
    edges = boundary_edges(problem, mesh, "dirichlet")
    if not edges:
        return {}
    points = _edge_points(problem, mesh, (0.0, 1.0))
    values = _values(coefficient(problem.u_D), points, 2)
    ends = _ends(mesh, edges, _coordinates(points, 2))
    return {vertex: value[j] for pair, value in zip(ends, values, strict=True) for j, vertex in enumerate(pair)}


def dirichlet_jumps(problem, mesh, admissible):
    """The jumps of u_D along Gamma_D larger than ``admissible`` (relative to the largest |u_D| sampled there), the
    largest first: a list of :class:`Jump`, empty for u_D continuous along Gamma_D.

    Where two Dirichlet edges meet, their own values of u_D at the common vertex are compared (u_D given per side
    differs there).  Inside every edge u_D is sampled on ``SAMPLES`` equal intervals; an interval is kept while its
    difference of u_D departs from the mean of the differences beside it (of the same width; at an end of the edge,
    from the line through the two on its one side) by more than ``admissible``, and its halves are checked in turn,
    ``BISECTIONS`` times, down to 2^-45 of the edge.  The departure is a third difference of u_D, O(w^3) on an
    interval of width w where u_D is smooth, O(w) at a kink, O(w^a) at a cusp |y - c|^a, and the jump itself where
    u_D jumps: a jump is a departure that still exceeds ``admissible`` at the end and changed by less than 10 % over
    the last ``SETTLE`` halvings (a cusp's shrinks by 2^-10a).  Several jumps are told apart down to 1e-9 of the
    edge; jumps that cancel within one sampling interval (1/``SAMPLES`` of the edge) are not seen.
    """
    edges = boundary_edges(problem, mesh, "dirichlet")
    if not edges:
        return []
    u_D = coefficient(problem.u_D)
    points = _edge_points(problem, mesh, np.linspace(0.0, 1.0, SAMPLES + 1))
    samples, xy = _values(u_D, points, SAMPLES + 1), _coordinates(points, SAMPLES + 1)
    scale = max(float(np.max(np.abs(samples))), 1e-300)
    return sorted(_vertex_jumps(problem, mesh, edges, samples, xy, scale, admissible)
                  + _inside_jumps(problem, mesh, edges, samples, scale, admissible), reverse=True)


def _vertex_jumps(problem, mesh, edges, samples, xy, scale, admissible):
    """The jumps of u_D between two Dirichlet edges at their common vertex (``dirichlet_jumps``)."""
    seen, jumps = {}, []
    for (element, _), pair, value in zip(edges, _ends(mesh, edges, xy), samples, strict=True):
        for vertex, here in zip(pair, (value[0], value[-1]), strict=True):
            if vertex in seen:
                side, there = seen[vertex]
                size = float(np.max(np.abs(here - there))) / scale
                if size > admissible:
                    where = (f"where the Dirichlet sides '{min(side, element.mat)}' and '{max(side, element.mat)}' "
                             "meet" if side != element.mat else f"between two edges of the Dirichlet side '{side}'")
                    jumps.append(Jump(size, tuple(mesh[ngs.NodeId(ngs.VERTEX, vertex)].point), where))
            seen[vertex] = element.mat, here
    return jumps


def _departures(before, here, after, far_before, far_after, has_before, has_after):
    """How far the differences ``here`` of u_D over some intervals depart from the mean of the differences
    ``before`` and ``after`` over their neighbours of the same width (arrays of shape (intervals, dim)), or, where a
    neighbour is missing (``has_before``, ``has_after`` False: the end of an edge), from the line through the two
    differences on the other side."""
    beside = np.where(has_after[:, None], np.where(has_before[:, None], (before + after) / 2, 2 * after - far_after),
                      2 * before - far_before)
    return here - beside


def _inside_jumps(problem, mesh, edges, samples, scale, admissible):
    """The jumps of u_D inside the Dirichlet edges, by halving the sampling intervals (``dirichlet_jumps``)."""
    u_D, limit, dim = coefficient(problem.u_D), admissible * scale, samples.shape[2]
    steps, k = np.diff(samples, axis=1), np.arange(SAMPLES)  # steps[e, k]: over interval k of edge e
    near = [steps[:, np.clip(k + shift, 0, SAMPLES - 1)].reshape(-1, dim) for shift in (-2, -1, 1, 2)]
    first, last = np.tile(k == 0, len(edges)), np.tile(k == SAMPLES - 1, len(edges))
    departure = _departures(near[1], steps.reshape(-1, dim), near[2], near[0], near[3], ~first, ~last)
    edge, a, width = np.repeat(np.arange(len(edges)), SAMPLES), np.tile(k / SAMPLES, len(edges)), np.full(
        len(first), 1 / SAMPLES)
    u_a, u_b = samples[:, :-1].reshape(-1, dim), samples[:, 1:].reshape(-1, dim)
    low, high = np.full(len(a), np.inf), np.zeros(len(a))  # the departure's range over the last SETTLE levels
    for level in range(BISECTIONS + 1):
        size = np.max(np.abs(departure), axis=1)
        keep = np.flatnonzero(size > limit)
        keep = keep[np.argsort(size[keep])[-MAX_INTERVALS:]]
        edge, a, width, u_a, u_b, departure, size, low, high = (
            v[keep] for v in (edge, a, width, u_a, u_b, departure, size, low, high))
        if level >= BISECTIONS - SETTLE:
            low, high = np.minimum(low, size), np.maximum(high, size)
        if level == BISECTIONS or not len(a):
            break
        half = width / 2
        t = np.clip(a[:, None] + half[:, None] * np.array([-1, 1, 3]), 0.0, 1.0)
        u_0, u_m, u_4 = _values(u_D, _edge_points(problem, mesh, t.ravel(), np.repeat(edge, 3)), 3).transpose(1, 0, 2)
        d = u_a - u_0, u_m - u_a, u_b - u_m, u_4 - u_b
        has_before, has_after, present = a - half >= 0, a + 3 * half <= 1, np.ones(len(a), dtype=bool)
        departure = np.concatenate([_departures(d[0], d[1], d[2], d[0], d[3], has_before, present),
                                    _departures(d[1], d[2], d[3], d[0], d[3], present, has_after)])
        edge, a, width = np.tile(edge, 2), np.concatenate([a, a + half]), np.tile(half, 2)
        u_a, u_b, low, high = np.concatenate([u_a, u_m]), np.concatenate([u_m, u_b]), np.tile(low, 2), np.tile(high, 2)
    jump = high <= 1.1 * low  # a jump keeps its size; what a kink or a cusp leaves shrinks
    return _apart(problem, mesh, edges, edge[jump], a[jump] + width[jump] / 2, size[jump] / scale)


def _apart(problem, mesh, edges, edge, at, size):
    """One :class:`Jump` for each group of jumps found within 1e-9 of an edge of each other (the largest of the
    group: a jump makes its neighbours depart by half its size), at the parameters ``at`` of the edges ``edge``."""
    if not len(at):
        return []
    order = np.lexsort((at, edge))
    edge, at, size = edge[order], at[order], size[order]
    starts = np.flatnonzero(np.concatenate([[True], (np.diff(edge) != 0) | (np.diff(at) > 1e-9)]))
    chosen = [start + int(np.argmax(group)) for start, group in zip(starts, np.split(size, starts[1:]), strict=True)]
    xy = _coordinates(_edge_points(problem, mesh, at[chosen], edge[chosen]), 1)[:, 0]
    return [Jump(float(size[i]), tuple(map(float, point)), f"inside the Dirichlet side '{edges[edge[i]][0].mat}'")
            for i, point in zip(chosen, xy, strict=True)]


def set_dirichlet_vertices(problem, mesh, s):
    """Set the vertex values of the continuous GridFunction ``s`` on Gamma_D to u_D there, exactly."""
    for vertex, value in dirichlet_vertex_values(problem, mesh).items():
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
    xy = _coordinates(points, count)
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
