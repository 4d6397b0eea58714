"""The problem files shipped in ngdgfric/data (the paper's examples and the scenes of ngdgfric.examples.SCENES):
every one solves through the command line to a KKT-clean solution, and each scene carries the data its comment
describes and behaves as its physics says."""

import dataclasses
import math
import subprocess
import sys

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric import cli, commands
from ngdgfric.contact import contact_state
from ngdgfric.domain import Arc, Domain
from ngdgfric.examples import SCENES, example
from ngdgfric.problem_file import example_file, shipped_files

MAXH = 0.25  # coarse: the whole file runs in seconds


def solve_by_command_line(path, tmp_path, monkeypatch, *options):
    """``ngdgfric solve PATH --maxh MAXH`` through :func:`ngdgfric.cli.run`; (its record, the Solution it made)."""
    solutions = []

    def keep(*args, **kwargs):
        solutions.append(ndf.solve(*args, **kwargs))
        return solutions[-1]

    monkeypatch.setattr(commands, "solve", keep)
    (record,) = cli.run(["solve", str(path), "--maxh", str(MAXH), "--out", str(tmp_path), *options])
    (sol,) = solutions
    return record, sol


def test_the_scenes_are_shipped_and_loadable_by_name():
    assert set(SCENES) == {"half_disk", "block_with_hole", "two_materials_symmetric", "indentation", "rubber_pad",
                           "two_cylinders"}
    assert set(shipped_files()) == {"6.1", "6.2", *SCENES}
    for name in SCENES:
        assert example_file(name).name == f"{name}.toml"
        problem = example(name)
        assert isinstance(problem, ndf.ContactProblem) and problem.name != name  # each file names its scene
    with pytest.raises(ValueError, match="half_disk"):
        example("half_disc")


@pytest.mark.parametrize("name", sorted(shipped_files()))
def test_every_shipped_file_solves_through_the_command_line(name, tmp_path, monkeypatch):
    path = example_file(name)
    record, sol = solve_by_command_line(path, tmp_path, monkeypatch)
    assert record["ndof"] == sol.ndof and record["mesh"] == f"Netgen maxh = {MAXH:g}"
    assert record["energy_norm"] > 0 and math.isfinite(record["eta_h"])
    kkt = ndf.kkt_residuals(sol)
    assert kkt["lam_excess"] <= 1e-12 and kkt["complementarity"] <= 1e-10
    # a body held by contact only (two_cylinders): the laws at the traces of u_h differ from the solver's forces by
    # round-off that the free body's compliance 1 / eps in W and the stiff c_n = 1e5 amplify (measured 5.2e-9 for
    # sipg p = 1 here, 7.8e-8 for cg; the equilibrium with the solver's forces 2e-13)
    assert kkt["equilibrium"] <= (1e-8 if sol.problem.pairs else 1e-9)
    for suffix in ("csv", "vtu", "png"):
        assert (tmp_path / f"{path.stem}_{record['method']}_p1.{suffix}").stat().st_size > 0


@pytest.mark.slow  # a fresh process
def test_a_scene_file_in_a_fresh_process(tmp_path):
    done = subprocess.run([sys.executable, "-m", "ngdgfric", "solve", str(example_file("half_disk")), "--maxh", "0.5",
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("Half-disk on a plane: Netgen maxh = 0.5")
    assert (tmp_path / "half_disk_sipg_p1.csv").exists()


def solved(name):
    problem = example(name)
    return problem, ndf.solve(problem, ndf.netgen_mesh(problem, MAXH))


def test_half_disk():
    """Radius 1, centre (0, 1), flat side on top pushed down by 0.01; frictionless, c_n = 1e4 E, m_n = 1,
    g_a = y / (1 - y) (the distance to y = 0 along the normal (x, y - 1)) clipped at 10."""
    problem, sol = solved("half_disk")
    (name, loop), = problem.geometry.regions
    arc, top = loop.sides()
    assert isinstance(arc, Arc) and arc.centre == pytest.approx((0, 1), abs=1e-15) and arc.radius == 1.0
    assert top == ((1.0, 1.0), (-1.0, 1.0)) and loop.labels == ("contact", "top")
    assert (problem.dirichlet, problem.contact, problem.u_D) == ("top", "contact", (0.0, -0.01))
    assert (problem.c_tau, problem.m_n, problem.c_n) == (0.0, 1.0, 1e4 * problem.E)
    mesh = sol.mesh
    for y in (0.0, 0.3, 0.5, 0.9):  # the gap along the normal from (x, y) on the circle
        assert problem.g_a(mesh(0.0, y)) == pytest.approx(y / (1 - y), rel=1e-14, abs=1e-15)
    assert problem.g_a(mesh(0.0, 0.95)) == 10.0  # clipped, finite up to y = 1
    state = contact_state(sol)
    touching = state["pressure"] > 0
    assert touching.any() and np.all(np.abs(state["x"][touching]) < 0.2)  # a small patch below the centre
    assert sol.u(mesh(0.0, 1 - 1e-9)) == pytest.approx((0.0, -0.01), abs=1e-3)


def test_block_with_hole():
    problem, sol = solved("block_with_hole")
    assert isinstance(problem.geometry, Domain) and len(problem.geometry.holes) == 1
    assert problem.geometry.area == pytest.approx(2 - math.pi / 16, rel=1e-12)
    assert problem.g == {"load": (0.0, -5.0)} and problem.dirichlet == "support"
    assert set(problem.traction) == {"load", "free", "hole"}
    state = contact_state(sol)
    below = (state["x"] > 0.5) & (state["x"] < 1.5)
    pressure = state["pressure"][below]
    assert np.all(pressure > 0)  # the loaded third presses on the foundation ...
    weakest = state["x"][below][np.argmin(pressure)]
    assert abs(weakest - 1.0) < 0.1 and pressure.min() < 0.5 * pressure.max()  # ... around the hole, not under it


def test_two_materials_symmetric():
    problem, sol = solved("two_materials_symmetric")
    assert problem.geometry.region_names == ("rubber", "steel")
    assert problem.E == {"rubber": 10.0, "steel": 1000.0} and problem.nu == {"rubber": 0.4, "steel": 0.3}
    assert problem.symmetry == ("axis",) and problem.u_D == (0.0, -0.01)
    rubber, steel = (loop for _, loop in problem.geometry.regions)
    assert rubber.labels[2] == steel.labels[0] == "interface"
    mesh = sol.mesh
    assert ngs.Integrate(sol.discretization.material.mu, mesh) == pytest.approx(
        0.4 * 10 / 2.8 + 0.6 * 1000 / 2.6, rel=1e-12)  # each region its own material
    u_axis = np.array([sol.u(mesh(1e-9, y)) for y in (0.1, 0.5, 0.9)])
    u_side = np.array([sol.u(mesh(1 - 1e-9, y)) for y in (0.1, 0.5, 0.9)])
    assert np.max(np.abs(u_axis[:, 0])) < 0.02 * np.max(np.abs(u_side[:, 0]))  # u . n = 0 on the symmetry plane


def test_indentation():
    problem, sol = solved("indentation")
    assert problem.u_D == {"punch": (0.0, -0.02)} and problem.dirichlet == "punch" and problem.traction == "free"
    mesh = sol.mesh
    assert sol.u(mesh(0.0, 1 - 1e-9)) == pytest.approx((0.0, -0.02), abs=2e-3)  # the punch pushes 0.02 ...
    assert abs(sol.u(mesh(0.9, 1 - 1e-9))[1]) < 0.1 * 0.02  # ... the free top far from it hardly moves
    state = contact_state(sol)
    pressure, x = state["pressure"], np.abs(state["x"])
    assert np.mean(pressure[x < 0.3]) > 1.5 * np.mean(pressure[x > 0.7])  # the foundation carries it below the punch


def test_two_cylinders():
    """The two quarter cylinders of ngdgfric.studies.two_cylinders written as a file: the same problem (materials per
    region, the arcs, the pressure P / 2 on the top, the pair arc2 against arc1 with c_n = 1e5), two bodies touching
    at the origin, the upper one held by the contact only (its rigid motion in y free for B_h)."""
    from ngdgfric.studies.two_cylinders import two_cylinders

    problem = example("two_cylinders")
    made, P = two_cylinders()
    assert dataclasses.replace(problem, name=made.name) == made
    assert problem.geometry.bodies == (("lower",), ("upper",)) or len(problem.geometry.bodies) == 2
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, MAXH), order=2)
    assert sol.info["proximal_steps"] >= 1  # load control: the proximal steps held the upper body
    (side, other, on_side, on_other, _), = ndf.force_balance(sol).pair_resultants()
    assert (side, other) == ("arc2", "arc1")
    assert on_side[1] == pytest.approx(P / 2, rel=1e-10) and on_other[1] == pytest.approx(-P / 2, rel=1e-10)
