"""Lifting operators r_e and r_0 (Arnold, Brezzi, Cockburn, Marini 2002) for B_h^(3), B_h^(4), B_h^(5).

For a symmetric tensor phi on an edge e in E_h^o, r_e(phi) in Sigma_h is defined by

    int_Omega r_e(phi) : tau dx = - int_e phi : {tau} ds      for all tau in Sigma_h,

and r_0 = sum_{e in E_h^o} r_e.  Sigma_h: discontinuous symmetric 2x2 tensors of degree p (the
order of V_h).  It contains eps_h(V_h) (degree p - 1), as ABCM require; degree p rather than
p - 1 because the jumps [v] of V_h are of degree p on the edges, and only then is r_e injective on
them (||r_e([v])|| ~ h_e^-1/2 ||[v]||_e), so that the local lifting penalty of Bassi et al.
controls every jump.

With a varying material {tau} is the weighted average of :mod:`ngdgfric.dg.material` and C is each
element's own (the liftings then match the consistency terms of :mod:`ngdgfric.dg.forms`).

r_e is supported on the (one or two) elements sharing e.  The edges of E_h^o are coloured so that
no triangle has two edges of one colour; for one colour c the liftings of its edges have disjoint
supports, so r_c = sum_{e in c} r_e gives sum_{e in c} (C r_e, r_e) = (C r_c, r_c).  With
R_c the matrix of u -> -int_{edges of c} [u] : {tau}, M the mass matrix of Sigma_h (diagonal on straight
elements: orthogonal L2 basis; a block per curved element) and K the matrix of (C sigma, tau):

    sum_e (C r_e[u], r_e[v]) = sum_c v^T R_c^T M^-1 K M^-1 R_c u,
    (C r_0[u], r_0[v])       = v^T R^T M^-1 K M^-1 R u,        R = sum_c R_c.

Cost: one skeleton form per colour (3-5 colours), each restricted to its edges by a facet
BitArray (``definedonelements``), M and K on Sigma_h without facet couplings, sparse products
scattered into the DG pattern; the global lifting couples each element with its neighbours'
neighbours (a two-ring stencil, about twice the nonzeros).
"""

from typing import NamedTuple

import ngsolve as ngs
import numpy as np

from ..problem import coefficient, stress
from ..sparse import diagonal
from ..threads import threads
from .forms import has_dirichlet_data, normal_part

__all__ = ["lifting_space", "EdgeColour", "edge_colours", "lifting_matrices", "lifting_terms"]


def lifting_space(mesh, order, dgjumps=True):
    """Sigma_h: discontinuous symmetric 2x2 tensors of degree ``order`` (``dgjumps``: with the
    facet couplings in the matrix pattern, for the skeleton forms; the dofs are the same)."""
    return ngs.MatrixValued(ngs.L2(mesh, order=order, dgjumps=dgjumps), dim=2, symmetric=True)


class EdgeColour(NamedTuple):
    """One colour of E_h^o: its facets as a BitArray over the mesh's facet numbers (for
    ``definedonelements``) and as an order-0 facet GridFunction (1 on them, 0 elsewhere)."""

    facets: ngs.BitArray
    indicator: ngs.GridFunction


def edge_colours(problem, mesh):
    """The colours of E_h^o (interior and Dirichlet edges), a list of :class:`EdgeColour`.

    Greedy colouring: an edge may not share a colour with another edge of a triangle it bounds
    (at most 4 such edges, so at most 5 colours).  The edges of every triangle come from the mesh
    topology as facet numbers.  On a refined mesh these include the bisected coarse edges, which
    no triangle has and which get no dof: the order-0 facet space numbers the facets in use in
    increasing order (NGSolve 6.2; checked here by the count and in the tests facet by facet
    against ``GetDofNrs``; ``GetDofNrs`` per element would cost 25 times the colouring).
    """
    space = ngs.FacetFESpace(mesh, order=0)
    edge_of = np.array([[facet.nr for facet in element.facets] for element in mesh.Elements(ngs.VOL)],
                       dtype=np.int64)
    in_use = np.zeros(mesh.nfacet, dtype=bool)
    in_use[edge_of] = True
    numbering = np.cumsum(in_use) - 1
    if numbering[-1] + 1 != space.ndof:
        raise RuntimeError(f"{space.ndof} facet dofs but {numbering[-1] + 1} edges of triangles")
    dof_of_facet = np.where(in_use, numbering, -1)
    on_boundary = np.zeros(space.ndof, dtype=bool)
    for part in ("traction", "contact"):
        on_boundary |= np.array(list(space.GetDofs(mesh.Boundaries(problem.where(part)))), dtype=bool)
    excluded = (dof_of_facet < 0) | on_boundary[dof_of_facet]  # not an edge of the mesh, or on Gamma_F, Gamma_C
    colour = _greedy_colours(edge_of, excluded)
    colours = []
    for k in range(colour.max() + 1):
        indicator = ngs.GridFunction(space)
        indicator.vec.FV().NumPy()[dof_of_facet[colour == k]] = 1.0
        colours.append(EdgeColour(ngs.BitArray(colour == k), indicator))
    return colours


def _greedy_colours(edge_of, excluded):
    """Colours 0, 1, ... of the edges not ``excluded`` (-1 for those), taken in edge order, each
    the smallest that no other edge of its (one or two) triangles has (``edge_of``: the three
    edges of every triangle).  The conflicts are built with numpy, the sequential pass runs on
    Python lists (numpy scalars would be slower)."""
    n_edges = len(excluded)
    first = np.concatenate([edge_of[:, i] for i in (0, 0, 1, 1, 2, 2)])
    other = np.concatenate([edge_of[:, j] for j in (1, 2, 0, 2, 0, 1)])
    order = np.argsort(first, kind="stable")
    first, other = first[order], other[order]
    slot = np.arange(len(first)) - np.searchsorted(first, first)  # position among the edge's conflicts
    conflicts = np.full((n_edges, 4), n_edges)  # n_edges: a sentinel that never has a colour
    conflicts[first, slot] = other
    colour = [-1] * (n_edges + 1)
    for e, (skip, near) in enumerate(zip(excluded.tolist(), conflicts.tolist(), strict=True)):
        if not skip:
            used = {colour[f] for f in near}
            k = 0
            while k in used:
                k += 1
            colour[e] = k
    return np.array(colour[:-1])


def _block_inverse(mat):
    """M^-1 of the mass matrix of Sigma_h, block diagonal with small blocks: diagonal on straight elements
    (orthogonal L2 basis; entries below 1e-13 (m_ii m_jj)^(1/2) are round-off), a block per element and component
    on curved ones.  The blocks are the connected sets of the other rows (labels spread along the entries until
    they settle); blocks of one size are inverted together."""
    values, cols, rowptr = mat.CSR()
    values, cols = np.asarray(values), np.asarray(cols, dtype=np.int64)
    rowptr = np.asarray(rowptr, dtype=np.int64)
    d = diagonal(mat)
    rows = np.repeat(np.arange(mat.height), np.diff(rowptr))
    # an entry couples rows i and j if |m_ij| > 1e-13 (m_ii m_jj)^(1/2): symmetric in i and j (the diagonal varies
    # by orders of magnitude with the degree of the basis function and the size of the element), so a row is
    # coupled exactly when the rows it couples to are (no longer an error on tiny or high-order elements)
    keep = (rows == cols) | (np.abs(values) > 1e-13 * np.sqrt(np.abs(d[rows] * d[cols])))
    rows, cols, values = rows[keep], cols[keep], values[keep]
    single = np.ones(mat.height, dtype=bool)
    single[rows[rows != cols]] = single[cols[rows != cols]] = False  # both ends, whatever the round-off
    coupled = np.flatnonzero(~single)
    index = np.flatnonzero(single)
    out_rows, out_cols, out_values = [index], [index], [1.0 / d[single]]
    if coupled.size:
        inside = ~single[rows]
        rows, cols, values = rows[inside], cols[inside], values[inside]
        for block_rows, block_cols, block_values in _blocks(coupled, rows, cols, values):
            out_rows.append(block_rows)
            out_cols.append(block_cols)
            out_values.append(block_values)
    return ngs.la.SparseMatrixd.CreateFromCOO(np.concatenate(out_rows), np.concatenate(out_cols),
                                              np.concatenate(out_values), mat.height, mat.height)


def _blocks(members, rows, cols, values):
    """The inverses of the diagonal blocks of the matrix (rows, cols, values) on the rows ``members`` (sorted),
    as COO triplets, one per block size."""
    local = np.searchsorted(members, rows), np.searchsorted(members, cols)
    label = np.arange(len(members))
    while True:
        spread = label.copy()
        np.minimum.at(spread, local[0], label[local[1]])
        if np.array_equal(spread, label):
            break
        label = spread
    if np.any(label[local[0]] != label[local[1]]):
        raise RuntimeError("the mass matrix of Sigma_h is not block diagonal")
    order = np.lexsort((np.arange(len(members)), label))
    starts = np.flatnonzero(np.r_[True, np.diff(label[order]) != 0])
    sizes = np.diff(np.r_[starts, len(members)])
    position = np.empty(len(members), dtype=np.int64)
    position[order] = np.arange(len(members)) - np.repeat(starts, sizes)
    block_of = np.empty(len(members), dtype=np.int64)
    block_of[order] = np.repeat(np.arange(len(starts)), sizes)
    for size in np.unique(sizes):
        blocks = np.flatnonzero(sizes == size)
        index = np.full(len(starts), -1)
        index[blocks] = np.arange(len(blocks))
        mine = index[block_of[local[0]]] >= 0
        dense = np.zeros((len(blocks), size, size))
        dense[index[block_of[local[0][mine]]], position[local[0][mine]], position[local[1][mine]]] = values[mine]
        rows_of = members[order[starts[blocks][:, None] + np.arange(size)]]  # (blocks, size)
        yield np.repeat(rows_of, size, axis=1).ravel(), np.tile(rows_of, (1, size)).ravel(), \
            np.linalg.inv(dense).ravel()


def lifting_matrices(problem, material, mesh, V, order, local=True, total=False):
    """(list of R_c, P = M^-1 K M^-1, list of r_c) as NGSolve sparse matrices and vectors (module docstring).

    ``material``: the :class:`~ngdgfric.dg.material.Material` (C element by element in K, and the weights of
    the average {tau}, the same as in the consistency terms of :func:`ngdgfric.dg.forms.dg_terms`);
    ``local``: the matrices R_c of the edge colours; ``total``: append R = sum_c R_c (assembled
    directly, over all of E_h^o).  On symmetry sides the lifting sees the normal part (u . n) n of u
    (:func:`ngdgfric.dg.forms.normal_part`).  r_c: the liftings of the prescribed displacement u_D on Gamma_D
    (the jump there is u - u_D, so r_e[u] = R_c u - r_c), None if u_D = 0.
    """
    S = lifting_space(mesh, order)
    cells = lifting_space(mesh, order, dgjumps=False)  # block-diagonal patterns for M and K
    with threads(V.ndof):
        P = _lifted_stiffness(material, cells)
        trace = _dirichlet_trace(problem, mesh, order)
        colours = edge_colours(problem, mesh) if local else []
        R = [_lifting_matrix(problem, material, mesh, V, S, *colour) for colour in colours]
        r = [_lifted_data(problem, mesh, cells, trace, colour.indicator) for colour in colours]
        if total:
            everywhere = ngs.BitArray(mesh.nfacet)
            everywhere.Set()
            R.append(_lifting_matrix(problem, material, mesh, V, S, everywhere, ngs.CF(1.0)))
            r.append(_lifted_data(problem, mesh, cells, trace, ngs.CF(1.0)))
    return R, P, r


def _lifted_stiffness(material, cells):
    """P = M^-1 K M^-1 on Sigma_h (M the mass matrix, K that of (C sigma, tau), both block diagonal; ``cells``:
    Sigma_h without facet couplings)."""
    sigma, tau = cells.TnT()
    mass = ngs.BilinearForm(cells)
    mass += ngs.InnerProduct(sigma, tau) * ngs.dx
    mass.Assemble()
    stiffness = ngs.BilinearForm(cells)
    stiffness += ngs.InnerProduct(stress(material.own, sigma), tau) * ngs.dx
    stiffness.Assemble()
    m_inv = _block_inverse(mass.mat)
    return m_inv @ stiffness.mat.DeleteZeroElements(0.0) @ m_inv  # C couples not every pair


def _supports(problem, mesh):
    """The measures of Gamma_D and of the symmetry sides (None if the mesh has none) for the lifting forms."""
    dirichlet = ngs.ds(skeleton=True, definedon=mesh.Boundaries(problem.where("dirichlet")))
    symmetry = ngs.ds(skeleton=True, definedon=mesh.Boundaries(problem.where("symmetry"))) \
        if any(name in mesh.GetBoundaries() for name in problem.sides("symmetry")) else None
    return dirichlet, symmetry


def _lifting_matrix(problem, material, mesh, V, S, facets, indicator):
    """R_c: V_h -> Sigma_h of the edges ``facets`` (a BitArray) and the boundary edges where ``indicator`` is 1."""
    u, tau = V.TrialFunction(), S.TestFunction()
    n = ngs.specialcf.normal(2)
    dirichlet, symmetry = _supports(problem, mesh)
    # the skeleton loop visits only the colour's facets (2.6 times faster than multiplying by the indicator on all
    # of them, at 49k DOFs)
    form = ngs.BilinearForm(trialspace=V, testspace=S)
    form += -(u - u.Other()) * (material.average(tau, tau.Other()) * n) * ngs.dx(skeleton=True,
                                                                                 definedonelements=facets)
    form += -indicator * u * (tau * n) * dirichlet
    if symmetry is not None:
        form += -indicator * normal_part(u, n) * (tau * n) * symmetry
    form.Assemble()
    return form.mat.DeleteZeroElements(0.0)  # the pattern holds all facet couplings


def _lifted_data(problem, mesh, cells, trace, indicator):
    """r_c: the lifting of u_D (``trace``, :func:`_dirichlet_trace`) on the Dirichlet edges where ``indicator`` is
    1, a vector on Sigma_h; None if u_D = 0."""
    if trace is None:
        return None
    tau = cells.TestFunction()
    dirichlet, _ = _supports(problem, mesh)
    form = ngs.BilinearForm(trialspace=trace.space, testspace=cells)  # test space S crashed NGSolve
    form += -indicator * trace.space.TrialFunction() * (tau * ngs.specialcf.normal(2)) * dirichlet
    form.Assemble()
    lifted = form.mat.CreateColVector()
    lifted.data = form.mat * trace.vec
    return lifted


def _dirichlet_trace(problem, mesh, order):
    """u_D on Gamma_D as a GridFunction of a vector facet space: its L2 projection onto polynomials of degree
    ``order`` + 2 on every Dirichlet edge (exact for polynomial data of that degree; a LinearForm with the
    symmetric tensor test functions of Sigma_h falls back to an unoptimised path of NGSolve that prints
    "called base class apply trans"), None if u_D = 0."""
    if not has_dirichlet_data(problem):
        return None
    trace = ngs.GridFunction(ngs.FacetFESpace(mesh, order=order + 2) ** 2)
    trace.Set(coefficient(problem.u_D), ngs.BND, definedon=mesh.Boundaries(problem.where("dirichlet")))
    return trace


def lifting_terms(problem, material, mesh, V, order, method, eta):
    """The lifting terms of ``method``: (pairs (weight, sparse matrix on V), to be added to B_h's matrix by
    :func:`ngdgfric.sparse.sparse_sum` (the local terms lie in the DG pattern, so they are scattered into it
    without a union pattern), and the load vector they give a prescribed displacement u_D (None if u_D = 0 or
    the method has no liftings)).

    Bassi et al. (B_h^(3)): eta sum_e (C r_e, r_e); Brezzi et al. (B_h^(4)): that plus
    (C r_0, r_0); LDG (B_h^(5)): (C r_0, r_0).  With [u] = u - u_D on Gamma_D, (C r_e[u], r_e[v]) =
    v^T R^T P (R u - r), so u_D adds eta R^T P r to the right-hand side.
    """
    if method.penalty != "lift" and not method.global_lift:
        return [], None
    local = method.penalty == "lift"
    R, P, r = lifting_matrices(problem, material, mesh, V, order, local=local, total=method.global_lift)
    weights = [eta] * (len(R) - 1 if method.global_lift else len(R)) + [1.0] * method.global_lift
    terms, load = [], None
    with threads(V.ndof):
        for weight, R_c, r_c in zip(weights, R, r, strict=True):
            R_t = R_c.CreateTranspose()
            terms.append((weight, R_t @ P @ R_c))
            if r_c is not None:
                if load is None:
                    load = ngs.BaseVector(V.ndof)
                    load[:] = 0.0
                lifted = r_c.CreateVector()
                lifted.data = P * r_c
                load.data += weight * (R_t * lifted)
    return terms, load
