"""The DG bilinear forms B_h^(1..5) of Section 3 and the load functional, as one construction.

All five methods share the volume term and the consistency terms

    B_h(u, v) = (sigma_h(u), eps_h(v)) - s <[u], {sigma_h(v)}> - <[v], {sigma_h(u)}> + stabilisation,

with s = +1 except NIPG (s = -1), and differ only in the stabilisation: the edge penalty
eta p^2 / h_e [u]:[v] or the local liftings sum_e eta (C r_e[u], r_e[v]) (:mod:`ngdgfric.liftings`),
and the global lifting (C r_0[u], r_0[v]); the rows are :data:`ngdgfric.methods.METHODS`.

Jumps are the symmetric tensor jumps of Section 2.1, [v] = sym(v+ (x) n+ + v- (x) n-), on
interior edges and [v] = sym(v (x) n) on Dirichlet edges (E_h^o = E_h^i u E_h^D); the
averages are {sigma} = (sigma+ + sigma-)/2 and {sigma} = sigma on the boundary.  For p = 1 the
edge penalty is the paper's eta h_e^-1; for p > 1 it carries the usual factor p_e^2, which keeps
the coercivity threshold of eta independent of h and p up to a constant.  With a variable order
per element (hp), p_e = max(p_T+, p_T-) on interior edges (the inverse trace inequality of the
higher-order neighbour decides coercivity) and p_e = p_T on boundary edges.
"""

import ngsolve as ngs

from .problem import coefficient, strain, stress

__all__ = ["edge_length", "edge_penalty", "edge_order", "dg_terms", "load_terms", "jump_inner"]


def jump_inner(a, b, n):
    """[a]:[b] for symmetric tensor jumps [a] = sym(a (x) n), [b] = sym(b (x) n) with |n| = 1.

    sym(a (x) n) : sym(b (x) n) = (a.b + (a.n)(b.n)) / 2; ``a``, ``b`` are the vector jumps
    v+ - v- (interior edges, n = n+) or v (Dirichlet edges).
    """
    return 0.5 * (a * b + (a * n) * (b * n))


def edge_length(mesh):
    """CoefficientFunction equal to h_e = |e| on every edge of a straight-sided triangle mesh.

    On a facet, NGSolve's ``specialcf.mesh_size`` is |det J_T| / |e| = 2 |T| / |e|, so
    |e| = 2 |T| / mesh_size with the element area |T| stored in an order-0 L2 GridFunction.
    """
    area = ngs.GridFunction(ngs.L2(mesh, order=0))
    area.vec.FV().NumPy()[:] = ngs.Integrate(ngs.CF(1) * ngs.dx, mesh, element_wise=True).NumPy()
    return 2 * area / ngs.specialcf.mesh_size


def edge_penalty(eta, order, h_e):
    """The edge penalty weight eta p^2 / h_e (eta / h_e for p = 1, Section 3).

    ``order``: p (a number) or a CoefficientFunction p_e (see :func:`edge_order`).
    """
    return eta * order * order / h_e


def edge_order(order):
    """p_e on interior edges: ``order`` itself if it is a number, max(p_T+, p_T-) for an element
    order CoefficientFunction (a piecewise constant GridFunction)."""
    if not isinstance(order, ngs.CoefficientFunction):
        return order
    return ngs.IfPos(order - order.Other(), order, order.Other())


def _stress_normal(problem, w, n):
    return stress(problem, strain(w)) * n


def dg_terms(problem, mesh, u, v, method, eta, order, h_e=None):
    """The integrals of B_h(u, v) for the edge-penalty part of ``method`` (Section 3).

    Returns a list of symbolic integrals (one integrator each: NGSolve assembles separate
    skeleton integrators several times faster than their sum).  Lifting terms are added by the
    caller from :mod:`ngdgfric.liftings`.  ``u``, ``v`` are trial and test functions (or any
    vector proxies) of a DG space with ``dgjumps=True``; ``order``: p, or the element order
    GridFunction of a variable-order space.
    """
    s = method.symmetry
    n = ngs.specialcf.normal(2)
    dirichlet = mesh.Boundaries(problem.dirichlet)
    interior = ngs.dx(skeleton=True)
    boundary = ngs.ds(skeleton=True, definedon=dirichlet)
    ju, jv = u - u.Other(), v - v.Other()
    avg_sn = lambda w: 0.5 * (_stress_normal(problem, w, n) + _stress_normal(problem, w.Other(), n))  # noqa: E731
    terms = [
        ngs.InnerProduct(stress(problem, strain(u)), strain(v)) * ngs.dx,
        -s * ju * avg_sn(v) * interior,
        -jv * avg_sn(u) * interior,
        -s * u * _stress_normal(problem, v, n) * boundary,
        -v * _stress_normal(problem, u, n) * boundary,
    ]
    if method.penalty == "edge":
        if h_e is None:
            h_e = edge_length(mesh)
        terms += [edge_penalty(eta, edge_order(order), h_e) * jump_inner(ju, jv, n) * interior,
                  edge_penalty(eta, order, h_e) * jump_inner(u, v, n) * boundary]
    return terms


def load_terms(problem, mesh, v):
    """(f, v) of (1.4): body force on Omega and traction g on Gamma_F."""
    f, g = coefficient(problem.f), coefficient(problem.g)
    terms = [f * v * ngs.dx]
    if problem.traction in mesh.GetBoundaries():
        terms.append(g * v * ngs.ds(skeleton=True, definedon=mesh.Boundaries(problem.traction)))
    return terms
