"""ngdgfric.studies.curved: Hertz on a curved half-disk, the discrete energy, fits, and optimal rates on an
annulus with curved elements (the lost order without curving)."""

import dataclasses
import math

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.reference import energy_norm_squared_parts
from ngdgfric.studies.curved import (
    annulus_problem,
    discrete_energy,
    fit_algebraic,
    fit_exponential,
    half_disk,
    half_width,
    hertz_measures,
    hertz_problem,
    inscribed,
    reference_error,
    uniform_meshes,
)


@pytest.fixture(scope="module")
def hertz_run():
    """A coarse hp run of the Hertz problem (a / R ~ 0.03, c_n a / E* ~ 3000) and its last solution with an
    estimate at least 30 times the final one."""
    problem = hertz_problem(0.002, 1e5)
    levels = []

    def keep(level, sol, est):
        levels.append(dict(sol=sol, eta_h=est.eta_h))

    run = ndf.adapt(problem, ndf.netgen_mesh(problem, 0.25), rtol=3e-3, keep=keep, progress=None, solver_tol=1e-11)
    return run, [level for level in levels if level["eta_h"] >= 30 * run.estimate.eta_h][-1]


def test_half_disk_polygon_is_inscribed_with_a_vertex_at_the_lowest_point():
    polygon = half_disk(1.0, sides=8)
    v = np.asarray(polygon.vertices)
    np.testing.assert_allclose(np.hypot(v[:, 0], v[:, 1] - 1.0), 1.0, atol=1e-15)
    assert (0.0, 0.0) in polygon.vertices and polygon.labels.count("contact") == 8
    assert polygon.area == pytest.approx(8 * 0.5 * math.sin(math.pi / 8))  # 8 triangles with the centre (0, 1)
    assert half_disk(1.0).area == pytest.approx(math.pi / 2, rel=1e-14)


def test_half_width_is_the_zero_of_the_interpolated_penetration():
    x = np.linspace(-1, 1, 201)
    a, left, right = half_width(x, 0.09 - x**2)  # a parabola: linear interpolation is off by O(dx^2)
    assert a == pytest.approx(0.3, abs=1e-4) and left == pytest.approx(-right)
    assert all(math.isnan(value) for value in half_width(x, -1 - x**2))


def test_fits_recover_exponential_and_algebraic_laws():
    n = np.array([1e3, 3e3, 1e4, 3e4, 1e5])
    b, rms = fit_exponential(n, 2 * np.exp(-0.3 * n ** (1 / 3)))
    assert b == pytest.approx(0.3, rel=1e-10) and rms < 1e-12
    s, rms = fit_algebraic(n, 5 * n**-1.5)
    assert s == pytest.approx(1.5, rel=1e-10) and rms < 1e-12
    assert fit_algebraic(n, np.exp(-0.3 * n ** (1 / 3)))[1] > fit_exponential(n, np.exp(-0.3 * n ** (1 / 3)))[1]


@pytest.mark.slow
def test_coarse_hp_run_matches_hertz_within_two_percent(hertz_run):
    run, _ = hertz_run
    m = hertz_measures(run.solution)
    assert m["holes"] == 0  # one contact interval, symmetric about x = 0
    assert m["x_left"] == pytest.approx(-m["x_right"], rel=1e-3)
    assert m["F"] == pytest.approx(m["F_n"], rel=1e-3)  # the contact zone is nearly flat (a / R ~ 0.03)
    assert 0.02 < m["a"] < 0.04
    assert abs(m["rel_a"]) < 0.02 and abs(m["rel_p0"]) < 0.02
    assert m["p0"] == pytest.approx(m["p_max"], rel=1e-2)  # the peak is at x = 0


def test_discrete_solution_minimises_the_discrete_energy():
    problem = hertz_problem(0.01, 1e3)
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.2), order=2, solver_tol=1e-12)
    assert np.count_nonzero(ndf.contact_state(sol)["gap"] > 0) > 0  # the contact law is active
    direction = np.random.default_rng(1).standard_normal(sol.ndof)

    def energy(t):
        u = ngs.GridFunction(sol.u.space)
        u.vec.FV().NumPy()[:] = sol.u.vec.FV().NumPy() + t * direction
        return discrete_energy(dataclasses.replace(sol, u=u))

    centre = energy(0.0)
    rises = []
    for t in (1e-5, 1e-6):  # small enough to keep the contact set: J_h is quadratic there
        plus, minus = energy(t) - centre, energy(-t) - centre
        assert plus > 0 and minus > 0
        assert abs(plus - minus) < 1e-8 * (plus + minus)  # no first-order term: J_h'(u_h) = 0
        rises.append(plus)
    assert rises[0] == pytest.approx(100 * rises[1], rel=1e-6)


def test_reference_error_of_a_solution_against_itself_is_its_jump_part():
    problem = hertz_problem(0.002, 1e3)
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.25), order=3)
    volume, _ = energy_norm_squared_parts(sol.discretization.problem, sol.mesh, sol.u)
    jumps = ndf.energy_norm(sol) ** 2 - volume  # with [u_h] = u_h - u_D on Gamma_D
    assert jumps > 0
    assert reference_error(sol, sol) ** 2 == pytest.approx(jumps, rel=1e-6)


@pytest.mark.slow
def test_energy_and_pointwise_reference_errors_agree(hertz_run):
    run, early = hertz_run
    sol, reference = early["sol"], run.solution
    by_energy = math.sqrt(2 * (discrete_energy(sol) - discrete_energy(reference)))
    assert reference_error(sol, reference) == pytest.approx(by_energy, rel=0.15)


@pytest.fixture(scope="module")
def annulus_meshes():
    problem, u = annulus_problem()
    return problem, u, uniform_meshes(ndf.netgen_mesh(problem, 0.5), 3)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["sipg", "bassi"])
@pytest.mark.parametrize("order", [1, 2])
def test_curved_meshes_give_the_optimal_rates_for_error_and_estimator(annulus_meshes, method, order):
    problem, u, meshes = annulus_meshes
    hs, errors, etas = [], [], []
    for mesh in meshes[1:]:
        sol = ndf.solve(problem, mesh, method=method, order=order)
        hs.append(ndf.meshes.element_diameters(mesh).max())
        errors.append(ndf.energy_norm(sol, u))
        etas.append(ndf.estimate(sol).eta_h)
    rate, eta_rate = (np.polyfit(np.log(hs), np.log(values), 1)[0] for values in (errors, etas))
    assert rate == pytest.approx(order, abs=0.15)
    assert eta_rate == pytest.approx(order, abs=0.3)


@pytest.mark.slow
def test_straight_boundary_edges_lose_the_order_of_p3(annulus_meshes):
    problem, u, meshes = annulus_meshes
    curved, straight = [], []
    for mesh in meshes[1:3]:
        curved.append(ndf.energy_norm(ndf.solve(problem, mesh, order=3), u))
        polygonal, rebuilt = inscribed(problem, mesh)
        assert rebuilt.ne == mesh.ne and not polygonal.geometry.curved
        straight.append(ndf.energy_norm(ndf.solve(polygonal, rebuilt, order=3), u))
    assert np.log2(curved[0] / curved[1]) > 2.7
    assert np.log2(straight[0] / straight[1]) < 2.3
    assert straight[1] > 3 * curved[1]
