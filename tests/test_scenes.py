"""The user scenes of ngdgfric.studies.scenes: their exact solutions satisfy their laws, Hertz's formulas."""

import math

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.adaptivity import minimum_angle
from ngdgfric.problem import strain_of, stress
from ngdgfric.studies.scenes import SCENES, hertz_solution, layers_indented


def test_hertz_pressure_integrates_to_the_force_and_the_half_width_matches_the_indentation_curvature():
    force, E, nu, radius = 2.3e-3, 1.0, 0.3, 1.0
    a, p0 = hertz_solution(force, E, nu, radius)
    x = np.linspace(-a, a, 200001)
    assert np.trapezoid(p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None)), x) == pytest.approx(force, rel=1e-6)
    # Johnson (4.43): p0 = E* a / (2 R)
    assert p0 == pytest.approx(E / (1 - nu**2) * a / (2 * radius), rel=1e-12)


@pytest.mark.parametrize("c", [0.5, 1 / 3])
def test_the_layered_exact_solution_satisfies_the_compliance_law_and_equilibrium(c):
    scene = layers_indented(c=c)
    problem, exact = scene.problem, scene.exact
    mesh = scene.mesh(0)
    sigma = stress(problem, strain_of(exact))
    # uniaxial: sigma_yy = -P everywhere, sigma_xx = sigma_xy = 0 (traction-free sides, div sigma = 0)
    points = mesh(np.linspace(0.05, 0.95, 7), np.linspace(0.02, 0.98, 7))
    values = np.asarray(sigma(points)).reshape(-1, 4)
    pressure = -values[0, 3]
    assert np.allclose(values[:, 3], -pressure) and np.allclose(values[:, :3], 0, atol=1e-14)
    # on top (Gamma_C, n = (0, 1)): sigma_n = -c_n (u_n - g_a)_+ with u_n = u_y(1), g_a = -d
    top = np.asarray(exact(mesh(0.5, 1.0))).ravel()[1]
    assert -pressure == pytest.approx(-problem.c_n * (top - problem.g_a), rel=1e-12)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_every_scene_has_a_family_of_meshes_that_fit_it(name):
    scene = SCENES[name]()
    meshes = [scene.mesh(k) for k in range(2)]
    for mesh in meshes:
        ndf.check_mesh(scene.problem, mesh)
    assert 2 < meshes[1].ne / meshes[0].ne < 6  # two to four times the elements per level (Netgen: fewer)
    assert scene.levels >= 3 and scene.description


def test_the_wedge_has_triangles_as_thin_as_its_tip():
    scene = SCENES["wedge"]()
    assert minimum_angle(scene.mesh(0)) == pytest.approx(6.6, abs=1e-6)
    assert math.degrees(math.atan2(scene.problem.geometry.vertices[2][1], 2)) == pytest.approx(6.6)


def test_the_strips_jump_lies_on_element_edges():
    scene = SCENES["strip"]()
    sol = ndf.solve(scene.problem, scene.mesh(0), order=1)
    material = sol.discretization.material
    assert material.jumps and material.unresolved == 0 and material.mu.space.globalorder == 0
    assert ngs.Integrate(material.mu, sol.mesh) == pytest.approx(4 * (1e3 + 1e5) / 2.6, rel=1e-12)
