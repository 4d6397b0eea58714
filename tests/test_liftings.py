import dataclasses
import warnings

import ngsolve as ngs
import numpy as np
import pytest
from reference_liftings import dense, reference_parts, reference_system

import ngdgfric as ndf
from ngdgfric.dg.methods import PenaltyWarning
from ngdgfric.meshes import refine

# the methods with a lifting operator: Bassi et al., Brezzi et al., LDG
LIFTING_METHODS = [name for name, m in ndf.METHODS.items() if m.penalty == "lift" or m.global_lift]


def _bisected():
    p = ndf.example_6_1()
    mesh = ndf.netgen_mesh(p, 0.35)  # unstructured, then bisected: facet numbers include the inactive parent edges
    refine(mesh, np.arange(mesh.ne) % 3 == 0)
    assert mesh.nfacet > ngs.FacetFESpace(mesh, order=0).ndof
    return p, mesh, 3


def _hp():
    p, mesh, _ = _bisected()
    return p, mesh, np.random.default_rng(3).integers(1, 5, size=mesh.ne)


def _symmetric():  # regions (material per region), an interface, a symmetry side, u_D != 0
    p = ndf.load_problem(ndf.example_file("two_materials_symmetric"))
    return p, ndf.netgen_mesh(p, 0.25), 2


def _curved():  # curved elements of degree 3, u_D != 0
    from ngdgfric.domain import Domain, Loop

    domain = Domain({"omega": Loop([(-1, 1), (1, 1)], ["contact", "dirichlet"], arcs={0: (0.0, 0.0)})})
    p = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=1e2, m_n=1, g_a=ngs.y, c_tau=0.05,
                           geometry=domain, u_D=(0.005, -0.01))
    return p, ndf.netgen_mesh(p, 0.45), 3


def _varying():  # E and nu vary inside the elements: degree-p fields, weights that vary along the edges
    p = dataclasses.replace(ndf.example_6_2(), E=2500 * (1 + 0.5 * ngs.x * ngs.y), nu=0.3 + 0.1 * ngs.x)
    return p, ndf.uniform_mesh(p, 1 / 4), 2


def _layered():  # four geometric layers towards a corner, p = 3: elements 1/16 of the coarse ones
    from ngdgfric.hp import containing

    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 0.5)
    for _ in range(4):
        refine(mesh, containing(mesh, p.geometry.corners[:1]), bisections=2)
    return p, mesh, 3


SCENES = {"bisected": _bisected, "hp": _hp, "symmetric": _symmetric, "curved": _curved, "varying": _varying,
          "layered": _layered}


@pytest.mark.slow
@pytest.mark.parametrize("scene", SCENES)
def test_the_lifting_terms_are_those_of_the_definition(scene):
    """B_h's matrix and load with the liftings assembled from moments and element kernels equal the same terms
    built from the definition edge by edge (tests/reference_liftings.py) for Bassi et al., Brezzi et al. and LDG, to
    round-off (measured <= 1e-15 relative; tested at 1e-12): on a bisected Netgen mesh, with degrees 1..4 per
    element, with regions, an interface, a symmetry side and u_D, on curved elements, with a material that varies
    inside the elements, and on four layers of elements down to 1/16 of the coarse ones."""
    p, mesh, order = SCENES[scene]()
    parts = None
    for method in LIFTING_METHODS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ndf.MaterialWarning)
            disc = ndf.Discretization(p, mesh, method=method, order=order)
        parts = parts or reference_parts(disc)
        A, F = reference_system(disc, parts)
        assert np.abs(dense(disc.A) - A).max() <= 1e-12 * np.abs(A).max()
        assert np.abs(disc.F.FV().NumPy() - F).max() <= 1e-12 * np.abs(F).max()


@pytest.mark.parametrize("method", [name for name in ndf.DG_METHODS if ndf.METHODS[name].symmetry == 1])
def test_symmetric_methods_give_symmetric_matrices(method):
    p, mesh, _ = _bisected()
    A = dense(ndf.Discretization(p, mesh, method=method, order=2).A)
    assert np.abs(A - A.T).max() <= 1e-12 * np.abs(A).max()


def test_the_global_lifting_reaches_the_neighbours_neighbours_and_no_further():
    """Brezzi et al. and LDG couple an element with its neighbours' neighbours, Bassi et al. with its neighbours
    only: the matrices' nonzeros per row against the element graph of the mesh."""
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    nonzeros = {name: ndf.Discretization(p, mesh, method=name, order=1).A.nze for name in ("sipg", "bassi", "ldg")}
    neighbours = {el.nr: {n.nr for f in el.facets for n in mesh[f].elements} for el in mesh.Elements()}
    two_ring = {e: set().union(*(neighbours[n] for n in near)) for e, near in neighbours.items()}
    block = 6 ** 2  # P1: 3 functions per component and element, 2 components
    assert nonzeros["sipg"] == nonzeros["bassi"] == block * sum(map(len, neighbours.values()))
    assert nonzeros["ldg"] == block * sum(map(len, two_ring.values()))


def test_bassi_is_coercive_above_3_and_warns_at_or_below():
    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    A = dense(ndf.Discretization(p, mesh, method="bassi", eta=3.5).A)
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
    """The three methods solve a half-disk with curved elements to the round-off of the KKT system."""
    p, mesh, order = _curved()
    for method in LIFTING_METHODS:
        sol = ndf.solve(p, mesh, method=method, order=order)
        assert ndf.kkt_residuals(sol)["equilibrium"] < 1e-12 and ndf.contact_state(sol)["pressure"].max() > 0
