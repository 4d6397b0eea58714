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


@pytest.mark.parametrize("sizes", [0.25, {"lower": 1 / 3, "upper": 1 / 5}, {"lower": 1 / 6, "upper": 1 / 10}],
                         ids=["matching", "non-matching", "non-matching finer"])
def test_swapping_the_sides_of_a_pair_changes_nothing_on_a_flat_interface(sizes):
    """A load that is not uniform (a tilted displacement of the top, with friction, stick and slip) on a flat
    interface.  Matching meshes: the law's points and the projection are the same from either side, the normals
    opposite: the solutions agree to round-off (measured 3.4e-16).  Non-matching meshes: the jump is projected onto
    the edges of the pair's side, which differ from the other side's, so the solutions differ by less than the
    estimated error: the SIPG energy of the difference below eta_h / 4 (measured 0.027 eta_h on h = 1/3 : 1/5 and
    1/6 : 1/10)."""
    problem = patch_problem(load=False)
    upper = exact_parts()[1]
    problem = dataclasses.replace(problem, u_D={"top": upper + ngs.CF((0.002 * ngs.x, -0.003 * ngs.x))},
                                  pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=0.001)])
    mesh = ndf.netgen_mesh(problem, sizes)
    first = ndf.solve(problem, mesh, method="sipg", order=2)
    swapped = ndf.solve(dataclasses.replace(problem, pairs=[problem.pairs[0].swapped()]), mesh, method="sipg", order=2)
    a, b = first.u.vec.FV().NumPy(), swapped.u.vec.FV().NumPy()  # one space: the same coefficients
    if isinstance(sizes, dict):
        difference = first.u.vec.CreateVector()
        difference.data = first.u.vec - swapped.u.vec
        energy = np.sqrt(ngs.InnerProduct(difference, first.discretization.A * difference))
        assert 0 < energy < 0.25 * ndf.estimate(first).eta_h
    else:
        assert np.linalg.norm(a - b) < 1e-13 * np.linalg.norm(a)
    sticking = np.abs(first.info["pair_multiplier"]) < 1 - 1e-9
    assert np.any(sticking) and not np.all(sticking)


def test_a_stiff_second_body_acts_as_the_rigid_foundation():
    """The upper body pressed and sheared on the foundation (its bottom side a contact side, flat, g_a = 0) against
    the same body on a second body 1e6 times stiffer: the displacements of the upper body agree to 1e-3 of their
    largest value at 35 points (measured 3.1e-4; 2.3e-3 with a body 1e3 times stiffer) and to 1e-3 relative in
    |||u|||."""
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
    sol_one = ndf.solve(one, mesh_one, method="sipg", order=2)
    u_one = sol_one.u
    samples = [(x, y) for x in np.linspace(0.05, 0.95, 7) for y in np.linspace(1.05, 1.45, 5)]
    a = np.array([u_two(mesh_two(x, y)) for x, y in samples])
    b = np.array([u_one(mesh_one(x, y)) for x, y in samples])
    assert np.max(np.abs(a - b)) < 1e-3 * np.max(np.abs(b))
    # in |||.|||: the one-body SIPG energy of the difference, u_two projected onto the one-body mesh (its upper
    # body is meshed apart: 66 elements against 70; the projection's error included); measured 5.7e-4
    projected = ngs.GridFunction(u_one.space)
    projected.Set(u_two)
    difference = projected.vec.CreateVector()
    difference.data = projected.vec - u_one.vec
    A = sol_one.discretization.A
    assert ngs.InnerProduct(difference, A * difference) < 1e-6 * ngs.InnerProduct(u_one.vec, A * u_one.vec)


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


def tilted(problem):
    """``problem`` (the displacement-driven patch test) with a load that is not uniform: the top moved by a tilted
    displacement, with friction on the pair (stick and slip)."""
    return dataclasses.replace(problem, u_D={"top": exact_parts()[1] + ngs.CF((0.002 * ngs.x, -0.003 * ngs.x))},
                               pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=0.001)])


def sheared(problem):
    """``problem`` (the force-driven patch test) with a shear load 2 S x on top (S = 0.0005, below the friction
    capacity c_tau x 1 = 0.001; the roller on the upper body's left side takes part of it): stick and slip."""
    return dataclasses.replace(problem, g={"top": (0.001 * ngs.x, -P)},
                               pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=0.001)])


def difference(first, second):
    """The relative differences (u in L2 on the solution's mesh, the pair forces in the max norm) of two solutions
    of one problem on one mesh (the same space: coefficient by coefficient)."""
    u = ngs.GridFunction(first.u.space)
    u.vec.data = first.u.vec - second.u.vec
    mesh = first.mesh
    forces = first.info["pair_forces"]
    return (float(np.sqrt(ngs.Integrate(u**2, mesh) / ngs.Integrate(first.u**2, mesh))),
            float(np.max(np.abs(forces - second.info["pair_forces"])) / np.max(np.abs(forces))))


@pytest.mark.skipif(not ndf.solvers.pardiso.available(), reason="needs MKL PARDISO")
@pytest.mark.parametrize("load", [False, True], ids=["displacement", "force"])
@pytest.mark.parametrize("method", ["sipg", "bassi", "cg"])
def test_full_space_newton_solves_the_patch_test(non_matching, method, load):
    """The full-space Newton (:mod:`ngdgfric.solvers.fullspace`) on the pair's points: the patch test exact, the
    condensed solution and pair forces reproduced, for a body held by contact only (load) through the proximal steps
    of :mod:`ngdgfric.solvers.floating` around the full-space solve.  Measured at p = 1, 2: differences at most
    3.2e-14 (displacement) and 1.4e-10 (force: bassi p = 1, pair forces; the full space stops at an equilibrium
    residual up to 1e-10, and its error against the exact solution is 5.3e-11, the condensed solve's 1.6e-13); tested
    at 1e-10 against the exact solution, as the patch test, and at 5e-10 against the condensed solve for the force."""
    problem = patch_problem(load)
    for order in (1, 2):
        condensed = ndf.solve(problem, non_matching, method=method, order=order, formulation="condensed")
        full = ndf.solve(problem, non_matching, method=method, order=order, formulation="full-space")
        assert full.info["linear_solver"] == "pardiso (full space)"
        assert ("proximal_steps" in full.info) == load
        assert relative_error(full) < 1e-10
        assert max(difference(condensed, full)) < (5e-10 if load else 1e-10)


@pytest.mark.skipif(not ndf.solvers.pardiso.available(), reason="needs MKL PARDISO")
@pytest.mark.parametrize("load", [False, True], ids=["displacement", "force"])
def test_full_space_newton_agrees_with_friction(non_matching, load):
    """Stick and slip at the pair's points (a tilted displacement of the top, or a shear load on the body held by
    contact): the full space and the condensed solver agree (sipg p = 2; measured u 2.5e-14 and 4.6e-14, forces
    7.8e-14 and 4.0e-13, multipliers 6.8e-13 and 4.6e-12)."""
    problem = tilted(patch_problem(False)) if not load else sheared(patch_problem(True))
    condensed = ndf.solve(problem, non_matching, order=2, formulation="condensed")
    full = ndf.solve(problem, non_matching, order=2, formulation="full-space")
    sticking = np.abs(condensed.info["pair_multiplier"]) < 1 - 1e-9
    assert np.any(sticking) and not np.all(sticking)
    u, forces = difference(condensed, full)
    assert u < 1e-12
    assert forces < 1e-11
    assert np.max(np.abs(condensed.info["pair_multiplier"] - full.info["pair_multiplier"])) < 1e-10


UZAWA_TOL = dict(solver_tol=1e-10, kkt_tol=1e-10)
"""Uzawa's tolerances in the comparisons with friction (the defaults, 1e-8 and 1e-6, left u 6.6e-7 and the pair
forces 1.5e-4 apart on the tilted load)."""
OTHER_SOLVERS = [("uzawa", {}), ("fixed_point", dict(inner="newton")), ("fixed_point", dict(inner="uzawa"))]


@pytest.mark.parametrize("solver, options", OTHER_SOLVERS, ids=["uzawa", "fixed_point-newton", "fixed_point-uzawa"])
@pytest.mark.parametrize("method", ["sipg", "nipg", "cg"])
def test_uzawa_and_the_fixed_point_solve_the_patch_test(non_matching, method, solver, options):
    """Uzawa's multiplier update and inner problem at the pair's points (``PairTerms`` of
    :mod:`ngdgfric.solvers.nonlinear`), and the fixed point around Uzawa or Newton (m_t = 0: one inner solve), on
    the displacement-driven patch test: exact, the condensed Newton's solution and pair forces reproduced (p = 2;
    measured at most 3.4e-15 ... 2.1e-14 and pair forces 1.1e-13)."""
    problem = patch_problem(load=False)
    newton = ndf.solve(problem, non_matching, method=method, order=2)
    other = ndf.solve(problem, non_matching, method=method, order=2, solver=solver, **options)
    assert relative_error(other) < 1e-10
    assert max(difference(newton, other)) < 1e-10
    assert other.info["pair_forces"][0].sum() == pytest.approx(P, rel=1e-10)


@pytest.mark.parametrize("solver, options", OTHER_SOLVERS, ids=["uzawa", "fixed_point-newton", "fixed_point-uzawa"])
def test_uzawa_and_the_fixed_point_agree_with_friction(non_matching, solver, options):
    """Stick and slip at the pair's points (the tilted displacement of the top): Uzawa to its tolerance
    (``UZAWA_TOL``: measured u 6.6e-11, pair forces 1.5e-8 relative, multipliers 3.4e-7; the fixed point around Uzawa
    stops Uzawa at its own solver_tol 1e-8: 6.6e-9, 1.5e-6, 3.4e-5) and the fixed point around Newton (exact: one
    inner solve) agree with the condensed Newton (sipg p = 2)."""
    problem = tilted(patch_problem(False))
    newton = ndf.solve(problem, non_matching, order=2)
    sticking = np.abs(newton.info["pair_multiplier"]) < 1 - 1e-9
    assert np.any(sticking) and not np.all(sticking)
    tolerances = dict(kkt_tol=1e-10) if solver == "fixed_point" else UZAWA_TOL
    other = ndf.solve(problem, non_matching, order=2, solver=solver, **options,
                      **({} if options.get("inner") == "newton" else tolerances))
    u, forces = difference(newton, other)
    loose = 100.0 if options.get("inner") == "uzawa" else 1.0
    assert u < 1e-9 * loose
    assert forces < 1e-6 * loose
    assert np.max(np.abs(newton.info["pair_multiplier"] - other.info["pair_multiplier"])) < 1e-5 * loose


def test_uzawa_refuses_a_body_held_by_contact_only(non_matching):
    """The force-driven patch test: Uzawa's inner matrix is singular while the upper body does not touch; a
    ValueError names the body, and the fixed point with Newton inside solves it (proximal steps)."""
    problem = patch_problem(load=True)
    with pytest.raises(ValueError, match=r"uzawa cannot solve a body held by contact only: nothing but the contact "
                                         r"pairs holds the translation in y of body 1 \(regions 'upper'\)"):
        ndf.solve(problem, non_matching, solver="uzawa")
    assert relative_error(ndf.solve(problem, non_matching, solver="fixed_point")) < 1e-10


def test_the_fixed_point_refuses_a_pair_bound_that_depends_on_the_penetration(non_matching):
    problem = dataclasses.replace(patch_problem(load=False), pairs=[ndf.ContactPair("c2", "c1", c_n=C_N, c_tau=0.1,
                                                                                    m_t=1.0)])
    with pytest.raises(ValueError, match=r"fixed_point does not freeze the friction bound of a contact pair \(m_t = 1"):
        ndf.solve(problem, non_matching, solver="fixed_point")
    with pytest.raises(ValueError, match=r"uzawa solves the reduced law m_t = 0 only"):
        ndf.solve(problem, non_matching, solver="uzawa")


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


def test_the_equilibrated_bound_refuses_pairs_with_its_reason(non_matching):
    """The equilibrated bound has no pair terms: it refuses pairs with its reason (estimate, equilibrate and adapt
    with estimator="equilibrated"); the estimator, adapt, the KKT residuals, the contact state, the force balance
    and the solvers have the pairs' terms (tests/test_pair_residuals.py, tests/test_pair_outputs.py)."""
    problem = patch_problem(load=False)
    sol = ndf.solve(problem, non_matching)
    for call in (lambda: ndf.equilibrate(sol), lambda: ndf.estimate(sol, kind="equilibrated"),
                 lambda: ndf.adapt(problem, non_matching, max_levels=1, estimator="equilibrated")):
        with pytest.raises(ValueError, match="refused: contact pairs .two bodies. are not built into it"):
            call()


# ---- the search (ngdgfric.contact.pairing) ----------------------------------------------------------------------

def arcs(gap=0.05):
    """A half-disk (radius 1, its arc 'c1') under a half-ring whose inner arc 'c2' (radius 1 + gap) faces it."""
    lower = ndf.Loop([(-1, 0), (1, 0)], ["bottom", "c1"], arcs={1: (0, 1)})
    r = 1 + gap
    upper = ndf.Loop([(r, 0), (1.5, 0), (-1.5, 0), (-r, 0)], ["r2", "top", "l2", "c2"], arcs={1: (0, 1.5), 3: (0, r)})
    return ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                              geometry=ndf.Domain({"lower": lower, "upper": upper}), dirichlet=("bottom", "top"),
                              traction=("r2", "l2"), contact=(), pairs=[ndf.ContactPair("c2", "c1", c_n=1.0)])


@pytest.mark.parametrize("order", [1, 3])
def test_the_bucket_search_finds_what_a_search_of_every_sample_finds(order):
    """The closest points on a curved side (the arc of radius 1, curved to degree ``order``, 0.05 h long edges)
    of points near it (within a cell of the bucket grid) and far from it (out to 3 radii, the search through the
    edges' boxes): the same nearest sample as the smallest of all points-by-samples distances (the first where
    several tie); after Newton's method the distance to the side is the least over every edge (each edge projected
    from its own nearest sample), to 1e-12: where the nearest sample is an edge's end, the point may lie across
    from the neighbouring edge (a tie of the two edges' end samples went to the lower edge, clamped at its end: on
    flat non-matching sides such points paired with a vertex instead of the edge across, and B's rows repeated)."""
    from ngdgfric.contact.curves import SideCurves

    problem = arcs()
    mesh = ndf.netgen_mesh(problem, {"lower": 0.05, "upper": 0.04})
    ndf.Discretization(problem, mesh, order=order)  # curves the mesh
    curves = SideCurves(mesh, "c1")
    rng = np.random.default_rng(7)
    angle, radius = rng.uniform(-0.3, np.pi + 0.3, 3000), np.concatenate([rng.uniform(0.97, 1.03, 2000),
                                                                          rng.uniform(0.0, 3.0, 1000)])
    xy = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    xy = np.concatenate([xy, curves.ends.reshape(-1, 2), curves.samples[::7, 5]])  # vertices and samples: ties
    samples = curves.samples.reshape(-1, 2)
    nearest = np.argmin(np.linalg.norm(xy[:, None, :] - samples[None], axis=2), axis=1)
    edge, s = curves.nearest_sample(xy)
    assert np.array_equal(edge, nearest // len(curves.grid))
    assert np.array_equal(s, curves.grid[nearest % len(curves.grid)])
    count, grid = len(curves.coefficients), len(curves.grid)
    per_edge = np.linalg.norm(xy[:, None, None, :] - curves.samples[None], axis=3).argmin(axis=2)  # (points, edges)
    every_edge = np.repeat(np.arange(count)[None], len(xy), axis=0)
    _, distance_every = curves.project(every_edge.ravel(), curves.grid[per_edge.ravel()], np.repeat(xy, count, axis=0))
    least = distance_every.reshape(len(xy), count).min(axis=1)
    found_edge, found_s, distance = curves.closest(xy)
    assert np.max(np.abs(distance - least)) < 1e-12
    assert np.max(np.abs(np.linalg.norm(curves.at(found_edge, found_s) - xy, axis=1) - distance)) < 1e-14
    assert grid == curves.samples.shape[1]


def test_the_cuts_are_those_of_every_vertex_and_edge():
    """The cuts of the pair's side (the outer arc, curved to degree 2) at the closest points of the other side's
    vertices: the same as projecting every vertex onto every edge (nearest sample, Newton) and keeping those inside
    the edge within reach, to 1e-12."""
    from ngdgfric.contact.curves import SideCurves
    from ngdgfric.contact.pairing import _breakpoints

    problem = arcs()
    mesh = ndf.netgen_mesh(problem, {"lower": 0.1, "upper": 0.077})
    ndf.Discretization(problem, mesh, order=2)
    curves, other = SideCurves(mesh, "c2"), SideCurves(mesh, "c1")
    reach = 0.3
    edge, s = _breakpoints(curves, other, reach)
    vertices = np.unique(np.round(other.ends.reshape(-1, 2), 14), axis=0)
    expected = []
    for e in range(len(curves.coefficients)):
        k = np.argmin(np.linalg.norm(vertices[:, None, :] - curves.samples[e][None], axis=2), axis=1)
        t, distance = curves.project(np.full(len(vertices), e), curves.grid[k], vertices)
        expected += [(e, value) for value in np.unique(t[(distance <= reach) & (t > 1e-12) & (t < 1 - 1e-12)])]
    assert len(expected) > len(curves.coefficients) // 2
    assert np.array_equal(edge, [e for e, _ in expected])
    assert np.max(np.abs(s - np.array([value for _, value in expected]))) < 1e-12


def overhang(lift=0.02):
    """Rollers at x = 0 and y = 0: the lower block [0, 1] x [0, 1] under an upper block [0, 1.5] x [1 + lift,
    1.5 + lift] that overhangs it by 0.5, pressed by the uniform pressure P on its top."""
    lower = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "right1", "c1", "left1"])
    upper = ndf.Loop([(0, 1 + lift), (1.5, 1 + lift), (1.5, 1.5 + lift), (0, 1.5 + lift)],
                     ["c2", "right2", "top", "left2"])
    return ndf.ContactProblem(E={"lower": E1, "upper": E2}, nu={"lower": NU1, "upper": NU2}, f=(0, 0),
                              g={"top": (0, -P)}, c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                              geometry=ndf.Domain({"lower": lower, "upper": upper}), dirichlet=(),
                              symmetry=("bottom", "left1", "left2"), traction=("right1", "right2", "top"),
                              contact=(), pairs=[ndf.ContactPair("c2", "c1", c_n=C_N)])


@pytest.mark.parametrize("method", ["sipg", "cg"])
def test_an_overhanging_block_is_held_by_the_side_beneath_it_only(method):
    """The pair's points of the upper block's bottom side lie over the lower block's top side only (x <= 1, their
    weights add up to its length 1): beyond its end nothing lies across, and the points there are left out, not
    given the gap to the end vertex.  The pair carries the whole applied force 1.5 P."""
    problem = overhang()
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, {"lower": 1 / 3, "upper": 1 / 5}), method=method, order=2)
    (_, points, _), = sol.contact.pairs
    assert np.max(points.xy[:, 0]) < 1 + 1e-12 and np.min(points.xy[:, 0]) > 0
    assert points.weight.sum() == pytest.approx(1.0, rel=1e-12)
    normal, _ = sol.info["pair_forces"]
    assert normal.sum() == pytest.approx(1.5 * P, rel=1e-8)


def test_a_closed_side_has_no_ends_and_keeps_every_point():
    """A block's flat side above a disc (its circle 'c1' a closed side: every vertex is shared by two edges): each
    point of the block's side within reach keeps its closest point, also those whose closest point is a vertex of
    the circle's straight (p = 1) edges with an offset across the vertex's corner."""
    from ngdgfric.contact.pairing import pair_points

    disc = ndf.Loop.circle((0, 0), 1.0, "c1")
    block = ndf.Loop([(-1, 1.3), (1, 1.3), (1, 1.6), (-1, 1.6)], ["c2", "right2", "top", "left2"])
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                                 geometry=ndf.Domain({"disc": disc, "block": block}), dirichlet=("top",),
                                 traction=("right2", "left2"), contact=(), pairs=[ndf.ContactPair("c2", "c1", c_n=1.0)])
    mesh = ndf.netgen_mesh(problem, 0.4)
    ndf.Discretization(problem, mesh, order=1)
    points = pair_points(mesh, problem.pairs[0], 2, reach=5.0)
    piece = points.piece  # the pieces' points: the integration of the jump
    assert len(piece.edge) == 2 * points.pieces
    assert np.sum((piece.other_s == 0) | (piece.other_s == 1)) >= 4


def strips(length=0.6, order=1):
    """Two strips 1/16 high on meshes that do not match (h = 1/64 above, 1.3/64 below), the upper one pressed and
    sheared by its top's displacement: stick and slip along the pair (the scene of benchmarks/bench_pairs.py)."""
    lower = ndf.Loop([(0, 0), (length, 0), (length, 1 / 16), (0, 1 / 16)], ["bottom", "right1", "c1", "left1"])
    upper = ndf.Loop([(0, 1 / 16), (length, 1 / 16), (length, 1 / 8), (0, 1 / 8)], ["c2", "right2", "top", "left2"])
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                                 geometry=ndf.Domain({"lower": lower, "upper": upper}), dirichlet=("bottom", "top"),
                                 traction=("right1", "left1", "right2", "left2"), contact=(),
                                 pairs=[ndf.ContactPair("c2", "c1", c_n=100.0, c_tau=0.002)],
                                 u_D={"top": (0.0005, -0.002)})
    return problem, ndf.netgen_mesh(problem, {"lower": 1.3 / 64, "upper": 1 / 64})


@pytest.mark.parametrize("order", [1, 2])
def test_the_rows_of_a_flat_non_matching_pair_are_independent(order):
    """On flat sides that do not match, every point of the pieces pairs with the point across, and the jump is
    projected onto the Gauss points of the pair side's edges (as many as the foundation's): the rows of B are
    independent, the least eigenvalue of the scaled Delassus operator W above 1e-12, so the solve takes the plain
    iteration (no proximal point method), in at most 10 iterations (measured 5 at p = 1, 2 at p = 2; the same strip on
    the rigid foundation: 9 and 10; with the law at the pieces' points: 28 and 36 or none, W singular)."""
    from ngdgfric.solvers.newton import NewtonState
    from ngdgfric.solvers.reduced import independent

    problem, mesh = strips(order=order)
    disc = ndf.Discretization(problem, mesh, method="sipg", order=order)
    contact = ndf.Contact(disc)
    (_, points, _), = contact.pairs
    piece = points.piece
    across = ndf.contact.curves.SideCurves(mesh, "c1").at(piece.other_edge, piece.other_s)
    assert np.max(np.abs(across - ndf.contact.curves.SideCurves(mesh, "c2").at(piece.edge, piece.s))) < 1e-12
    assert independent(NewtonState(disc, contact, contact.traces).reduced.W)
    sol = ndf.solve(problem, mesh, method="sipg", order=order)
    assert not any(step.startswith("proximal") for step in sol.info["steps"])
    assert sol.iterations <= 10
