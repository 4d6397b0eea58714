"""Variable order per element, the hp decision, reference solutions."""

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.hp import HPState, hp_refine, refinement_parents, smooth
from ngdgfric.meshes import triangle_corners
from ngdgfric.reference import energy_error, load_reference, save_reference


def energy_errors(problem, u_exact, method, levels, draw_orders):
    errors = []
    for k in levels:
        mesh = ndf.uniform_mesh(problem, 2.0**-k)
        orders = draw_orders(mesh.ne)
        sol = ndf.solve(problem, mesh, method=method, order=orders)
        assert sol.discretization.orders.min() < sol.discretization.orders.max()
        errors.append(ndf.energy_norm(sol, u_exact))
    return np.array(errors)


@pytest.mark.slow
@pytest.mark.parametrize("method", sorted(ndf.METHODS))
def test_mixed_orders_converge_at_the_rate_of_the_lowest_order(elasticity, method):
    """Random p_T in {2, 3}: rate 2; random p_T in {1, 2, 3}: rate >= 1 and below the P1 error."""
    problem, u_exact = elasticity
    rng = np.random.default_rng(7)
    high = energy_errors(problem, u_exact, method, (2, 3, 4), lambda ne: rng.integers(2, 4, ne))
    assert np.log2(high[-2] / high[-1]) == pytest.approx(2, abs=0.3)
    mixed = energy_errors(problem, u_exact, method, (2, 4), lambda ne: rng.integers(1, 4, ne))
    assert np.log2(mixed[0] / mixed[1]) / 2 > 0.85
    p1 = ndf.energy_norm(ndf.solve(problem, ndf.uniform_mesh(problem, 2.0**-4), method=method), u_exact)
    assert mixed[1] < p1


def test_sipg_is_symmetric_with_mixed_orders():
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    orders = np.random.default_rng(3).integers(1, 4, mesh.ne)
    A = ndf.Discretization(problem, mesh, "sipg", orders).A.ToDense().NumPy()
    assert np.abs(A - A.T).max() < 1e-13 * np.abs(A).max()


def test_bad_order_arrays_raise():
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 2)
    with pytest.raises(ValueError, match="one per element"):
        ndf.Discretization(problem, mesh, order=np.ones(mesh.ne + 1, dtype=int))
    with pytest.raises(ValueError, match="one per element"):
        ndf.Discretization(problem, mesh, order=np.zeros(mesh.ne, dtype=int))


def distance_to_corner(mesh):
    """Distance of every element's centroid from the corner (0, 0.05) of Example 6.1."""
    return np.linalg.norm(triangle_corners(mesh).mean(axis=1) - [0, 0.05], axis=1)


def projection_errors(mesh, w, order):
    """|w - Pi_p w|_{H1(T)}^2 per element, Pi_p the element-wise L2 projection."""
    pw = ngs.GridFunction(ngs.L2(mesh, order=order))
    pw.Set(w)
    g = ngs.CF((w.Diff(ngs.x), w.Diff(ngs.y))) - ngs.Grad(pw)
    return ngs.Integrate(g * g, mesh, order=12, element_wise=True).NumPy().copy()


@pytest.mark.parametrize("order", [1, 2, 3])
def test_smoothness_rates_a_polynomial_smooth_and_a_corner_singularity_not(order):
    """Refine (twice bisect) the corner element and an interior one in h.  A polynomial of degree
    p + 1 meets the smooth-u prediction on every new element; r^(2/3) sin(2 phi / 3), singular at
    the corner (0, 0.05), meets it on the interior element's children but not at the corner."""
    problem = ndf.example_6_1()
    x, y = ngs.x, ngs.y - 0.05
    r, phi = ngs.sqrt(x * x + y * y), ngs.atan2(y, x)
    functions = {"polynomial": (1 + x) ** (order + 1) * (2 - y) + y ** (order + 1),
                 "singular": r ** (2 / 3) * ngs.sin(2 * phi / 3)}
    for name, w in functions.items():
        mesh = ndf.uniform_mesh(problem, 1 / 4)
        distance = distance_to_corner(mesh)
        corner, interior = int(np.argmin(distance)), int(np.argmin(np.abs(distance - 0.7)))
        marked = np.zeros(mesh.ne, dtype=bool)
        marked[[corner, interior]] = True
        ne = mesh.ne
        state = hp_refine(mesh, HPState.uniform(mesh, order), projection_errors(mesh, w, order), marked, max_order=6)
        assert state.orders.max() == order  # no prediction yet: the first step is in h
        parent, descendants = refinement_parents(mesh, ne)
        assert descendants[corner] == descendants[interior] == 4
        verdict = smooth(projection_errors(mesh, w, order), state.predicted)
        distance = distance_to_corner(mesh)
        at_corner = (parent == corner) & (distance == distance.min())
        assert verdict[parent == interior].all(), name
        if name == "polynomial":
            assert verdict[parent == corner].all()
        else:
            assert not verdict[at_corner].any() and verdict[(parent == corner) & ~at_corner].all()


@pytest.mark.slow
def test_hp_adapt_raises_orders_where_smooth_and_bisects_the_corners(tmp_path):
    problem = ndf.example_6_1()
    records = ndf.adapt(problem, order=2, hp=True, max_order=5, max_levels=14, rtol=0, progress=None,
                        csv_path=tmp_path / "hp.csv").levels
    assert records[-1]["p_max"] > records[-1]["p_min"]
    assert records[-1]["eta_h"] < 0.25 * records[0]["eta_h"]
    with pytest.raises(ValueError, match="max_order"):
        ndf.adapt(problem, order=3, hp=True, max_order=2)


def test_reference_round_trip_and_true_error(elasticity, tmp_path):
    problem, u_exact = elasticity
    fine = ndf.solve(problem, ndf.uniform_mesh(problem, 1 / 8), order=6)
    save_reference(fine, tmp_path / "ref.npz", eta_h=ndf.estimate(fine).eta_h)
    reference = load_reference(tmp_path / "ref.npz", problem)
    assert np.array_equal(reference.u.vec.FV().NumPy(), fine.u.vec.FV().NumPy())
    assert ndf.energy_norm(fine, u_exact) < 1e-6
    for maxh in (0.25, 0.125):
        sol = ndf.solve(problem, ndf.netgen_mesh(problem, maxh))
        assert energy_error(sol, reference) == pytest.approx(ndf.energy_norm(sol, u_exact), rel=0.01)
    with pytest.raises(FileNotFoundError, match="reference.py"):
        load_reference(tmp_path / "missing.npz", problem)


def test_reference_errors_agree_with_differences_computed_on_the_mesh(contact_problem):
    # P2 against P4 on one mesh: reference_errors finds the P4 solution by point search at its Gauss
    # points (exact here: the rule of degree 2 p + 4 integrates the P3 gradients' squares exactly),
    # difference_norms interpolates P2 into P4 (exact); the volume parts must agree to round-off
    from ngdgfric.reference import energy_norm_squared_parts, reference_errors
    from ngdgfric.studies import difference_norms

    problem, _ = contact_problem
    mesh = ndf.uniform_mesh(problem, 1 / 8)
    coarse, fine = (ndf.solve(problem, mesh, order=p) for p in (2, 4))
    ours, theirs = reference_errors(coarse, fine), difference_norms(coarse, fine)
    for name in ("h1", "l2", "energy_volume"):
        assert ours[name] == pytest.approx(theirs[name], rel=1e-9), name
    assert ours["energy"] == pytest.approx(energy_error(coarse, fine), rel=1e-14)
    volume, _ = energy_norm_squared_parts(problem, fine.mesh, fine.u)
    assert ours["relative"] == pytest.approx(ours["energy"] / volume**0.5, rel=1e-9)


def test_refinement_parents_follow_netgen_parent_elements():
    """The whole-array parent chains against GetParentElement element by element, after double and
    single bisections of random sets."""
    problem = ndf.example_6_1()
    mesh = ndf.uniform_mesh(problem, 1 / 4)
    rng = np.random.default_rng(1)
    for step in range(4):
        ne = mesh.ne
        mesh.SetRefinementFlags(list(rng.random(ne) < 0.3))
        mesh.Refine(onlyonce=bool(step % 2))
        parent, descendants = refinement_parents(mesh, ne)
        expected = np.arange(mesh.ne)
        for nr in range(ne, mesh.ne):
            ancestor = mesh.GetParentElement(ngs.ElementId(ngs.VOL, nr)).nr
            expected[nr] = ancestor if ancestor < ne else expected[ancestor]
        np.testing.assert_array_equal(parent, expected)
        np.testing.assert_array_equal(descendants, np.bincount(expected, minlength=ne))
