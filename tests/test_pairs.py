"""Two bodies in contact (ContactPair, ngdgfric.contact.pairing, ngdgfric.contact.pair_traces,
ngdgfric.solvers.floating): the contact patch test on non-matching meshes for every method, load control, swapped
sides, a stiff second body against the rigid foundation, sliding friction, and the named errors."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.errors import SolverError

E1, NU1, E2, NU2, P, C_N = 1.0, 0.3, 2.0, 0.2, 0.01, 50.0


def stacked(upper_top=1.5, labels=("c1", "c2")):
    lower = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "right1", labels[0], "left1"])
    upper = ndf.Loop([(0, 1), (1, 1), (1, upper_top), (0, upper_top)], [labels[1], "right2", "top", "left2"])
    return ndf.Domain({"lower": lower, "upper": upper})


def exact_parts():
    """Uniaxial stress sigma_yy = -P in plane strain in both bodies, rollers at x = 0 and y = 0, the jump of u_y
    across the interface P / c_n (the compliance law at the uniform pressure P)."""
    def strains(E, nu):
        return nu * (1 + nu) * P / E, -(1 - nu**2) * P / E
    (a1, b1), (a2, b2) = strains(E1, NU1), strains(E2, NU2)
    return (ngs.CF((a1 * ngs.x, b1 * ngs.y)), ngs.CF((a2 * ngs.x, b1 - P / C_N + b2 * (ngs.y - 1))))


def patch_problem(load, side="c2", other="c1"):
    """The patch test: a uniform pressure P on top (``load``) or the exact displacement prescribed there."""
    upper = exact_parts()[1]
    common = dict(E={"lower": E1, "upper": E2}, nu={"lower": NU1, "upper": NU2}, f=(0, 0), c_n=0.0, m_n=1.0,
                  g_a=0.0, c_tau=0.0, geometry=stacked(), symmetry=("bottom", "left1", "left2"), contact=(),
                  pairs=[ndf.ContactPair(side, other, c_n=C_N)])
    if load:
        return ndf.ContactProblem(g={"top": (0, -P)}, dirichlet=(), traction=("right1", "right2", "top"), **common)
    return ndf.ContactProblem(g=(0, 0), dirichlet="top", traction=("right1", "right2"), u_D={"top": upper}, **common)


def relative_error(sol):
    """The relative L2 error of sol.u against the exact solution, on the solution's own mesh."""
    mesh, (lower, upper) = sol.mesh, exact_parts()
    exact = ngs.CF(tuple(mesh.MaterialCF({"lower": lower[i], "upper": upper[i]}) for i in range(2)))
    return float(np.sqrt(ngs.Integrate((sol.u - exact) ** 2, mesh) / ngs.Integrate(exact**2, mesh)))


@pytest.fixture(scope="module")
def non_matching():
    """h = 1/3 below, 1/5 above: the two sides of the interface share only their ends."""
    return ndf.netgen_mesh(patch_problem(load=True), {"lower": 1 / 3, "upper": 1 / 5})


@pytest.mark.parametrize("load", [False, True], ids=["displacement", "force"])
@pytest.mark.parametrize("method", ndf.METHODS)
def test_the_patch_test_is_passed_to_round_off(non_matching, method, load):
    """The exact solution is piecewise linear with a jump across the interface: every method reproduces it on
    meshes that do not match there (h = 1/3 against 1/5), at p = 1, p = 2 and p = 1 below against p = 2 above,
    with the uniform pressure P in every pair point.  Measured: at most 1.7e-12 relative (cg with the load)."""
    problem = patch_problem(load)
    mixed = np.array([1 if el.mat == "lower" else 2 for el in non_matching.Elements(ngs.VOL)])
    for order in (1, 2, mixed):
        sol = ndf.solve(problem, non_matching, method=method, order=order)
        assert relative_error(sol) < 1e-10
        normal, tangential = sol.info["pair_forces"]
        assert normal.sum() == pytest.approx(P, rel=1e-10)  # the pressure P over the length 1
        assert np.max(np.abs(tangential)) < 1e-12 * P


@pytest.mark.parametrize("lift, g_a", [(0.02, 0.0), (0.0, 0.02), (0.05, -0.03)],
                         ids=["geometric gap", "offset", "both"])
def test_the_gap_is_closed_before_the_pressure_acts(lift, g_a):
    """The upper body lifted by ``lift`` (a gap the pairing measures from the geometry) and the pair's offset
    ``g_a``, pressed by the force: the upper body comes down by the whole gap lift + g_a, rigidly, on top of the
    patch-test solution (error at round-off; measured at most 7.3e-13)."""
    gap = lift + g_a
    lower = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "right1", "c1", "left1"])
    upper = ndf.Loop([(0, 1 + lift), (1, 1 + lift), (1, 1.5 + lift), (0, 1.5 + lift)], ["c2", "right2", "top", "left2"])
    problem = dataclasses.replace(patch_problem(load=True), geometry=ndf.Domain({"lower": lower, "upper": upper}),
                                  pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, g_a=g_a)])
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, {"lower": 1 / 3, "upper": 1 / 5}), order=2)
    (a1, b1), (a2, b2) = ((nu * (1 + nu) * P / E, -(1 - nu**2) * P / E) for E, nu in ((E1, NU1), (E2, NU2)))
    exact_upper = ngs.CF((a2 * ngs.x, b1 - P / C_N - gap + b2 * (ngs.y - 1 - lift)))
    mesh = sol.mesh
    exact = ngs.CF(tuple(mesh.MaterialCF({"lower": exact_parts()[0][i], "upper": exact_upper[i]}) for i in range(2)))
    error = np.sqrt(ngs.Integrate((sol.u - exact) ** 2, mesh) / ngs.Integrate(exact**2, mesh))
    assert error < 1e-10


def test_the_patch_test_counts_its_pieces(non_matching):
    """The common refinement of the two sides (Netgen's points at 1/3, 2/3 below and at about 0.199, 0.398,
    0.596, 0.797 above) cuts the unit interface into 7 pieces whose weights add up to its length."""
    contact = ndf.Contact(ndf.Discretization(patch_problem(True), non_matching, order=1))
    (_, points, _), = contact.pairs
    assert points.pieces == 7
    assert points.weight.sum() == pytest.approx(1.0, rel=1e-14)
    assert np.max(np.abs(points.gap)) < 1e-14


@pytest.mark.parametrize("sizes", [0.25, {"lower": 1 / 3, "upper": 1 / 5}], ids=["matching", "non-matching"])
def test_swapping_the_sides_of_a_pair_changes_nothing_on_a_flat_interface(sizes):
    """On a flat interface the common refinement and its Gauss points are the same from either side and the normals
    opposite: the solutions agree to round-off on matching and non-matching meshes (a load that is not uniform: a
    tilted displacement of the top, with friction, stick and slip; measured 2.8e-16 and 8.3e-16)."""
    problem = patch_problem(load=False)
    upper = exact_parts()[1]
    problem = dataclasses.replace(problem, u_D={"top": upper + ngs.CF((0.002 * ngs.x, -0.003 * ngs.x))},
                                  pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=0.001)])
    mesh = ndf.netgen_mesh(problem, sizes)
    first = ndf.solve(problem, mesh, method="sipg", order=2)
    swapped = ndf.solve(dataclasses.replace(problem, pairs=[problem.pairs[0].swapped()]), mesh, method="sipg", order=2)
    a, b = first.u.vec.FV().NumPy(), swapped.u.vec.FV().NumPy()  # one space: the same coefficients
    assert np.linalg.norm(a - b) < 1e-13 * np.linalg.norm(a)
    sticking = np.abs(first.info["pair_multiplier"]) < 1 - 1e-9
    assert np.any(sticking) and not np.all(sticking)


def test_a_stiff_second_body_acts_as_the_rigid_foundation():
    """The upper body pressed and sheared on the foundation (its bottom side a contact side, flat, g_a = 0) against
    the same body on a second body 1e6 times stiffer: the displacements of the upper body agree to 1e-3 of their
    largest value at 35 points (measured 3.1e-4; 2.3e-3 with a body 1e3 times stiffer)."""
    shift = ngs.CF((0.002, -0.01))
    two = ndf.ContactProblem(E={"lower": 1e6, "upper": 1.0}, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0,
                             c_tau=0.0, geometry=stacked(), dirichlet=("bottom", "top"),
                             traction=("right1", "left1", "right2", "left2"), contact=(),
                             pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=0.002)],
                             u_D={"top": shift})
    block = ndf.Polygon.rectangle(0, 1, 1, 1.5, "contact", "right2", "top", "left2")
    one = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=C_N, m_n=1.0, g_a=0.0, c_tau=0.002,
                             geometry=block, dirichlet="top", traction=("right2", "left2"), u_D={"top": shift})
    mesh_two = ndf.netgen_mesh(two, {"lower": 0.5, "upper": 0.125})
    mesh_one = ndf.netgen_mesh(one, 0.125)
    u_two = ndf.solve(two, mesh_two, method="sipg", order=2).u
    u_one = ndf.solve(one, mesh_one, method="sipg", order=2).u
    samples = [(x, y) for x in np.linspace(0.05, 0.95, 7) for y in np.linspace(1.05, 1.45, 5)]
    a = np.array([u_two(mesh_two(x, y)) for x, y in samples])
    b = np.array([u_one(mesh_one(x, y)) for x, y in samples])
    assert np.max(np.abs(a - b)) < 1e-3 * np.max(np.abs(b))


def test_sliding_beyond_the_friction_limit_gives_c_tau_times_the_length():
    """The upper block pressed down and pulled 10 times farther sideways than the friction bound lets it stick:
    every pair point slips, and the friction force is c_tau times the contact length (1) to round-off."""
    c_tau = 0.001
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                                 geometry=stacked(), dirichlet=("bottom", "top"),
                                 traction=("right1", "left1", "right2", "left2"), contact=(),
                                 pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=c_tau)],
                                 u_D={"top": (0.05, -0.01)})
    mesh = ndf.netgen_mesh(problem, {"lower": 1 / 3, "upper": 1 / 5})
    for method in ("sipg", "nipg", "cg"):
        sol = ndf.solve(problem, mesh, method=method, order=2)
        normal, tangential = sol.info["pair_forces"]
        assert np.all(normal > 0)
        assert np.all(np.abs(np.abs(sol.info["pair_multiplier"]) - 1) < 1e-12)
        assert abs(tangential.sum()) == pytest.approx(c_tau * 1.0, rel=1e-12)


def test_a_body_that_nothing_holds_is_named():
    """The upper body pulled up (load control): nothing holds its vertical translation; a SolverError names it."""
    problem = dataclasses.replace(patch_problem(load=True), g={"top": (0, P)})
    with pytest.raises(SolverError, match=r"nothing holds the translation in y of body 1 \(regions 'upper'\)"):
        ndf.solve(problem, ndf.netgen_mesh(problem, 0.3))


@pytest.mark.parametrize("change, message", [
    (dict(pairs=[ndf.ContactPair("c2", "top", c_n=1.0)]), "belong to one body"),
    (dict(pairs=[ndf.ContactPair("c2", "c1", c_n=1.0), ndf.ContactPair("c1", "right2", c_n=1.0)]),
     r"pairs\[1\]: side 'c1' is in pairs\[0\] too"),
    (dict(pairs=[ndf.ContactPair("c2", "c9", c_n=1.0)]), "the geometry has no side 'c9'"),
    (dict(pairs=[]), "sides 'c1' and 'c2' of two bodies touch but are not a contact pair"),
    (dict(pairs=[], contact="c1", traction=("right1", "right2", "top", "c2")),
     "sides 'c1' and 'c2' of two bodies touch but are not a contact pair"),
])
def test_bad_pairs_are_named(change, message):
    with pytest.raises(ValueError, match=message):
        dataclasses.replace(patch_problem(load=True), **change)


@pytest.mark.parametrize("field, value, message", [
    ("c_n", -1.0, "c_n must be >= 0"), ("m_n", 0.5, "m_n must be >= 1"), ("g_a", float("nan"), "g_a must be a finite"),
    ("reach", 0.0, "reach must be > 0"), ("other", "c2", "needs two sides"),
])
def test_bad_pair_data_are_named(field, value, message):
    with pytest.raises(ValueError, match=message):
        dataclasses.replace(ndf.ContactPair("c2", "c1", c_n=1.0), **{field: value})


def test_sides_out_of_reach_are_named():
    """Two squares 1 apart with reach 0.01: no point of one side finds the other."""
    lower = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "right1", "c1", "left1"])
    upper = ndf.Loop([(0, 2), (1, 2), (1, 3), (0, 3)], ["c2", "right2", "top", "left2"])
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                                 geometry=ndf.Domain({"lower": lower, "upper": upper}), dirichlet=("bottom", "top"),
                                 traction=("right1", "left1", "right2", "left2"), contact=(),
                                 pairs=[ndf.ContactPair("c2", "c1", c_n=1.0, reach=0.01)])
    with pytest.raises(ValueError, match=r"sides 'c2' and 'c1' of a contact pair do not face each other: no point of "
                                         r"'c2' comes within reach = 0.01 of 'c1' \(closest 1\)"):
        ndf.solve(problem, ndf.netgen_mesh(problem, 0.5))


def test_tools_without_pair_terms_refuse_pairs(non_matching):
    """The KKT residuals, the contact state, the force balance and the other solvers have no terms for the pairs
    yet: each refuses by name instead of leaving them out; the equilibrated bound refuses pairs with its reason."""
    problem = patch_problem(load=False)
    sol = ndf.solve(problem, non_matching)
    for call, name in ((lambda: ndf.kkt_residuals(sol), "kkt_residuals"),
                       (lambda: ndf.contact_state(sol), "contact_state"),
                       (lambda: ndf.force_balance(sol), "force_balance"),
                       (lambda: ndf.solve(problem, non_matching, solver="uzawa"), "solver='uzawa'")):
        with pytest.raises(ValueError, match=f"{name} does not handle contact pairs"):
            call()
    for call in (lambda: ndf.equilibrate(sol), lambda: ndf.estimate(sol, kind="equilibrated"),
                 lambda: ndf.adapt(problem, non_matching, max_levels=1, estimator="equilibrated")):
        with pytest.raises(ValueError, match="refused: contact pairs .two bodies. are not built into it"):
            call()
