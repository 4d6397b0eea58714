"""The lifting terms of Bassi et al., Brezzi et al. and LDG straight from their definition, edge by edge, dense:
the oracle that tests/test_liftings.py holds ngdgfric.dg.liftings (moments, kernels, block scatter) against.

For every edge e of E_h^o and of the symmetry sides, R_e: V_h -> Sigma_h is the matrix of
u -> -int_e [u] : {tau} ds (tau in Sigma_h, the weighted average of ngdgfric.dg.material, the normal part on
symmetry sides), assembled by NGSolve on that edge alone; then, with M and K the mass matrices of
Sigma_h for (sigma, tau) and (C sigma, tau), (C r_e[u], r_e[v]) = v^T R_e^T M^-1 K M^-1 R_e u, and r_0 = sum_e r_e.
u_D on a Dirichlet edge gives R_e u_D = -int_e (u_D (x) n) : tau ds (u_D interpolated on the edges in degree
p + 4).  Only for small meshes.
"""

import ngsolve as ngs
import numpy as np

from ngdgfric.dg.forms import dg_terms, load_terms, normal_part
from ngdgfric.meshes import facet_indicator
from ngdgfric.problem import coefficient, stress


def dense(mat):
    return mat.ToDense().NumPy().copy()


def _edges(problem, mesh):
    """(facet BitArray, order-0 facet indicator) of every edge of E_h^o and of the symmetry sides."""
    space = ngs.FacetFESpace(mesh, order=0)
    off = sum(facet_indicator(mesh, problem.where(part)).vec.FV().NumPy() for part in ("traction", "contact"))
    for facet in range(mesh.nfacet):
        dofs = space.GetDofNrs(ngs.NodeId(ngs.FACET, facet))
        if len(dofs) == 1 and off[dofs[0]] < 0.5:
            indicator = ngs.GridFunction(space)
            indicator.vec.FV().NumPy()[dofs[0]] = 1.0
            bits = ngs.BitArray(mesh.nfacet)
            bits.Clear()
            bits.Set(facet)
            yield bits, indicator


def lifting_parts(disc):
    """P = M^-1 K M^-1 and, one edge after the other, (rows, R_e on them, R_e u_D) (R_e vanishes outside the rows
    of its elements; R_e u_D is zero off Gamma_D), dense."""
    problem, mesh, material = disc.problem, disc.mesh, disc.material
    S, cells = (ngs.MatrixValued(ngs.L2(mesh, order=disc.order, dgjumps=jumps), dim=2, symmetric=True)
                for jumps in (True, False))  # the same dofs; a mixed boundary form with facet couplings crashed
    sigma, tau = S.TnT()
    mass, stiffness = ngs.BilinearForm(S), ngs.BilinearForm(S)
    mass += ngs.InnerProduct(sigma, tau) * ngs.dx
    stiffness += ngs.InnerProduct(stress(material.own, sigma), tau) * ngs.dx
    mass.Assemble()
    stiffness.Assemble()
    m_inv = np.linalg.inv(dense(mass.mat))
    P = m_inv @ dense(stiffness.mat) @ m_inv
    u, n = disc.V.TrialFunction(), ngs.specialcf.normal(2)
    dirichlet = facet_indicator(mesh, problem.where("dirichlet"))
    symmetry = facet_indicator(mesh, problem.where("symmetry"))
    trace = ngs.GridFunction(ngs.FacetFESpace(mesh, order=disc.order + 4) ** 2)  # u_D, exact for the examples' data
    trace.Set(coefficient(problem.u_D), ngs.BND, definedon=mesh.Boundaries(problem.where("dirichlet")))

    def edges():
        for bits, edge in _edges(problem, mesh):
            form = ngs.BilinearForm(trialspace=disc.V, testspace=S)
            form += -(u - u.Other()) * (material.average(tau, tau.Other()) * n) * ngs.dx(skeleton=True,
                                                                                          definedonelements=bits)
            form += -edge * (dirichlet * u + symmetry * normal_part(u, n)) * (tau * n) * ngs.ds(skeleton=True)
            form.Assemble()
            data = ngs.BilinearForm(trialspace=trace.space, testspace=cells)  # R_e u_D = -int_e u_D . (tau n)
            data += -edge * dirichlet * trace.space.TrialFunction() * (cells.TestFunction() * n) * \
                ngs.ds(skeleton=True)
            data.Assemble()
            near, rows = _rows(form.mat)
            lifted = np.zeros(S.ndof)
            data_rows, data_block = _rows(data.mat)
            lifted[data_rows] = data_block @ trace.vec.FV().NumPy()
            yield near, rows, lifted

    return P, edges()


def _rows(mat):
    """(rows, dense block): the rows of a sparse matrix that hold entries, and those rows as a dense array."""
    rows, cols, values = (np.asarray(x) for x in mat.COO())
    near = np.unique(rows)
    block = np.zeros((len(near), mat.width))
    np.add.at(block, (np.searchsorted(near, rows), cols), values)
    return near, block


def reference_parts(disc):
    """(sum_e R_e^T P R_e, sum_e R_e^T P R_e u_D, R^T P R, R^T P R u_D) with R = sum_e R_e over the edges of E_h^o
    and the symmetry sides, dense (module docstring); R_e vanishes outside the rows of its two elements."""
    P, edges = lifting_parts(disc)
    n = disc.V.ndof
    local_matrix, local_load = np.zeros((n, n)), np.zeros(n)
    triplets, data_total = [], np.zeros(P.shape[0])
    for near, rows, lifted in edges:
        support = np.union1d(near, np.flatnonzero(lifted))  # R_e's rows, and its columns:
        cols = np.flatnonzero(np.abs(rows).sum(axis=0))
        R = np.zeros((len(support), len(cols)))
        R[np.searchsorted(support, near)] = rows[:, cols]
        block = R.T @ P[np.ix_(support, support)]
        local_matrix[np.ix_(cols, cols)] += block @ R
        local_load[cols] += block @ lifted[support]
        r, c = np.nonzero(rows)
        triplets.append((near[r], c, rows[r, c]))
        data_total += lifted
    rows_total, cols_total, values_total = (np.concatenate(x) for x in zip(*triplets, strict=True))
    R = ngs.la.SparseMatrixd.CreateFromCOO(rows_total, cols_total, values_total, P.shape[0], n)
    r, c = np.nonzero(P)
    sparse_P = ngs.la.SparseMatrixd.CreateFromCOO(r, c, P[r, c], *P.shape)
    global_matrix = dense(R.CreateTranspose() @ (sparse_P @ R))
    x = R.CreateColVector()
    x.FV().NumPy()[:] = P @ data_total
    y = R.CreateRowVector()
    y.data = R.T * x
    return local_matrix, local_load, global_matrix, y.FV().NumPy().copy()


def reference_system(disc, parts=None):
    """(A, F) of the discretisation's method from the definition (module docstring), dense and numpy: B_h's form
    and load with weight (C r[u - u_D], r[v]) = weight v^T R^T P (R u - R u_D) added (``parts``: those of
    :func:`reference_parts`, computed if not given)."""
    method = disc.method
    u, v = disc.V.TnT()
    a = ngs.BilinearForm(disc.V)
    for term in dg_terms(disc.forms, u, v):
        a += term
    a.Assemble()
    f = ngs.LinearForm(disc.V)
    for term in load_terms(disc.forms, v):
        f += term
    f.Assemble()
    A, F = dense(a.mat), f.vec.FV().NumPy().copy()
    local_matrix, local_load, global_matrix, global_load = reference_parts(disc) if parts is None else parts
    if method.penalty == "lift":
        A = A + float(disc.penalty.boundary) * local_matrix
        F = F + float(disc.penalty.boundary) * local_load
    if method.global_lift:
        A, F = A + global_matrix, F + global_load
    return A, F
