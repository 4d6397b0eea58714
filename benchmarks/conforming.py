"""The conforming baseline: the contact problem (1.4)-(1.10) by plain H1 finite elements, solved exactly.

What a user of NGSolve would write instead of ngdgfric, as fast as we could make it, to measure the
package against (issue 28).  It reads the problem data from an ``ngdgfric.ContactProblem`` and uses
nothing else of the package: its own forms, contact solver, estimator and marking.

PDE (paper, Section 1): -div sigma(u) = f in Omega, sigma = lam tr(eps) I + 2 mu eps, u = u_D on
Gamma_D, sigma n = g on Gamma_F, and on Gamma_C with the outward normal n and t = (-n_y, n_x):

    sigma_n = -c_n (u_n - g_a)_+^{m_n}                                  (1.8)
    |sigma_tau| <= c_tau,  sigma_tau = -c_tau lam_tau,  lam_tau u_tau = |u_tau|   (1.9), m_t = 0

(the reduced law (1.10): the friction bound is c_tau on all of Gamma_C, as in ngdgfric).

Discretisation.  u_h in the H1 vector space of degree p (NGSolve's ``VectorH1``, hierarchical basis,
static condensation of the cell bubbles).  The contact integrals j_n and j_tau use the (p+1)-point
Gauss-Lobatto rule on every edge of Gamma_C: its points are the K = p E_C + 1 nodes of the degree-p
trace space, so the tangential and normal trace values at the points,

    y_t,k = u_h(x_k) . t,    y_n,k = u_h(x_k) . n,

are a basis change of the trace dofs (u = T y, T the identity away from Gamma_C).  In the variables y the
discrete problem is a finite-dimensional one with point-wise laws, omega_k the quadrature weights:

    (T^T A T y - T^T F)_n,k + omega_k c_n (y_n,k - g_a)_+^{m_n} = 0,
    (T^T A T y - T^T F)_t,k + phi_k = 0,   |phi_k| <= s_k = omega_k c_tau,   phi_k y_t,k = s_k |y_t,k|.

Solver.  Semismooth Newton for the Alart-Curnier function phi_k = P_[-s_k, s_k](phi_k + r_k y_t,k) (the
primal-dual active set method; Hintermueller, Ito & Kunisch 2002, Hueber, Stadler & Wohlmuth 2008):
every step fixes y_t,k = 0 at the sticking points (Dirichlet dofs in the variables y), puts phi_k =
s_k sign at the slipping ones, linearises the compliance at the penetrating ones and solves one
sparse SPD system (sparse Cholesky).  It stops when the sets repeat (m_n = 1: then the laws hold
exactly, to the round-off of the linear solve) and the compliance Newton update is at round-off
(m_n > 1).  No regularisation.  Warm start: u_h and lam_tau of the previous level, prolongated.

Adaptivity.  Zienkiewicz-Zhu: eps(u_h) interpolated into continuous H1 of degree p (NGSolve's ``Set``:
element-wise projection, averaged), eta_T^2 = int_T C (eps* - eps(u_h)) : (eps* - eps(u_h)); Doerfler
marking with ``theta``; ``mesh.Refine()`` of the marked triangles (bisections with a conforming closure).

Run: ``python benchmarks/conforming.py --example 6.1 --order 3 --targets 1e-1 1e-2 1e-3``.
"""

import argparse
import contextlib
import math
import time
from dataclasses import dataclass
from pathlib import Path

import ngsolve as ngs
import numpy as np
from threadpoolctl import threadpool_limits

import ngdgfric as ndf

# ----------------------------------------------------------------------------------------- PARAMETERS
THETA = 0.5          # Doerfler parameter (benchmarks/README.md: the fastest to an accuracy of those tried)
H0 = 0.25            # the coarse structured mesh
MAX_NDOF = 4e5
MAX_NEWTON = 60
SMALL = 15000       # DOFs below which umfpack factorises faster than sparsecholesky
PARALLEL = 20000    # DOFs from which NGSolve's TaskManager pays (the same rule as ngdgfric)
R_SCALE = 0.1       # r_k = R_SCALE x the stiffness diagonal of y_t,k (0.1-0.3 did not cycle on 6.1/6.2)
ROOT = Path(__file__).resolve().parents[1]
REFERENCES = {"6.1": ROOT / "results" / "reference_6_1.npz", "6.2": ROOT / "results" / "reference_6_2.npz"}


# ----------------------------------------------------------------------------------------- CONTACT POINTS
def lobatto_rule(p):
    """The (p+1)-point Gauss-Lobatto rule on [0, 1]: nodes (ascending, 0 and 1 included), weights."""
    legendre = np.polynomial.legendre.Legendre.basis(p)
    nodes = np.concatenate([[-1.0], np.sort(legendre.deriv().roots().real), [1.0]])
    weights = 2.0 / (p * (p + 1) * legendre(nodes) ** 2)
    return (nodes + 1) / 2, weights / 2


@dataclass
class ContactPoints:
    """The K Lobatto points of Gamma_C on one mesh and the basis change u = T y.

    xy (K, 2), normal, tangent (K, 2), omega (K,) weights; it, jn (K,) the variables y_t,k and y_n,k (the
    indices of one vertex or edge dof of each component); free (K,) False at points with Dirichlet dofs;
    c_n, g_a, c_tau (K,): the data at the points; T: the sparse matrix of u = T y.
    """

    xy: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    omega: np.ndarray
    it: np.ndarray
    jn: np.ndarray
    free: np.ndarray
    c_n: np.ndarray
    g_a: np.ndarray
    c_tau: np.ndarray
    T: object
    scalar_vertex: np.ndarray   # (K_vertices,) scalar dof of each vertex point, points 0 .. K_vertices - 1
    bubbles: np.ndarray         # (E_C, p - 1) scalar bubble dofs of each edge
    interior: np.ndarray        # (E_C, p - 1) point numbers of each edge's interior points
    ends: np.ndarray            # (E_C, 2) point numbers of each edge's end points
    inverse: np.ndarray         # (E_C, p - 1, p - 1) Phi_b^-1: bubble values at the interior points, inverted
    hat: np.ndarray             # (E_C, p - 1, 2) values of the two end points' hat functions there


    mapped: object              # the Lobatto points of every contact edge, mapped (E_C x (p + 1))
    edge_point: np.ndarray      # (E_C, p + 1) point number of each mapped point


def _values(cf, points, size=1):
    return np.asarray(cf(points)).reshape(len(points), size)


def contact_points(problem, mesh, V, order):
    """The :class:`ContactPoints` of the H1 vector space V of degree ``order`` on ``mesh``."""
    p, nscalar = order, V.ndof // 2
    region = mesh.Boundaries(problem.where("contact"))
    sides = set(problem.sides("contact"))
    edges = [(el.vertices[0].nr, el.vertices[1].nr, *V.GetDofNrs(el)) for el in mesh.Elements(ngs.BND)
             if el.mat in sides]
    if not edges:
        raise ValueError("no edge on Gamma_C")
    table = np.array(edges, dtype=np.int64)
    E = len(table)
    corners, dofs = table[:, :2], table[:, 2:2 + p + 1]
    if not np.array_equal(table[:, 2 + p + 1:], dofs + nscalar):
        raise ValueError("unexpected dof numbering of VectorH1")
    nodes, weights = lobatto_rule(p)
    mapped = mesh.MapToAllElements({ngs.SEGM: ngs.IntegrationRule([(s,) for s in nodes], list(weights))}, region)
    xy = _values(ngs.CF((ngs.x, ngs.y)), mapped, 2).reshape(E, p + 1, 2)
    normals = _values(ngs.specialcf.normal(2), mapped, 2).reshape(E, p + 1, 2)
    coordinates = np.asarray(mesh.ngmesh.Coordinates())[:, :2]
    flip = np.linalg.norm(xy[:, 0] - coordinates[corners[:, 0]], axis=1) > \
        np.linalg.norm(xy[:, 0] - coordinates[corners[:, 1]], axis=1)
    corners[flip], dofs[flip, :2] = corners[flip][:, ::-1], dofs[flip, 1::-1]
    length = np.linalg.norm(xy[:, -1] - xy[:, 0], axis=1)
    misfit = max(np.abs(xy[:, 0] - coordinates[corners[:, 0]]).max(),
                 np.abs(xy[:, -1] - coordinates[corners[:, 1]]).max())
    if misfit > 1e-9 * length.max():
        raise RuntimeError("the mapped contact points do not follow the boundary elements")
    if np.ptp(normals, axis=1).max() > 1e-10:
        raise ValueError("the contact edges must be straight")
    n = normals[:, 0]
    vertex, ends = np.unique(corners, return_inverse=True)
    ends = ends.reshape(E, 2)
    Kv, q = len(vertex), p - 1
    vertex_normal = np.zeros((Kv, 2))
    vertex_normal[ends[:, 0]] = n
    vertex_normal[ends[:, 1]] = n
    if max(np.abs(vertex_normal[ends[:, k]] - n).max() for k in range(2)) > 1e-10:
        raise ValueError("Gamma_C must be straight at its vertices (one normal per contact vertex)")
    interior = Kv + np.arange(E * q).reshape(E, q)
    edge_point = np.column_stack([ends[:, 0], interior, ends[:, 1]])
    K = Kv + E * q
    xy_points = np.zeros((K, 2))
    xy_points[edge_point.ravel()] = xy.reshape(-1, 2)
    normal = np.zeros((K, 2))
    normal[edge_point.ravel()] = np.repeat(n, p + 1, axis=0)
    omega = np.bincount(edge_point.ravel(), weights=(weights[None, :] * length[:, None]).ravel(), minlength=K)
    scalar_vertex = np.zeros(Kv, dtype=np.int64)
    scalar_vertex[ends[:, 0]], scalar_vertex[ends[:, 1]] = dofs[:, 0], dofs[:, 1]
    bubbles = dofs[:, 2:]
    it = np.concatenate([scalar_vertex, bubbles.ravel()])
    jn = it + nscalar
    free_dofs = V.FreeDofs()
    free = np.array([free_dofs[int(i)] and free_dofs[int(j)] for i, j in zip(it, jn, strict=True)], dtype=bool)
    data = {}
    for name in ("c_n", "g_a", "c_tau"):
        values = np.zeros(K)
        values[edge_point.ravel()] = _values(ndf.problem.coefficient(getattr(problem, name)), mapped).ravel()
        data[name] = values
    # Phi_b: the bubbles' values at the interior points (E, q points, q functions); the ends' hat functions there
    phi = np.zeros((E, q, q))
    if q:
        probe = ngs.GridFunction(ngs.H1(mesh, order=p))
        inner = mesh.MapToAllElements({ngs.SEGM: ngs.IntegrationRule([(s,) for s in nodes[1:-1]],
                                                                    list(weights[1:-1]))}, region)
        for k in range(q):
            probe.vec[:] = 0.0
            probe.vec.FV().NumPy()[bubbles[:, k]] = 1.0
            phi[:, :, k] = _values(ngs.BoundaryFromVolumeCF(probe), inner).reshape(E, q)
    s = nodes[1:-1]
    hat = np.broadcast_to(np.stack([1 - s, s], axis=1), (E, q, 2)).copy()
    inverse = np.linalg.inv(phi) if q else phi
    T = _basis_change(V.ndof, nscalar, scalar_vertex, vertex_normal, bubbles, dofs[:, :2], n, inverse, hat)
    return ContactPoints(xy_points, normal, np.column_stack([-normal[:, 1], normal[:, 0]]), omega, it, jn, free,
                         data["c_n"], data["g_a"], data["c_tau"], T, scalar_vertex, bubbles, interior, ends, inverse,
                         hat, mapped, edge_point)


def _basis_change(ndof, nscalar, scalar_vertex, vertex_normal, bubbles, end_dofs, n, inverse, hat):
    """u = T y as an NGSolve sparse matrix: the identity away from Gamma_C; at a contact vertex u = t y_t + n y_n;
    on edge e the bubble coefficients of component c are Phi_b^-1 (u_c(x_int) - hat u_c(ends)), u_c = t_c y_t +
    n_c y_n at every point (edge normal ``n``)."""
    rows, cols, vals = [], [], []
    contact = np.zeros(ndof, dtype=bool)
    t_vertex = np.column_stack([-vertex_normal[:, 1], vertex_normal[:, 0]])
    t = np.column_stack([-n[:, 1], n[:, 0]])
    E, q = bubbles.shape
    ih = np.einsum("ekj,eji->eki", inverse, hat)                      # (E, q, 2): Phi_b^-1 hat
    for c in range(2):
        row = scalar_vertex + c * nscalar
        contact[row] = True
        rows += [row, row]
        cols += [scalar_vertex, scalar_vertex + nscalar]
        vals += [t_vertex[:, c], vertex_normal[:, c]]
        if not q:
            continue
        row = bubbles + c * nscalar                                      # (E, q)
        contact[row.ravel()] = True
        for direction, offset in ((t, 0), (n, nscalar)):
            rows.append(np.repeat(row[:, :, None], q, axis=2).ravel())
            cols.append(np.repeat((bubbles + offset)[:, None, :], q, axis=1).ravel())
            vals.append((inverse * direction[:, c, None, None]).ravel())
            rows.append(np.repeat(row[:, :, None], 2, axis=2).ravel())
            cols.append(np.repeat((end_dofs + offset)[:, None, :], q, axis=1).ravel())
            vals.append((-ih * direction[:, c, None, None]).ravel())
    rest = np.flatnonzero(~contact)
    rows, cols, vals = np.concatenate(rows + [rest]), np.concatenate(cols + [rest]), np.concatenate(
        vals + [np.ones(len(rest))])
    return ngs.la.SparseMatrixd.CreateFromCOO(rows, cols, vals, ndof, ndof)


def point_values(cp, cf):
    """Values of a volume CoefficientFunction (scalar) at the K contact points."""
    values = np.zeros(len(cp.omega))
    values[cp.edge_point.ravel()] = _values(ngs.BoundaryFromVolumeCF(cf), cp.mapped).ravel()
    return values


def set_trace(cp, gf, values):
    """Make the scalar H1 GridFunction ``gf`` the degree-p function on Gamma_C with these values at the K points
    (its other dofs zero)."""
    vector = gf.vec.FV().NumPy()
    vector[:] = 0.0
    vector[cp.scalar_vertex] = values[:len(cp.scalar_vertex)]
    if cp.bubbles.shape[1]:
        ends = values[cp.ends]                                            # (E, 2)
        inner = values[cp.interior] - np.einsum("eji,ei->ej", cp.hat, ends)
        vector[cp.bubbles.ravel()] = np.einsum("ekj,ej->ek", cp.inverse, inner).ravel()


# ----------------------------------------------------------------------------------------- SOLVER
def stiffness(problem, V):
    """a(u, v) = int C eps(u) : eps(v) (statically condensed) and (f, v) = int f v + int_{Gamma_F} g v."""
    u, v = V.TnT()
    mu, lam = problem.mu, problem.lam

    def eps(w):
        return ngs.Sym(ngs.Grad(w))

    a = ngs.BilinearForm(V, condense=True)
    a += (2 * mu * ngs.InnerProduct(eps(u), eps(v)) + lam * ngs.div(u) * ngs.div(v)) * ngs.dx
    f = ngs.LinearForm(V)
    f += ndf.problem.coefficient(problem.f) * v * ngs.dx
    if problem.sides("traction"):
        f += ndf.problem.coefficient(problem.g) * v * ngs.ds(definedon=V.mesh.Boundaries(problem.where("traction")))
    a.Assemble()
    f.Assemble()
    return a, f


def _positive_power(d, m):
    """(d_+^m, d/dd d_+^m) point by point."""
    positive = d > 0
    dp = np.where(positive, d, 0.0)
    if m == 1:
        return dp, positive.astype(float)
    return dp**m, np.where(positive, m * dp ** (m - 1), 0.0)


@dataclass
class ContactSolution:
    """The laws at the points after a solve: y_t, y_n (traces), phi (friction forces), N (normal forces), lam_tau
    (phi / s or the slip direction), stick (mask), iterations (linear solves)."""

    y_t: np.ndarray
    y_n: np.ndarray
    phi: np.ndarray
    N: np.ndarray
    lam_tau: np.ndarray
    stick: np.ndarray
    iterations: int


def _diagonal_positions(pointers, columns, rows):
    """Positions of the diagonal entries (i, i), i in ``rows``, in the value array of a CSR matrix."""
    return np.array([pointers[i] + np.searchsorted(columns[pointers[i]:pointers[i + 1]], i) for i in rows],
                    dtype=np.int64)


def direct_solver(ndof):
    """NGSolve's fastest direct solver for these systems: umfpack below SMALL DOFs (sparsecholesky takes at least
    ~20 ms whatever the size), sparsecholesky above (2-3 times faster than umfpack and pardiso at 7e4 DOFs)."""
    return "umfpack" if ndof < SMALL else "sparsecholesky"


def solve_contact(problem, V, cp, u, lam_tau, inverse=None, max_newton=MAX_NEWTON):
    """Solve the discrete contact problem on V exactly (module docstring); ``u`` (the displacement) and the scalar
    H1 function ``lam_tau`` are the warm start on entry and the solution on exit.  Returns a
    :class:`ContactSolution`."""
    mesh = V.mesh
    m_n = problem.m_n
    a, f = stiffness(problem, V)
    lift = ngs.GridFunction(V)
    u_D = problem.u_D
    if not (isinstance(u_D, (tuple, list)) and all(ndf.problem.is_number(c) and c == 0 for c in u_D)):
        lift.Set(ndf.problem.coefficient(u_D), definedon=mesh.Boundaries(problem.where("dirichlet")))
    r = f.vec.CreateVector()
    r.data = f.vec - a.mat * lift.vec
    r.data += a.harmonic_extension_trans * r
    T = cp.T
    Tt = T.CreateTranspose()
    A = Tt @ a.mat @ T
    b = (Tt * r).Evaluate().FV().NumPy().copy()
    values, columns, pointers = A.CSR()
    values = np.asarray(values)
    pointers = np.asarray(pointers, dtype=np.int64)
    columns = np.asarray(columns, dtype=np.int64)
    diagonal = _diagonal_positions(pointers, columns, cp.jn)
    base = values[diagonal].copy()
    n, t = cp.normal, cp.tangent
    k = np.flatnonzero(cp.free)
    it, jn = cp.it[k], cp.jn[k]
    lift_xy = np.column_stack([point_values(cp, lift[i]) for i in range(2)])[k]
    y0_t, y0_n = np.sum(lift_xy * t[k], axis=1), np.sum(lift_xy * n[k], axis=1)
    u_xy = np.column_stack([point_values(cp, u[i]) for i in range(2)])[k]
    y_t, y_n = np.sum(u_xy * t[k], axis=1), np.sum(u_xy * n[k], axis=1)
    s = cp.omega[k] * cp.c_tau[k]
    wc = cp.omega[k] * cp.c_n[k]
    g_a = cp.g_a[k]
    r_k = R_SCALE * values[_diagonal_positions(pointers, columns, it)]
    phi = s * np.clip(point_values(cp, lam_tau)[k], -1.0, 1.0)
    z = phi + r_k * y_t
    stick, sign = np.abs(z) < s, np.where(z >= 0, 1.0, -1.0)
    y_bar = y_n
    free_base = V.FreeDofs(True)
    delta = A.CreateColVector()
    residual = A.CreateColVector()
    rhs = A.CreateColVector()
    visited = set()
    iterations = 0
    while True:
        iterations += 1
        if iterations > max_newton:
            raise RuntimeError(f"semismooth Newton: no convergence in {max_newton} steps")
        N, dN = _positive_power(y_bar - g_a, m_n)
        N, dN = wc * N, wc * dN
        values[diagonal[k]] = base[k] + dN
        freedofs = ngs.BitArray(free_base)
        for i in it[stick]:
            freedofs[int(i)] = False
        rhs_np = b.copy()
        rhs_np[jn] -= N + dN * (y0_n - y_bar)
        rhs_np[it] -= np.where(stick, 0.0, s * sign)
        rhs.FV().NumPy()[:] = rhs_np
        d = delta.FV().NumPy()
        d[:] = 0.0
        d[it[stick]] = -y0_t[stick]
        residual.data = rhs - A * delta
        delta.data += A.Inverse(freedofs, inverse=inverse or direct_solver(V.ndof)) * residual
        d = delta.FV().NumPy()
        y_t, y_n = y0_t + d[it], y0_n + d[jn]
        residual.data = rhs - A * delta   # zero on free rows; the stick forces on the others
        forces = residual.FV().NumPy()[it]
        phi = np.where(stick, forces, s * sign)
        z = phi + r_k * y_t
        new_stick, new_sign = np.abs(z) < s, np.where(z >= 0, 1.0, -1.0)
        if m_n == 1:
            normal_done = np.array_equal(y_n - g_a > 0, y_bar - g_a > 0)
        else:
            normal_done = np.max(np.abs(y_n - y_bar), initial=0.0) <= 1e-13 * max(np.max(np.abs(d)), 1e-300)
        same = np.array_equal(new_stick, stick) and np.array_equal(new_sign[~stick], sign[~stick])
        state = (new_stick.tobytes(), np.where(new_stick, 0.0, new_sign).tobytes(), (y_n - g_a > 0).tobytes())
        if not same and state in visited:  # a cycle of the active sets: weigh the forces more (smaller r)
            r_k *= 0.1
        visited.add(state)
        stick, sign, y_bar = new_stick, new_sign, y_n
        if same and normal_done:
            break
    values[diagonal] = base
    u.vec.data = lift.vec + T * delta
    u.vec.data += a.harmonic_extension * u.vec
    u.vec.data += a.inner_solve * r
    N = wc * _positive_power(y_n - g_a, m_n)[0]
    lam = np.where(stick, phi / np.where(s > 0, s, 1.0), sign)
    lam_points = np.zeros(len(cp.omega))
    lam_points[k] = lam
    set_trace(cp, lam_tau, lam_points)
    return ContactSolution(y_t, y_n, phi, N, lam, stick, iterations)


# ----------------------------------------------------------------------------------------- ESTIMATE, MARK
def zz_indicators(problem, u, recovered):
    """eta_T^2 = int_T C (eps* - eps(u_h)) : (eps* - eps(u_h)), eps* = (xx, yy, xy) of eps(u_h) set into the
    continuous space of ``recovered`` (a GridFunction of H1 with dim=3)."""
    e = ngs.Sym(ngs.Grad(u))
    strain = ngs.CF((e[0, 0], e[1, 1], e[0, 1]))
    recovered.Set(strain)
    d = recovered - strain
    density = problem.lam * (d[0] + d[1]) ** 2 + 2 * problem.mu * (d[0] ** 2 + d[1] ** 2 + 2 * d[2] ** 2)
    return ngs.Integrate(density * ngs.dx, u.space.mesh, element_wise=True).NumPy().copy()


def dorfler(indicators, theta):
    """The smallest set of elements with sum eta_T^2 >= theta sum eta_T^2 (a boolean mask)."""
    order = np.argsort(-indicators)
    count = int(np.searchsorted(np.cumsum(indicators[order]), theta * indicators.sum())) + 1
    marked = np.zeros(len(indicators), dtype=bool)
    marked[order[:count]] = True
    return marked


# ----------------------------------------------------------------------------------------- THE LOOP
@contextlib.contextmanager
def working(ndof, parallel_from=PARALLEL):
    """One BLAS thread (idle OpenBLAS/MKL threads busy-wait and take the cores from NGSolve: the same setting as
    ngdgfric's default), and NGSolve's TaskManager from ``parallel_from`` DOFs on (on a machine whose other cores
    are busy, its threads wait for each other: there one thread, parallel_from = inf, is faster)."""
    with threadpool_limits(limits=1, user_api="blas"), \
            (ngs.TaskManager() if ndof >= parallel_from else contextlib.nullcontext()):
        yield


@dataclass
class Level:
    """One level of :func:`run`: ``seconds`` is cumulative (solve + estimate + mark + refine of all levels so far).
    ``mesh``, ``u`` and ``lam_tau`` are the live objects: they change when the loop goes on."""

    level: int
    ndof: int
    seconds: float
    eta_h: float
    newton: int
    mesh: object
    u: object
    lam_tau: object
    points: ContactPoints
    contact: ContactSolution


def run(problem, order, mesh=None, theta=THETA, max_ndof=MAX_NDOF, max_levels=60, inverse=None, h0=H0,
        parallel_from=PARALLEL):
    """Adaptive conforming FEM of degree ``order`` for ``problem`` (module docstring), a generator of
    :class:`Level` s.  ``mesh``: the coarse mesh (default: ``ngdgfric.uniform_mesh(problem, H0)``; refined in
    place).  Stops after ``max_levels`` levels or when the next mesh would have more than ``max_ndof`` DOFs.
    Time spent by the caller between levels is not counted."""
    if problem.m_t != 0 or not ndf.problem.is_number(problem.m_n):
        raise NotImplementedError("the baseline solves the reduced law m_t = 0 with one number m_n")
    mesh = ndf.uniform_mesh(problem, h0) if mesh is None else mesh
    problem = problem.on(mesh)
    V = ngs.VectorH1(mesh, order=order, dirichlet=problem.where("dirichlet"), autoupdate=True)
    u = ngs.GridFunction(V, autoupdate=True)
    lam_tau = ngs.GridFunction(ngs.H1(mesh, order=order, autoupdate=True), autoupdate=True)
    recovered = ngs.GridFunction(ngs.H1(mesh, order=order, dim=3, autoupdate=True), autoupdate=True)
    seconds = 0.0
    for level in range(max_levels):
        start = time.perf_counter()
        with working(V.ndof, parallel_from):
            cp = contact_points(problem, mesh, V, order)
            contact = solve_contact(problem, V, cp, u, lam_tau, inverse=inverse)
            indicators = zz_indicators(problem, u, recovered)
        seconds += time.perf_counter() - start
        yield Level(level, V.ndof, seconds, math.sqrt(indicators.sum()), contact.iterations, mesh, u, lam_tau, cp,
                    contact)
        start = time.perf_counter()
        if level == max_levels - 1 or V.ndof * 1.1 > max_ndof:
            return
        with working(V.ndof, parallel_from):
            mesh.SetRefinementFlags(dorfler(indicators, theta).tolist())
            mesh.Refine()
        seconds += time.perf_counter() - start


def true_error(problem, mesh, u, reference):
    """|||u_ref - u_h|||_h of ngdgfric.energy_error (the same norm; a conforming u_h with exact Dirichlet data has
    no jumps) for a displacement GridFunction u on ``mesh`` against an ``ngdgfric.Reference``."""
    return ndf.reference.gridfunction_errors(problem, mesh, u, reference)["energy"]


def time_to_targets(problem, order, targets, reference, **options):
    """For each target error: the first level whose true error is <= target, as a dict (seconds, ndof, levels,
    error); None for targets not reached.  ``options`` go to :func:`run`."""
    targets = sorted(targets, reverse=True)
    reached, history = {}, []
    for level in run(problem, order, **options):
        error = true_error(problem, level.mesh, level.u, reference)
        history.append((level.level, level.ndof, level.seconds, error, level.eta_h, level.newton))
        for target in targets:
            if target not in reached and error <= target:
                reached[target] = dict(seconds=level.seconds, ndof=level.ndof, levels=level.level + 1, error=error)
        if len(reached) == len(targets):
            break
    return {target: reached.get(target) for target in targets}, history


# ----------------------------------------------------------------------------------------- MAIN
def best_of(example, order, targets, repeat, **options):
    """time_to_targets of Example ``example`` ("6.1" or "6.2"), the fastest of ``repeat`` runs per target."""
    problem = ndf.example(example)
    reference = ndf.load_reference(REFERENCES[example], problem)
    best = {}
    for _ in range(repeat):
        results, _ = time_to_targets(problem, order, targets, reference, **options)
        for target, result in results.items():
            if result is not None and (best.get(target) is None or result["seconds"] < best[target]["seconds"]):
                best[target] = result
            best.setdefault(target, None)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--example", nargs="+", choices=sorted(REFERENCES), default=["6.1"])
    parser.add_argument("--order", type=int, nargs="+", default=[3])
    parser.add_argument("--targets", type=float, nargs="+", default=[1e-1, 1e-2, 1e-3])
    parser.add_argument("--theta", type=float, default=THETA)
    parser.add_argument("--h0", type=float, default=H0)
    parser.add_argument("--max-ndof", type=float, default=MAX_NDOF)
    parser.add_argument("--repeat", type=int, default=1, help="runs per case; the fastest is reported")
    parser.add_argument("--parallel-from", type=float, default=PARALLEL,
                        help="DOFs from which NGSolve's TaskManager runs (inf: one thread)")
    args = parser.parse_args(argv)
    print(f"conforming baseline, theta = {args.theta}, h0 = {args.h0}, TaskManager from {args.parallel_from:g} DOFs, "
          f"best of {args.repeat}; time = cumulative "
          f"seconds (solve + estimate + mark + refine) to the first level with true error <= target\n")
    print("| example | p | target | seconds | DOFs | levels | true error |")
    print("|---|---|---|---|---|---|---|")
    for example in args.example:
        for order in args.order:
            best = best_of(example, order, args.targets, args.repeat, theta=args.theta, h0=args.h0,
                           max_ndof=args.max_ndof, parallel_from=args.parallel_from)
            for target, r in best.items():
                row = "not reached | | | " if r is None else \
                    f"{r['seconds']:.2f} | {r['ndof']} | {r['levels']} | {r['error']:.3e}"
                print(f"| {example} | {order} | {target:.0e} | {row} |", flush=True)


if __name__ == "__main__":
    main()
