"""The contact laws of ngdgfric.contact.laws: each CoefficientFunction against its numpy twin at random points, and
each against properties that do not come from its own formula (derivatives by finite differences, the
Fenchel-Young equality of the conjugate, the inverse of the pressure law, the range of the projections)."""

import ngsolve as ngs
import numpy as np
import pytest
from netgen.geom2d import unit_square

from ngdgfric.contact import laws

EXPONENTS = [0.0, 1.0, 2.0, 1.5]


@pytest.fixture(scope="module")
def points():
    """200 random points of the unit square as mapped points of a mesh, and their coordinates (the mesh is kept
    alive with them: mapped points refer to it)."""
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.3))
    xy = np.random.default_rng(7).uniform(0.01, 0.99, (200, 2))
    return mesh(xy[:, 0], xy[:, 1]), xy, mesh


def data(xy):
    """A gap that changes sign across the square, and varying c_n, c_tau, g_a (CoefficientFunctions and values)."""
    x, y = ngs.x, ngs.y
    cfs = dict(gap=0.3 * x - 0.2 * y + 0.05 * x * y - 0.04, c=2.0 + x * x + 3 * y, g_a=0.1 * x - 0.05)
    X, Y = xy[:, 0], xy[:, 1]
    values = dict(gap=0.3 * X - 0.2 * Y + 0.05 * X * Y - 0.04, c=2.0 + X * X + 3 * Y, g_a=0.1 * X - 0.05)
    return cfs, values


def at(cf, points):
    return np.asarray(cf(points)).ravel()


@pytest.mark.parametrize("m", EXPONENTS)
def test_pressure_bound_and_energies_agree_with_their_numpy_twins(points, m):
    mapped, xy, _ = points
    cf, v = data(xy)
    assert 0.2 < np.mean(v["gap"] > 0) < 0.8  # contact and separation among the points
    pairs = [(laws.pressure(cf["gap"], cf["c"], m), laws.pressure_values(v["gap"], v["c"], m)),
             (laws.bound(cf["gap"], cf["c"], m), laws.bound_rate(v["gap"], v["c"], m)[0]),
             (laws.compliance_energy(cf["gap"], cf["c"], m), laws.compliance_energy_values(v["gap"], v["c"], m)),
             (laws.friction_energy(cf["c"], cf["gap"]), laws.friction_energy_values(v["c"], v["gap"]))]
    if m > 0:
        pairs.append((laws.pressure_conjugate(ngs.IfPos(cf["gap"], cf["gap"], 0), cf["g_a"], cf["c"], m),
                      laws.pressure_conjugate_values(np.maximum(v["gap"], 0), v["g_a"], v["c"], m)))
    # measured: |difference| <= 1.2e-16 with values up to 1.1 (the gap is rounded differently in the two forms);
    # atol 1e-15 is ten times that
    for symbolic, numeric in pairs:
        assert np.allclose(at(symbolic, mapped) * np.ones(len(xy)), numeric, rtol=0, atol=1e-15)


@pytest.mark.parametrize("m", EXPONENTS)
def test_rates_are_the_derivatives(points, m):
    """p' and beta' against central differences of p and beta, away from the kink at d = 0."""
    _, xy, _ = points
    _, v = data(xy)
    d, c, h = v["gap"], v["c"], 1e-6
    away = np.abs(d) > 1e-3
    for law, rate in ((lambda g: laws.pressure_values(g, c, m), laws.pressure_rate_values(d, c, m)),
                      (lambda g: laws.bound_rate(g, c, m)[0], laws.bound_rate(d, c, m)[1])):
        difference = (law(d + h) - law(d - h)) / (2 * h)
        assert np.allclose(rate[away], difference[away], rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("m", [1.0, 2.0, 1.5])
def test_conjugate_meets_fenchel_young_with_equality_at_the_law(points, m):
    """phi(d) + phi*(t) >= t (d + g_a) for every t >= 0, with equality at t = p(d); (phi*)' = g_a + p^-1."""
    _, xy, _ = points
    _, v = data(xy)
    d, c, g_a = v["gap"], v["c"], v["g_a"]
    t = laws.pressure_values(d, c, m)
    equality = laws.compliance_energy_values(d, c, m) + laws.pressure_conjugate_values(t, g_a, c, m) - t * (d + g_a)
    assert np.allclose(equality, 0, atol=1e-15)
    other = np.random.default_rng(1).uniform(0, 2, len(d))
    assert np.all(laws.compliance_energy_values(d, c, m) + laws.pressure_conjugate_values(other, g_a, c, m)
                  - other * (d + g_a) >= -1e-15)
    inside = d > 0
    assert np.allclose(laws.pressure_inverse_values(t, c, m)[inside], d[inside], rtol=1e-12)
    h = 1e-6
    positive = np.random.default_rng(2).uniform(0.1, 1.0, len(d))
    derivative = (laws.pressure_conjugate_values(positive + h, g_a, c, m)
                  - laws.pressure_conjugate_values(positive - h, g_a, c, m)) / (2 * h)
    assert np.allclose(derivative, g_a + laws.pressure_inverse_values(positive, c, m), rtol=1e-7)
    second = (laws.pressure_inverse_values(positive + h, c, m) - laws.pressure_inverse_values(positive - h, c, m)) / (
        2 * h)
    assert np.allclose(laws.pressure_inverse_rate_values(positive, c, m), second, rtol=1e-7)


def test_projections_agree_and_map_onto_the_unit_interval(points):
    mapped, xy, _ = points
    z_cf = 6 * ngs.x - 3 + ngs.y
    z = 6 * xy[:, 0] - 3 + xy[:, 1]
    assert np.any(np.abs(z) > 1) and np.any(np.abs(z) < 1)
    for symbolic, numeric in ((laws.project_unit, laws.project_unit_values),
                              (laws.smooth_unit, laws.smooth_unit_values)):
        values = numeric(z)
        assert np.allclose(at(symbolic(z_cf), mapped), values, rtol=1e-14, atol=1e-15)
        assert np.all(np.abs(values) <= 1) and np.all(values[np.abs(z) >= 1] == np.sign(z[np.abs(z) >= 1]))
    inside = np.abs(z) < 1
    assert np.array_equal(laws.project_unit_values(z)[inside], z[inside])
    # smooth_unit is C^1: slope 1 at 0 and 0 at +-1
    h = 1e-7
    at_zero, near_one = (laws.smooth_unit_values(np.array([s + h, s - h])) for s in (0.0, 1 - 1e-4))
    assert (at_zero[0] - at_zero[1]) / (2 * h) == pytest.approx(1, rel=1e-6)
    assert abs(near_one[0] - near_one[1]) / (2 * h) < 1e-3


def test_no_penetration_no_force():
    d = np.array([-1.0, -1e-12, 0.0])
    for m in EXPONENTS[1:]:
        assert np.all(laws.pressure_values(d, 3.0, m) == 0) and np.all(laws.pressure_rate_values(d, 3.0, m) == 0)
        assert np.all(laws.bound_rate(d, 3.0, m)[0] == 0)
    assert np.all(laws.bound_rate(d, 3.0, 0.0)[0] == 3.0)  # the reduced law (1.10): c_tau wherever
