"""Data per named part (ngdgfric/problem.py, forms.py, liftings.py): several sides per boundary part, symmetry
sides, prescribed displacements, data per region and per side; each checked against an equivalent problem
written another way, to round-off, for all five methods."""

import dataclasses
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest
from mirror import mirrored

import ngdgfric as ndf
from ngdgfric.domain import Domain, Loop
from ngdgfric.meshes import mesh_arrays

METHODS = list(ndf.METHODS)  # the five DG methods and the conforming baseline
COMMON = dict(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=1e2, m_n=1, g_a=0.0, c_tau=0.01)


@pytest.fixture(scope="module")
def symmetric_scene():
    half = ndf.ContactProblem(**COMMON, geometry=ndf.Polygon.rectangle(0, 0, 1, 1, bottom="contact",
                                                                       right="traction", top="dirichlet", left="axis"),
                              symmetry="axis", u_D=(0, -0.05))
    full = ndf.ContactProblem(**COMMON, geometry=ndf.Polygon.rectangle(-1, 0, 1, 1, bottom="contact",
                                                                       right="traction", top="dirichlet",
                                                                       left="traction"), u_D=(0, -0.05))
    return half, full, *mirrored(half, full)


@pytest.mark.parametrize("method", ndf.DG_METHODS)  # cg: continuity across the mirror line is not Nitsche's u . n = 0
@pytest.mark.parametrize("order", [1, 3])
def test_half_a_symmetric_scene_with_a_symmetry_side_is_the_whole_to_round_off(symmetric_scene, method, order):
    half, full, half_mesh, full_mesh = symmetric_scene
    a = ndf.solve(half, half_mesh, method=method, order=order)
    b = ndf.solve(full, full_mesh, method=method, order=order)
    assert ndf.energy_norm(a) ** 2 == pytest.approx(ndf.energy_norm(b) ** 2 / 2, rel=1e-12)
    assert ndf.kkt_residuals(a)["equilibrium"] < 1e-12 and ndf.contact_state(a)["pressure"].max() > 0


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("order", [1, 2])
def test_a_prescribed_displacement_equals_the_shifted_gap(method, order):
    """u_D = (0, -d) on the top of a block on a foundation is the rigid motion (0, -d) of the problem with
    u_D = 0 and the gap g_a - d: u_h(u_D) = u_h(g_a - d) + (0, -d) exactly (no strain, jumps unchanged)."""
    data = dict(COMMON, g=(0.0, -0.02), m_n=1.5, c_tau=0.05)
    geometry = ndf.Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="traction", top="dirichlet",
                                     left="traction")
    d = 0.03
    pushed = ndf.ContactProblem(**{**data, "g_a": 0.01}, geometry=geometry, u_D=(0, -d))
    shifted = ndf.ContactProblem(**{**data, "g_a": 0.01 - d}, geometry=geometry)
    mesh = ndf.netgen_mesh(pushed, 0.3)
    a = ndf.solve(pushed, mesh, method=method, order=order, solver_tol=1e-13)
    b = ndf.solve(shifted, mesh, method=method, order=order, solver_tol=1e-13)
    shift = ngs.GridFunction(b.u.space)
    shift.Set(ngs.CF((0, -d)))
    difference = a.u.vec.FV().NumPy() - b.u.vec.FV().NumPy() - shift.vec.FV().NumPy()
    assert np.abs(difference).max() < 1e-13 and ndf.contact_state(a)["pressure"].max() > 0
    assert ndf.kkt_residuals(a)["equilibrium"] < 1e-13


def test_a_prescribed_displacement_as_a_function_is_reproduced():
    """u = a rigid rotation plus a uniaxial strain, prescribed on top and bottom as functions of x, y, with
    nu = 0 and free sides (sigma n = 0 there), no contact and no friction (c_tau = 0: the reduced law (1.10)
    has friction without contact): u is affine, in V_h, and every method reproduces it."""
    u = ngs.CF((-0.01 * ngs.y, 0.01 * ngs.x - 0.02 * ngs.y))
    geometry = ndf.Polygon.rectangle(0, 0, 1, 1, bottom="dirichlet", right="traction", top="dirichlet",
                                     left="contact")
    problem = ndf.ContactProblem(**{**COMMON, "nu": 0.0, "g_a": 1.0, "c_tau": 0.0}, geometry=geometry, u_D=u)
    mesh = ndf.netgen_mesh(problem, 0.4)
    for method in METHODS:
        for order in (1, 2):
            sol = ndf.solve(problem, mesh, method=method, order=order)
            assert ndf.energy_norm(sol, u) < 1e-12, (method, order)


def test_several_contact_sides_with_their_own_data_equal_one_side_with_piecewise_data():
    vertices = [(0, 0), (1, 0), (2, 0), (2, 1), (0, 1)]
    split = ndf.Polygon(vertices, ["c1", "c2", "free", "top", "free"])
    one = ndf.Polygon(vertices, ["contact", "contact", "free", "top", "free"])
    data = dict(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), m_n=1, geometry=split, dirichlet="top", traction="free",
                u_D=(0.01, -0.05))
    parts = ndf.ContactProblem(**data, contact=["c1", "c2"], c_n={"c1": 1e3, "c2": 10.0},
                               g_a={"c1": 0.0, "c2": 0.01}, c_tau={"c1": 0.5, "c2": 0.01})
    jump = lambda a, b: ngs.IfPos(ngs.x - 1, b, a)  # noqa: E731
    whole = ndf.ContactProblem(**{**data, "geometry": one}, contact="contact", c_n=jump(1e3, 10.0),
                               g_a=jump(0.0, 0.01), c_tau=jump(0.5, 0.01))
    mesh_parts, mesh_whole = ndf.netgen_mesh(parts, 0.25), ndf.netgen_mesh(whole, 0.25)
    assert np.array_equal(mesh_arrays(mesh_parts)[1], mesh_arrays(mesh_whole)[1])
    for method in ("sipg", "bassi"):
        a, b = ndf.solve(parts, mesh_parts, method=method, order=2), ndf.solve(whole, mesh_whole, method=method,
                                                                               order=2)
        assert np.abs(a.u.vec.FV().NumPy() - b.u.vec.FV().NumPy()).max() < 1e-12
        state = ndf.contact_state(a)
        assert state["pressure"].max() > 0 and np.abs(state["lam_tau"]).max() > 0.99  # contact and slip


@pytest.mark.slow
def test_material_per_region_gives_the_exact_layered_solution_on_a_netgen_mesh():
    """E = 1 below y = 1/2 and 100 above as two regions, nu = 0, fixed at the bottom, pressure 1 on top: the
    exact u_y is piecewise linear; Netgen's mesh follows the interface, so every method reproduces it."""
    soft = Loop([(0, 0), (1, 0), (1, 0.5), (0, 0.5)], ["bottom", "free", "mid", "wall"])
    hard = Loop([(0, 0.5), (1, 0.5), (1, 1), (0, 1)], ["mid", "free", "top", "wall"])
    problem = ndf.ContactProblem(E={"soft": 1.0, "hard": 100.0}, nu=0.0, f=(0, 0), g={"top": (0.0, -1.0)},
                                 c_n=1.0, m_n=1, g_a=1.0, c_tau=0.0, geometry=Domain({"soft": soft, "hard": hard}),
                                 dirichlet="bottom", traction=["top", "free"], contact="wall")
    exact = ngs.CF((0, ngs.IfPos(ngs.y - 0.5, -0.5 - (ngs.y - 0.5) / 100, -ngs.y)))
    mesh = ndf.netgen_mesh(problem, 0.3)
    for method in METHODS:
        for order in (1, 2):
            sol = ndf.solve(problem, mesh, method=method, order=order)
            assert ndf.energy_norm(sol, exact) < 1e-11 * ndf.energy_norm(sol), (method, order)


def test_dict_data_are_checked_against_the_parts():
    geometry = ndf.Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="traction", top="dirichlet",
                                     left="traction")
    with pytest.raises(ValueError, match="c_n has no value for contact side 'c2'"):
        ndf.ContactProblem(**{**COMMON, "c_n": {"c1": 1.0}}, geometry=dataclasses.replace(
            geometry, labels=("c1", "traction", "dirichlet", "c2")), contact=["c1", "c2"])
    with pytest.raises(ValueError, match="E: 'steel' is not a region"):
        ndf.ContactProblem(**{**COMMON, "E": {"steel": 1.0}}, geometry=geometry)
    with pytest.raises(ValueError, match=r"g\['top'\] must have 2 real components|g: 'top' is not a traction"):
        ndf.ContactProblem(**{**COMMON, "g": {"top": 1.0}}, geometry=geometry)
    with pytest.raises(ValueError, match=r"m_n\['contact'\] must be >= 1"):
        ndf.ContactProblem(**{**COMMON, "m_n": {"contact": 0.5}}, geometry=geometry)
    with pytest.raises(ValueError, match=r"m_t\['contact'\] must be a number"):
        ndf.ContactProblem(**{**COMMON, "m_t": {"contact": ngs.x}}, geometry=geometry)
    with pytest.raises(ValueError, match="in both traction and symmetry"):
        ndf.ContactProblem(**COMMON, geometry=geometry, symmetry="traction")
    with pytest.raises(ValueError, match=r"nu\['omega'\] must be < 0.5"):
        ndf.ContactProblem(**{**COMMON, "nu": {"omega": 0.5}}, geometry=geometry)


def test_adapt_stops_at_a_relative_tolerance(tmp_path):
    problem = ndf.ContactProblem(**COMMON, geometry=ndf.Polygon.rectangle(0, 0, 1, 1, bottom="contact",
                                                                          right="traction", top="dirichlet",
                                                                          left="traction"), u_D=(0, -0.05))
    run = ndf.adapt(problem, rtol=0.02, progress=None, max_levels=30)
    last = run.levels[-1]
    assert run.stopped == "tol"
    assert last["target"] == pytest.approx(0.02 * ndf.energy_norm(run.solution), rel=1e-12)
    assert last["eta_h"] <= last["target"] and all(r["eta_h"] > r["target"] for r in run.levels[:-1])
    with pytest.raises(ValueError, match="rtol must be a finite number >= 0, got -1.0"):
        ndf.adapt(problem, rtol=-1.0)


def test_contact_sides_with_their_own_exponents():
    """m_n = 1.5 and 1, m_t = 1 and 0 on two contact sides: the Newton solver (exponents per Gauss point) and
    the fixed point on the friction bound (the symbolic law side by side) agree, and the KKT system holds."""
    vertices = [(0, 0), (1, 0), (2, 0), (2, 1), (0, 1)]
    data = dict(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), geometry=ndf.Polygon(vertices, ["c1", "c2", "free", "top", "free"]),
                dirichlet="top", traction="free", contact=["c1", "c2"], u_D=(0.02, -0.05), c_n=1e2, g_a=0.0,
                c_tau={"c1": 20.0, "c2": 0.01})
    problem = ndf.ContactProblem(**data, m_n={"c1": 1.5, "c2": 1.0}, m_t={"c1": 1.0, "c2": 0.0})
    mesh = ndf.netgen_mesh(problem, 0.3)
    newton = ndf.solve(problem, mesh, order=2, solver_tol=1e-12)
    fixed = ndf.solve(problem, mesh, order=2, solver="fixed_point", solver_tol=1e-12)
    scale = np.abs(newton.u.vec.FV().NumPy()).max()
    assert np.abs(newton.u.vec.FV().NumPy() - fixed.u.vec.FV().NumPy()).max() < 1e-8 * scale
    assert ndf.kkt_residuals(newton)["equilibrium"] < 1e-11
    state = ndf.contact_state(newton)
    first = state["x"] < 1
    assert state["pressure"][first].max() > 0 and state["pressure"][~first].max() > 0
    same = ndf.ContactProblem(**data, m_n={"c1": 1.5, "c2": 1.5}, m_t={"c1": 1.0, "c2": 1.0})
    number = ndf.ContactProblem(**data, m_n=1.5, m_t=1.0)
    a, b = ndf.solve(same, mesh, order=2), ndf.solve(number, mesh, order=2)
    assert np.array_equal(a.u.vec.FV().NumPy(), b.u.vec.FV().NumPy())


@pytest.mark.slow
def test_the_scene_of_the_guide_reaches_its_relative_tolerance(capsys):
    """The code block under "Regions, holes, curved sides" on the user guide's page on scenes, as written (regions,
    a hole, a symmetry side, u_D, two contact sides with their own data, adapt(rtol=1e-2))."""
    page = Path(__file__).resolve().parents[1] / "docs" / "user_guide" / "scenes.md"
    code = page.read_text().split("## Regions, holes, curved sides", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    namespace = {}
    exec(compile(code, str(page), "exec"), namespace)
    run = namespace["run"]
    assert run.stopped == "tol" and run.levels[-1]["eta_h"] <= 1e-2 * ndf.energy_norm(run.solution)
    assert ndf.kkt_residuals(run.solution)["equilibrium"] < 1e-12
    assert len(run.levels) <= 12  # 10 levels, 12k DOFs when written
