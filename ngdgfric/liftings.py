"""Lifting operators r_e and r_0 (Arnold, Brezzi, Cockburn, Marini 2002) for B_h^(3), B_h^(4), B_h^(5).

For a symmetric tensor phi on an edge e in E_h^o, r_e(phi) in Sigma_h is defined by

    int_Omega r_e(phi) : tau dx = - int_e phi : {tau} ds      for all tau in Sigma_h,

and r_0 = sum_{e in E_h^o} r_e.  Sigma_h: discontinuous symmetric 2x2 tensors of degree p (the
order of V_h).  It contains eps_h(V_h) (degree p - 1), as ABCM require; degree p rather than
p - 1 because the jumps [v] of V_h are of degree p on the edges, and only then is r_e injective on
them (||r_e([v])|| ~ h_e^-1/2 ||[v]||_e), so that the local lifting penalty of Bassi et al.
controls every jump.

r_e is supported on the (one or two) elements sharing e.  The edges of E_h^o are coloured so that
no triangle has two edges of one colour; for one colour c the liftings of its edges have disjoint
supports, so r_c = sum_{e in c} r_e gives sum_{e in c} (C r_e, r_e) = (C r_c, r_c).  With
R_c the matrix of u -> -int_{edges of c} [u] : {tau}, M the (diagonal: orthogonal L2 basis) mass
matrix of Sigma_h and K the matrix of (C sigma, tau):

    sum_e (C r_e[u], r_e[v]) = sum_c v^T R_c^T M^-1 K M^-1 R_c u,
    (C r_0[u], r_0[v])       = v^T R^T M^-1 K M^-1 R u,        R = sum_c R_c.

Cost: one skeleton form per colour (4-5 colours), sparse products; the global lifting couples
each element with its neighbours' neighbours (a two-ring stencil, about twice the nonzeros).
"""

import ngsolve as ngs
import numpy as np

from .forms import stress
from .linalg import diagonal, sparse_sum, threads

__all__ = ["lifting_space", "edge_colours", "lifting_matrices", "lifting_stiffness"]


def lifting_space(mesh, order):
    """Sigma_h: discontinuous symmetric 2x2 tensors of degree ``order``."""
    return ngs.MatrixValued(ngs.L2(mesh, order=order, dgjumps=True), dim=2, symmetric=True)


def edge_colours(problem, mesh):
    """Order-0 facet GridFunctions, one per colour, marking the edges of E_h^o of that colour.

    Greedy colouring: an edge may not share a colour with another edge of a triangle it bounds
    (at most 4 such edges, so at most 5 colours).  Edges are found from the triangles' vertices with
    numpy and matched to the facet dofs through their midpoints.
    """
    facets = ngs.FacetFESpace(mesh, order=0)
    points = np.asarray(mesh.ngmesh.Coordinates())
    triangles = mesh.ngmesh.Elements2D().NumPy()["nodes"].astype(np.int64) - 1
    pairs = np.sort(np.stack([triangles, np.roll(triangles, -1, axis=1)], axis=2), axis=2)  # (ne, 3, 2)
    edges, edge_of = np.unique(pairs.reshape(-1, 2), axis=0, return_inverse=True)
    edge_of = edge_of.reshape(-1, 3)
    # facet dof of every edge, by matching midpoints
    middle = ngs.GridFunction(facets)
    dof_mid = np.empty((facets.ndof, 2))
    for i, coordinate in enumerate((ngs.x, ngs.y)):
        middle.Set(coordinate, dual=True)
        dof_mid[:, i] = middle.vec.FV().NumPy()
    edge_mid = points[edges].mean(axis=1)
    scale = 1e-6 * np.min(np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1))
    if facets.ndof != len(edges):
        raise RuntimeError(f"{facets.ndof} facet dofs but {len(edges)} edges")
    key = lambda xy: np.round(xy / scale).astype(np.int64)  # noqa: E731
    order_dofs = np.lexsort(key(dof_mid).T[::-1])
    order_edges = np.lexsort(key(edge_mid).T[::-1])
    dof_of_edge = np.empty(len(edges), dtype=np.int64)
    dof_of_edge[order_edges] = order_dofs
    excluded = np.zeros(facets.ndof, dtype=bool)
    for name in (problem.traction, problem.contact):
        excluded |= np.array(list(facets.GetDofs(mesh.Boundaries(name))), dtype=bool)
    # conflicts: the other edges of the (one or two) triangles of every edge
    conflicts = [[] for _ in range(len(edges))]
    for a, b, c in edge_of:
        conflicts[a] += [b, c]
        conflicts[b] += [a, c]
        conflicts[c] += [a, b]
    colour = np.full(len(edges), -1)
    for e in range(len(edges)):
        if excluded[dof_of_edge[e]]:
            continue
        used = {colour[f] for f in conflicts[e]}
        colour[e] = next(k for k in range(6) if k not in used)
    indicators = []
    for k in range(colour.max() + 1):
        gf = ngs.GridFunction(facets)
        gf.vec.FV().NumPy()[dof_of_edge[colour == k]] = 1.0
        indicators.append(gf)
    return indicators


def _diagonal_inverse(mat):
    """M^-1 of a diagonal sparse matrix (the mass matrix of Sigma_h: orthogonal L2 basis)."""
    d = diagonal(mat)
    if abs(np.abs(np.asarray(mat.AsVector())).sum() - np.abs(d).sum()) > 1e-12 * np.abs(d).sum():
        raise RuntimeError("the mass matrix of Sigma_h is not diagonal")
    index = np.arange(mat.height)
    return ngs.la.SparseMatrixd.CreateFromCOO(index, index, 1.0 / d, mat.height, mat.height)


def lifting_matrices(problem, mesh, V, order, local=True, total=False):
    """(list of R_c, P = M^-1 K M^-1) as NGSolve sparse matrices (module docstring).

    ``local``: the matrices R_c of the edge colours; ``total``: append R = sum_c R_c (assembled
    directly, over all of E_h^o).
    """
    S = lifting_space(mesh, order)
    u = V.TrialFunction()
    sigma, tau = S.TnT()
    n = ngs.specialcf.normal(2)
    dirichlet = mesh.Boundaries(problem.dirichlet)
    jump = u - u.Other()
    with threads(V.ndof):
        mass = ngs.BilinearForm(S)
        mass += ngs.InnerProduct(sigma, tau) * ngs.dx
        mass.Assemble()
        stiffness = ngs.BilinearForm(S)
        stiffness += ngs.InnerProduct(stress(problem, sigma), tau) * ngs.dx
        stiffness.Assemble()
        m_inv = _diagonal_inverse(mass.mat)
        P = m_inv @ stiffness.mat.DeleteZeroElements(0.0) @ m_inv  # S has dgjumps: prune the pattern
        def assemble(indicator):
            form = ngs.BilinearForm(trialspace=V, testspace=S)
            form += -indicator * jump * (0.5 * (tau + tau.Other()) * n) * ngs.dx(skeleton=True)
            form += -indicator * u * (tau * n) * ngs.ds(skeleton=True, definedon=dirichlet)
            form.Assemble()
            return form.mat.DeleteZeroElements(0.0)  # the pattern holds all facet couplings

        R = [assemble(colour) for colour in edge_colours(problem, mesh)] if local else []
        if total:
            everywhere = ngs.GridFunction(ngs.FacetFESpace(mesh, order=0))
            everywhere.vec[:] = 1.0
            R.append(assemble(everywhere))
    return R, P


def lifting_stiffness(problem, mesh, V, order, method, eta):
    """The lifting terms of ``method`` as a sparse matrix on V (None if it has none).

    Bassi et al. (B_h^(3)): eta sum_e (C r_e, r_e); Brezzi et al. (B_h^(4)): that plus
    (C r_0, r_0); LDG (B_h^(5)): (C r_0, r_0).
    """
    if method.penalty != "lift" and not method.global_lift:
        return None
    local = method.penalty == "lift"
    R, P = lifting_matrices(problem, mesh, V, order, local=local, total=method.global_lift)
    terms = []
    with threads(V.ndof):
        if local:
            terms += [(eta, R_c.CreateTranspose() @ P @ R_c) for R_c in (R[:-1] if method.global_lift else R)]
        if method.global_lift:
            terms.append((1.0, R[-1].CreateTranspose() @ P @ R[-1]))
    return sparse_sum(terms)
