import warnings

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.dg.liftings import edge_colours, lifting_matrices, lifting_space
from ngdgfric.dg.methods import PenaltyWarning
from ngdgfric.meshes import facet_indicator, refine

# the methods with a lifting operator: Bassi et al., Brezzi et al., LDG
LIFTING_METHODS = [name for name, m in ndf.METHODS.items() if m.penalty == "lift" or m.global_lift]


@pytest.fixture(scope="module", params=["netgen", "bisected"])
def small(request):
    p = ndf.example_6_1()
    mesh = ndf.netgen_mesh(p, 0.35)  # unstructured: more colours than a structured mesh
    if request.param == "bisected":  # facet numbers then include the bisected edges: not the facet dofs
        refine(mesh, np.arange(mesh.ne) % 3 == 0)
        assert mesh.nfacet > ngs.FacetFESpace(mesh, order=0).ndof
    return p, mesh, ndf.Discretization(p, mesh, order=2)


def test_colours_separate_the_edges_of_every_triangle(small):
    p, mesh, _ = small
    colours = [colour.indicator for colour in edge_colours(p, mesh)]
    assert 3 <= len(colours) <= 5
    total = sum(c.vec.FV().NumPy() for c in colours)
    interior_or_dirichlet = ngs.Integrate(sum(colours) * ngs.dx(element_boundary=True), mesh, element_wise=True)
    assert np.max(total) == 1  # each edge has at most one colour
    assert np.max(interior_or_dirichlet.NumPy()) > 0
    for c in colours:  # no triangle has two edges of one colour
        per_element = ngs.Integrate(c * ngs.dx(element_boundary=True), mesh, element_wise=True).NumPy()
        lengths = ngs.Integrate(ngs.CF(1) * ngs.dx(element_boundary=True), mesh, element_wise=True).NumPy()
        # one edge is shorter than half the perimeter, two edges are longer (triangle inequality)
        assert np.all(per_element < lengths / 2)


def test_colour_bitarrays_mark_the_facets_of_the_indicators(small):
    p, mesh, _ = small
    space = ngs.FacetFESpace(mesh, order=0)
    for colour in edge_colours(p, mesh):
        marked = np.array(list(colour.facets), dtype=bool)
        assert marked.size == mesh.nfacet
        values = colour.indicator.vec.FV().NumPy()
        for facet in range(mesh.nfacet):  # facet -> dof through NGSolve's own node lookup
            dofs = space.GetDofNrs(ngs.NodeId(ngs.FACET, facet))
            assert marked[facet] == (len(dofs) == 1 and values[dofs[0]] == 1.0)


def test_lifting_identity_and_global_lifting(small):
    p, mesh, disc = small
    R, _, _ = lifting_matrices(p, disc.material, mesh, disc.V, 2, local=True, total=True)
    S = lifting_space(mesh, 2)
    rng = np.random.default_rng(7)
    u = ngs.GridFunction(disc.V)
    u.vec.FV().NumPy()[:] = rng.standard_normal(disc.V.ndof)
    tau = ngs.GridFunction(S)
    tau.vec.FV().NumPy()[:] = rng.standard_normal(S.ndof)
    n = ngs.specialcf.normal(2)
    tmp = tau.vec.CreateVector()

    def paired(mat):  # tau^T R u = int r(u) : tau (R = M r)
        tmp.data = mat * u.vec
        return float(np.dot(tau.vec.FV().NumPy(), tmp.FV().NumPy()))

    # - int_{E_h^o} [u] : {tau} ds, computed independently from element-boundary integrals
    jump = u - u.Other()
    interior = ngs.Integrate(-0.5 * jump * (0.5 * (tau + tau.Other()) * n) * ngs.dx(element_boundary=True), mesh)
    dirichlet = ngs.Integrate(-facet_indicator(mesh, p.dirichlet) * u * (tau * n) * ngs.dx(element_boundary=True),
                              mesh)
    local = sum(paired(R_c) for R_c in R[:-1])
    assert local == pytest.approx(interior + dirichlet, rel=1e-10)
    assert paired(R[-1]) == pytest.approx(local, rel=1e-10)  # r_0 = sum_e r_e


@pytest.mark.parametrize("method", [name for name in ndf.DG_METHODS if ndf.METHODS[name].symmetry == 1])
def test_symmetric_methods_give_symmetric_matrices(small, method):
    p, mesh, _ = small
    A = ndf.Discretization(p, mesh, method=method).A.ToDense().NumPy()
    assert np.abs(A - A.T).max() <= 1e-12 * np.abs(A).max()


def test_bassi_is_coercive_above_3_and_warns_at_or_below():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    A = ndf.Discretization(p, mesh, method="bassi", eta=3.5).A.ToDense().NumPy()
    assert np.linalg.eigvalsh(0.5 * (A + A.T)).min() > 0
    with pytest.warns(PenaltyWarning, match="threshold 3"):
        ndf.Discretization(p, mesh, method="bassi", eta=3.0)
    with pytest.raises(ValueError, match="threshold"):
        ndf.Discretization(p, mesh, method="bassi", eta=2.0, penalty_check="raise")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ndf.Discretization(p, mesh, method="bassi")  # the default eta is fine


@pytest.mark.parametrize("method", LIFTING_METHODS)
@pytest.mark.parametrize("order, levels", [(1, (2, 3, 4)), (2, (1, 2, 3))])
def test_lifting_methods_converge_at_the_optimal_rate(elasticity, method, order, levels):
    problem, u_exact = elasticity
    errors = [ndf.energy_norm(ndf.solve(problem, ndf.uniform_mesh(problem, 2.0**-k), method=method, order=order),
                              u_exact) for k in levels]
    assert np.log2(errors[-2] / errors[-1]) == pytest.approx(order, abs=0.15)


def test_lifting_methods_on_curved_elements():
    """On a curved mesh the mass matrix of Sigma_h has a full block per curved element and component (it was
    taken to be diagonal, and Bassi, Brezzi and LDG stopped with "not diagonal"): its inverse is exact, and the
    three methods solve a half-disk to the round-off of the KKT system."""
    from ngdgfric.dg.liftings import _block_inverse
    from ngdgfric.domain import Domain, Loop

    domain = Domain({"omega": Loop([(-1, 1), (1, 1)], ["contact", "dirichlet"], arcs={0: (0.0, 0.0)})})
    p = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=1e2, m_n=1, g_a=ngs.y, c_tau=0.05,
                           geometry=domain, u_D=(0.005, -0.01))
    mesh = ndf.netgen_mesh(p, 0.3)
    curved = ngs.Mesh(mesh.ngmesh.Copy())
    curved.Curve(3)
    sigma, tau = lifting_space(curved, 3, dgjumps=False).TnT()
    mass = ngs.BilinearForm(sigma.space)
    mass += ngs.InnerProduct(sigma, tau) * ngs.dx
    mass.Assemble()
    x = mass.mat.CreateColVector()
    x.FV().NumPy()[:] = np.random.default_rng(0).random(len(x))
    y = x.CreateVector()
    y.data = _block_inverse(mass.mat) * (mass.mat * x)
    assert np.abs(y.FV().NumPy() - x.FV().NumPy()).max() < 1e-12
    for method in LIFTING_METHODS:
        sol = ndf.solve(p, mesh, method=method, order=3)
        assert ndf.kkt_residuals(sol)["equilibrium"] < 1e-12 and ndf.contact_state(sol)["pressure"].max() > 0


def test_the_lifting_mass_matrix_is_inverted_on_tiny_high_order_elements():
    # ten geometric layers towards the corners and p = 7: the mass matrix of Sigma_h is diagonal up to round-off
    # entries of 1.7e-13 against the diagonal of a low-degree row of a tiny element, but below 1e-13 of the
    # geometric mean of the two diagonals (the row criterion called it "not block diagonal": adapt with Bassi et
    # al. crashed on Example 6.1)
    from ngdgfric.dg.liftings import _block_inverse
    from ngdgfric.hp import containing
    from ngdgfric.meshes import refine

    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 0.5)
    for _ in range(10):
        refine(mesh, containing(mesh, problem.geometry.corners), bisections=2)
    cells = lifting_space(mesh, 7, dgjumps=False)
    sigma, tau = cells.TnT()
    mass = ngs.BilinearForm(cells)
    mass += ngs.InnerProduct(sigma, tau) * ngs.dx
    mass.Assemble()
    x = mass.mat.CreateColVector()
    x.FV().NumPy()[:] = np.random.default_rng(0).standard_normal(len(x))
    y = (_block_inverse(mass.mat) @ mass.mat * x).Evaluate()
    assert np.max(np.abs(y.FV().NumPy() - x.FV().NumPy())) <= 1e-10
