"""Stored reference solutions: the file is validated and must belong to the problem (ngdgfric.reference)."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.reference import difference, energy_norm_squared_parts, reference_errors


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """(folder, problem): a P1 reference of Example 6.1 on h = 1/2 saved as a.npz, one of 6.2 as other.npz."""
    folder = tmp_path_factory.mktemp("references")
    for name, problem in (("a", ndf.example_6_1()), ("other", ndf.example_6_2())):
        sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
        ndf.save_reference(sol, folder / f"{name}.npz", eta_h=0.5)
    return folder, ndf.example_6_1()


def tampered(folder, change, name="bad.npz"):
    with np.load(folder / "a.npz") as archive:
        data = {key: archive[key] for key in archive.files}
    change(data)
    np.savez(folder / name, **data)
    return folder / name


def test_round_trip_keeps_everything(saved):
    folder, problem = saved
    reference = ndf.load_reference(folder / "a.npz", problem)
    assert reference.eta_h == 0.5 and reference.mesh.ne == 8
    assert not list(folder.glob(".*"))  # no temporary file left by the atomic write


def test_reference_of_another_problem_is_refused(saved):
    folder, problem = saved
    # Example 6.2's reference loaded for 6.1 failed later with "Meshpoint 0 not in mesh!"
    with pytest.raises(ValueError, match="other.npz: made for another problem: its polygon"):
        ndf.load_reference(folder / "other.npz", problem)
    for change, message in (({"E": 2001.0}, "E = 2000 there, 2001 here"), ({"nu": 0.3}, r"\(nu, m_n, m_t\)"),
                            ({"g": (0.0, -190.0)}, r"g\[0\]"), ({"c_tau": 450.0 + 1e-6 * ndf.example_6_1().g[0]},
                                                               "c_tau")):
        with pytest.raises(ValueError, match=f"a.npz: made for another problem: .*{message}"):
            ndf.load_reference(folder / "a.npz", dataclasses.replace(problem, **change))


def _drop_fingerprint(data):
    del data["fp_data"]


def _nan_coefficient(data):
    data["u"][3] = np.nan


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(triangles=d["triangles"] + 100), r"triangles refer to vertices outside 0\.\.8"),  # segfault
    (lambda d: d.update(segments=-d["segments"]), "segments refer to vertices outside"),
    (lambda d: d.update(points=d["points"][:, :1]), "points has shape"),
    (lambda d: d.update(orders=d["orders"][:-1]), "orders: 7 orders"),
    (lambda d: d.update(orders=0 * d["orders"]), "need one in 1..30"),
    (lambda d: d.update(labels=d["labels"][:-1]), "labels for"),
    (lambda d: d.update(u=d["u"][:-1]), "coefficients for a space of dimension"),
    (lambda d: d.update(eta_h=np.array(-1.0)), "eta_h = -1.0 is negative"),
    (_nan_coefficient, "u holds non-finite values"),
    (_drop_fingerprint, "no fp_data"),
])
def test_defective_files_are_named(saved, change, message):
    folder, problem = saved
    with pytest.raises(ValueError, match=f"bad.npz: .*{message}"):
        ndf.load_reference(tampered(folder, change), problem)


@pytest.mark.parametrize("content", [b"hello" * 100, b"", None])
def test_unreadable_files_are_named(saved, content):
    folder, problem = saved
    path = folder / "broken.npz"
    whole = (folder / "a.npz").read_bytes()
    path.write_bytes(whole[:len(whole) // 2] if content is None else content)  # None: truncated
    with pytest.raises(ValueError, match="broken.npz: not a reference file"):
        ndf.load_reference(path, problem)


@pytest.mark.parametrize("key", ["fp_vertices", "fp_numbers", "fp_labels", "fp_names"])
def test_fingerprint_arrays_of_the_wrong_type_are_named(saved, key):
    folder, problem = saved
    path = tampered(folder, lambda d: d.update({key: np.array([["a", "b"]] * 3) if key == "fp_vertices"
                                               else np.array([1.0, 2.0, 3.0]) if key in ("fp_labels", "fp_names")
                                               else np.array(["x", "y", "z"])}))
    with pytest.raises(ValueError, match=f"bad.npz: {key} has shape"):
        ndf.load_reference(path, problem)


def test_energy_norm_of_a_linear_field_is_exact():
    """u = (x, 0) on Example 6.2 (Gamma_D = top side, n = (0, 1)): eps(u) = e_1 e_1^T, so the volume part is
    (lam + 2 mu) |Omega| = lam + 2 mu; [u] = 0 inside, and on Gamma_D |sym(u (x) n)|^2 = x^2 / 2, so the
    jump part is sum_e h_e^-1 int_e x^2 / 2 = 1 / (6 h) (Section 3)."""
    problem, h = ndf.example_6_2(), 1 / 4
    mesh = ndf.uniform_mesh(problem, h)
    u = ngs.GridFunction(ngs.L2(mesh, order=1) ** 2)
    u.Set(ngs.CF((ngs.x, 0)))
    volume, jumps = energy_norm_squared_parts(problem, mesh, u)
    assert volume == pytest.approx(problem.lam + 2 * problem.mu, rel=1e-12)
    assert jumps == pytest.approx(1 / (6 * h), rel=1e-12)
    w = difference(u, ngs.CF((ngs.x - 1, ngs.y)))  # u - w = (1, -y): eps = -e_2 e_2^T
    assert energy_norm_squared_parts(problem, mesh, w)[0] == pytest.approx(problem.lam + 2 * problem.mu, rel=1e-12)


def test_error_against_itself_is_its_jump_part(saved):
    """|||u_ref - u_h|||_h with u_h = u_ref: the volume part vanishes and the jump part is u_h's own (module
    docstring: [u - u_h] = -[u_h])."""
    folder, problem = saved
    reference = ndf.load_reference(folder / "a.npz", problem)
    errors = reference_errors(reference, reference)
    _, jumps = energy_norm_squared_parts(problem, reference.mesh, reference.u)
    assert errors["energy_volume"] < 1e-12 * ndf.energy_norm(reference)
    assert errors["energy"] == pytest.approx(jumps**0.5, rel=1e-12)


def test_data_given_as_functions_work_in_the_true_error_tools(tmp_path):
    # E and nu as CoefficientFunctions (energy_error used to raise TypeError: lam times a numpy array)
    problem = dataclasses.replace(ndf.example_6_2(), E=2500 * (1 + 0.1 * ngs.x), nu=0.3 + 0.05 * ngs.y)
    fine = ndf.solve(problem, ndf.uniform_mesh(problem, 0.125), order=3)
    ndf.save_reference(fine, tmp_path / "varying.npz", eta_h=1.0)
    reference = ndf.load_reference(tmp_path / "varying.npz", problem)
    coarse = ndf.solve(problem, ndf.uniform_mesh(problem, 0.125), order=1)  # P1 on the reference's mesh
    errors = reference_errors(coarse, reference)
    # energy / relative is the reference's own energy (int C eps(u_ref) : eps(u_ref))^(1/2), by point values
    # of E and nu at the P1 solution's Gauss points; NGSolve integrates the same symbolically
    own = energy_norm_squared_parts(problem, reference.mesh, reference.u)[0] ** 0.5
    assert 0 < errors["energy"] < ndf.energy_norm(coarse)
    assert errors["energy"] / errors["relative"] == pytest.approx(own, rel=1e-6)
    for other, name in ((dataclasses.replace(problem, nu=0.3), r"\(nu, m_n, m_t\)"),
                        (dataclasses.replace(problem, nu=0.3 + 0.06 * ngs.y), "nu = ")):
        with pytest.raises(ValueError, match=name):
            ndf.load_reference(tmp_path / "varying.npz", other)


def test_the_energy_norm_and_its_gram_matrix_are_one_definition():
    # |||w|||_h^2 by the integrals of energy_norm_squared_parts and by the matrix of energy_matrix (the one that
    # studies.cases.energy_gram uses for coercivity constants), on a scene with symmetry and Dirichlet sides
    from ngdgfric.dg.discretization import dg_space
    from ngdgfric.energy import energy_matrix

    problem = ndf.example("two_materials_symmetric")
    mesh = ndf.netgen_mesh(problem, 0.4)
    V = dg_space(mesh, 2)
    w = ngs.GridFunction(V)
    w.vec.FV().NumPy()[:] = np.random.default_rng(1).standard_normal(V.ndof)
    volume, jumps = energy_norm_squared_parts(problem.on(mesh), mesh, w)
    x = w.vec.FV().NumPy()
    assert x @ (energy_matrix(problem, mesh, V).ToDense().NumPy() @ x) == pytest.approx(volume + jumps, rel=1e-10)


def test_a_reference_of_the_conforming_baseline_loads_and_measures_like_its_dg_copy(tmp_path):
    # adapt's default method is cg (H^1): its solution saved as a reference failed to load ("34606
    # coefficients for a space of dimension 55356"); the file holds the DG copy, exact on straight elements
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 0.25)
    fine = ndf.solve(problem, mesh, method="cg", order=[2, 3] * (mesh.ne // 2))
    ndf.save_reference(fine, tmp_path / "cg.npz", eta_h=1.0)
    reference = ndf.load_reference(tmp_path / "cg.npz", problem)
    assert list(reference.orders) == list(fine.discretization.degrees)
    at = reference.mesh(np.linspace(0.05, 0.95, 7), np.linspace(0.1, 0.9, 7))
    assert np.asarray(reference.u(at)) == pytest.approx(np.asarray(fine.u(fine.mesh(np.linspace(0.05, 0.95, 7),
                                                                               np.linspace(0.1, 0.9, 7)))),
                                                        rel=1e-12, abs=1e-14)
    # against its own reference the volume part of the error vanishes (what is left is the jump part: u_h on
    # Gamma_D, where the baseline's Dirichlet condition is Nitsche's)
    assert reference_errors(fine, reference)["energy_volume"] <= 1e-10 * ndf.energy_norm(fine)


def test_energy_norm_against_a_gridfunction_is_exact_on_its_mesh_or_a_coarser_one_and_refused_elsewhere():
    # w quadratic: a P2 GridFunction holds it exactly on any mesh, so all three must agree with w as a
    # CoefficientFunction to round-off; on the user's own mesh object (not the Solution's copy) the jumps used to
    # be evaluated by point search on the wrong side (1e-8), on an unrelated Netgen mesh taken on its edges (1 %)
    from ngdgfric.meshes import netgen_mesh
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 0.25)
    sol = ndf.solve(problem, mesh, order=2)
    w = ngs.CF((0.01 * ngs.x * ngs.y, 0.02 * ngs.x - 0.01 * ngs.y**2))
    exact = ndf.energy_norm(sol, w)

    def on(other):
        g = ngs.GridFunction(ngs.L2(other, order=2) ** 2)
        g.Set(w)
        return g

    for other in (mesh, ndf.uniform_mesh(problem, 0.5)):
        assert ndf.energy_norm(sol, on(other)) == pytest.approx(exact, rel=1e-13)
    for other in (ndf.uniform_mesh(problem, 0.125), netgen_mesh(problem, 0.13)):
        with pytest.raises(ValueError, match=r"u_h.s mesh \(32 elements\) is not found to refine"):
            ndf.energy_norm(sol, on(other))


@pytest.mark.parametrize("h", [1 / 8, 1 / 16])
def test_two_solutions_of_one_problem_on_one_mesh_are_measured_coefficient_by_coefficient(h):
    """Newton's and Uzawa's solutions (coefficients equal to 1e-12) of Example 6.2, SIPG P1: each solution lives on
    its own copy of the mesh, and |||u_h - w||| took w's values there by point search at the Gauss points of Set's
    rule, which at P1 lie on the edges (0.6 = 1.8 % of |||u_h||| for w = u_h's twin).  Now the distance is the
    coefficient-wise one: zero to round-off for the twin, 1 % of |||u_h||| for 1.01 times the twin."""
    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, h)
    sol = ndf.solve(problem, mesh, method="sipg", order=1)
    twin = ndf.solve(problem, mesh, method="sipg", order=1, solver="uzawa", solver_tol=1e-11, kkt_tol=1e-11)
    norm = ndf.energy_norm(sol)
    assert np.abs(sol.u.vec.FV().NumPy() - twin.u.vec.FV().NumPy()).max() <= 1e-12 * np.abs(
        sol.u.vec.FV().NumPy()).max()
    assert ndf.energy_norm(sol, twin.u) <= 1e-9 * norm and ndf.energy_norm(twin, sol.u) <= 1e-9 * norm
    scaled = ngs.GridFunction(twin.u.space)
    scaled.vec.data = 1.01 * twin.u.vec
    assert ndf.energy_norm(sol, scaled) == pytest.approx(0.01 * norm, rel=1e-8)


def test_a_p1_solution_against_a_coarser_one_is_the_norm_of_the_prolongation():
    """u_h on a refinement of the coarse solution's mesh, P1: |||u_h - u_coarse||| equals the norm of u_h minus the
    coarse coefficients prolongated by NGSolve's own refinement (exact for nested L2 spaces), to round-off."""
    from ngdgfric.meshes import refined, snapshot

    problem = ndf.example_6_2()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    marked = np.arange(mesh.ne) % 3 == 0
    coarse = ndf.solve(problem, mesh, method="sipg", order=1)
    fine = ndf.solve(problem, refined(mesh, marked), method="nipg", order=1)
    live = snapshot(mesh)
    carried = ngs.GridFunction(ngs.L2(live, order=1, autoupdate=True) ** 2, autoupdate=True)
    carried.vec.data = coarse.u.vec
    ndf.meshes.refine(live, marked)
    difference = ngs.GridFunction(fine.u.space)
    difference.vec.data = fine.u.vec - carried.vec
    expected = sum(energy_norm_squared_parts(fine.discretization.problem, fine.mesh, difference)) ** 0.5
    assert ndf.energy_norm(fine, coarse.u) == pytest.approx(expected, rel=1e-12)


def test_a_coefficient_function_made_of_a_gridfunction_is_refused():
    """eps(w) of a CoefficientFunction w is its symbolic derivative, which sees a GridFunction as a constant:
    |||u_h - 0.5 u_h||| came out as |||u_h||| (for any factor).  Such a w is now refused by name."""
    problem = ndf.example_6_2()
    sol = ndf.solve(problem, ndf.uniform_mesh(problem, 1 / 4), method="sipg", order=2)
    for w in (0.5 * sol.u, 1.0 * sol.u, ngs.CF((sol.u[0], 0.0))):
        with pytest.raises(ValueError, match="symbolic derivative is not the derivative of its values.*GridFunction"):
            ndf.energy_norm(sol, w)


HOLE_AND_REGIONS = """
name = "Two blocks with a hole"
[material]
E = { left = 100.0, right = 300.0 }
nu = 0.3
[[geometry.region]]
name = "left"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.5, 1.0], [0.0, 1.0]]
labels = ["contact", "interface", "load", "free", "support"]
[[geometry.region]]
name = "right"
vertices = [[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.5, 1.0], [1.0, 1.0]]
labels = ["contact", "free", "free", "load", "interface"]
[[geometry.hole]]
centre = [1.5, 0.5]
radius = 0.25
label = "hole"
[boundaries]
dirichlet = "support"
traction = ["load", "free", "hole"]
contact = "contact"
[loads]
g = { load = [0.0, -5.0] }
[contact]
c_n = 300.0
m_n = 1.0
g_a = 0.0
c_tau = 0.2
"""


@pytest.mark.slow
def test_the_true_error_of_a_curved_scene_with_regions_against_a_finer_solution(tmp_path):
    """A user's scene with a circular hole (curved elements) and two materials, measured against adapt's finer
    solution of the same problem (a Solution as the reference): adapt's
    rtol = 1e-2 solution has a true error of 0.28e-2 |||u||| against the rtol = 1e-4 solution (0.2823e-2 against the
    rtol = 1e-5 one), inside [0.1, 1] x rtol; the reference's own error against itself is its jumps only; another
    problem is refused."""
    path = tmp_path / "scene.toml"
    path.write_text(HOLE_AND_REGIONS)
    problem = ndf.load_problem(path)
    coarse, fine = (ndf.adapt(problem, rtol=rtol).solution for rtol in (1e-2, 1e-4))
    norm = ndf.energy_norm(fine)
    errors = reference_errors(coarse, fine)
    assert 0.1e-2 <= errors["energy"] / norm <= 1e-2
    assert reference_errors(fine, fine)["energy_volume"] <= 1e-12 * norm
    with pytest.raises(ValueError, match="another problem.*c_tau"):
        ndf.energy_error(coarse, ndf.solve(dataclasses.replace(problem, c_tau={"contact": 0.3}), fine.mesh))
