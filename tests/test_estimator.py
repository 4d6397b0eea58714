import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.reference import energy_norm_squared_parts


@pytest.fixture(scope="module")
def solution():
    p = ndf.example_6_1()
    return ndf.solve(p, ndf.uniform_mesh(p, 1 / 8))


def test_element_indicators_sum_to_eta_squared(solution):
    est = ndf.estimate(solution)
    assert est.eta_T_squared.shape == (solution.mesh.ne,)
    assert est.eta_T_squared.sum() == pytest.approx(est.eta_h**2, rel=1e-12)
    assert sum(est.terms_squared.values()) == pytest.approx(est.eta_h**2, rel=1e-12)
    assert set(est.terms_squared) == {f"eta{i}" for i in range(1, 7)}


def test_eta3_equals_penalty_times_the_jump_part_of_the_energy_norm(solution):
    # eta_3^2 = eta / h_e ||[u]||^2 over E_h^o (p = 1): computed independently by reference.energy_norm_squared_parts
    _, jumps = energy_norm_squared_parts(solution.problem, solution.mesh, solution.u)
    assert ndf.estimate(solution).terms_squared["eta3"] == pytest.approx(solution.eta * jumps, rel=1e-10)


@pytest.mark.parametrize("method", [name for name, m in ndf.METHODS.items() if m.penalty == "lift"])
def test_eta3_of_the_lifting_methods_weighs_the_jumps_by_2_mu_eta(method):
    """For the lifting penalties eta is dimensionless: eta_3^2 = 2 mu eta / h_e ||[u]||^2 (Method.jump_weight)."""
    p = ndf.example_6_1()
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 8), method=method, eta=5.0)
    _, jumps = energy_norm_squared_parts(sol.problem, sol.mesh, sol.u)
    assert ndf.estimate(sol).terms_squared["eta3"] == pytest.approx(2 * p.mu * 5.0 * jumps, rel=1e-10)


def test_eta1_of_the_paper_vanishes_without_body_force(solution):
    assert ndf.estimate(solution, variant="paper").terms_squared["eta1"] == 0.0
    p = dataclasses.replace(ndf.example_6_1(), f=(1.0, 2.0))
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 4))
    # eta_1^2 = sum_T h_T^2 |f|^2 |T| = (sqrt(2)/4)^2 * 5 * 1 for h = 1/4 on the unit-area domain
    assert ndf.estimate(sol, variant="paper").terms_squared["eta1"] == pytest.approx(2 / 16 * 5, rel=1e-12)


def test_the_energy_variant_divides_by_2_mu_when_the_pressure_is_continuous():
    # u linear: the stress is constant, p_h = lam div u is its own continuous average, so the energy
    # terms are the paper's divided by 2 mu = E / (1 + nu) (eta_3, a penalty, unchanged), times the
    # calibration p^(-1/2) squared = 1/2
    p = dataclasses.replace(ndf.example_6_1(), f=(1.0, 2.0))
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), order=2)
    sol.u.Set(ngs.CF((1e-3 * (ngs.x - 1) + 2e-3 * ngs.y, -1e-3 * ngs.x + 5e-4 * (ngs.y - 0.05))))
    paper, energy = ndf.estimate(sol, variant="paper").terms_squared, ndf.estimate(sol).terms_squared
    assert paper["eta1"] == pytest.approx(2 / 16 * 5 / 4, rel=1e-10)  # (h/p)^2 |f|^2, p = 2
    for name in paper:
        factor = (1.0 if name == "eta3" else 1.4 / 2000) / 2
        assert energy[name] == pytest.approx(factor * paper[name], rel=1e-9, abs=1e-20), name


def test_eta3_vanishes_for_a_continuous_function_zero_on_gamma_d():
    p = ndf.example_6_1()
    sol = ndf.solve(p, ndf.uniform_mesh(p, 1 / 4), order=2)
    sol.u.Set(ngs.CF(((1 - ngs.x) * ngs.x, (1 - ngs.x) * ngs.y)))  # quadratic: exact in P2, 0 on x = 1
    est = ndf.estimate(sol)
    assert est.terms_squared["eta3"] < 1e-20
    assert est.terms_squared["eta2"] > 0


@pytest.mark.slow
def test_effectivity_index_is_stable_on_a_manufactured_contact_solution(contact_problem):
    problem, u_exact = contact_problem
    for order, levels in ((1, range(1, 7)), (2, range(0, 6))):
        ratios = []
        for k in levels:
            sol = ndf.solve(problem, ndf.uniform_mesh(problem, 2.0**-k), order=order)
            ratios.append(ndf.estimate(sol).eta_h / ndf.energy_norm(sol, u_exact))
        assert max(ratios) / min(ratios) <= 5, (order, ratios)


@pytest.mark.parametrize("theta", [0.0, -0.1, 1.5, float("nan")])
def test_dorfler_rejects_bad_theta(theta):
    with pytest.raises(ValueError, match="theta"):
        ndf.dorfler_mark(np.ones(4), theta)


def test_dorfler_marks_the_minimal_set():
    values = np.array([1.0, 5.0, 2.0, 2.0, 0.0])
    np.testing.assert_array_equal(ndf.dorfler_mark(values, 0.5), [False, True, False, False, False])
    np.testing.assert_array_equal(ndf.dorfler_mark(values, 0.51), [False, True, True, False, False])
    assert ndf.dorfler_mark(values, 1.0).sum() == 4  # the zero indicator is never needed
    assert not ndf.dorfler_mark(np.zeros(3), 0.3).any()
    rng = np.random.default_rng(1)
    for _ in range(20):
        v = rng.random(50) ** 3
        marked = ndf.dorfler_mark(v, 0.3)
        assert v[marked].sum() >= 0.3 * v.sum()
        # minimal: dropping the smallest marked indicator breaks the bulk criterion
        assert v[marked].sum() - v[marked].min() < 0.3 * v.sum()


def test_element_integrals_equal_integrate_element_wise():
    from ngdgfric.estimator import element_integrals

    p = ndf.example_6_1()
    mesh = ndf.uniform_mesh(p, 1 / 4)
    u = ngs.GridFunction(ngs.VectorL2(mesh, order=3))
    u.Set(ngs.CF((ngs.x * ngs.y**2, ngs.sin(3 * ngs.x))))
    u.vec.FV().NumPy()[:] += np.random.default_rng(0).standard_normal(len(u.vec)) * 0.1  # discontinuous
    n = ngs.specialcf.normal(2)
    on_contact = ndf.meshes.facet_indicator(mesh, p.contact)

    integrands = {"volume": [(ngs.x * u[0] ** 2, False)],
                  "boundary": [(on_contact * (u * n) ** 2, True), (ngs.InnerProduct(u, u), True)],
                  "mixed": [(u[1], False), (ngs.specialcf.mesh_size * (u * n), True)]}
    degrees = np.where(np.arange(mesh.ne) % 3 == 0, 2, 3)  # Gauss rules of degree 6 and 8
    together = element_integrals(mesh, integrands, degrees)
    for name, terms in integrands.items():
        for p in (2, 3):  # Integrate integrates with 5 + bonus
            alone = sum(ngs.Integrate(cf * ngs.dx(element_boundary=boundary, bonus_intorder=2 * p + 2 - 5), mesh,
                                      element_wise=True).NumPy() for cf, boundary in terms)
            mine = degrees == p
            assert np.allclose(together[name][mine], alone[mine], rtol=1e-12, atol=1e-14 * np.max(np.abs(alone)))


def _effectivity(problem, u, method="sipg", order=1, h=1 / 8, variant="energy"):
    sol = ndf.solve(problem, ndf.uniform_mesh(problem, h), method=method, order=order)
    return ndf.estimate(sol, variant=variant).eta_h / ndf.energy_norm(sol, u)


def test_the_energy_variant_makes_the_effectivity_independent_of_the_units_of_E():
    # the same displacement with E = 1 and E = 1e6 (data scaled): u_h is the same, the energy error
    # scales like sqrt(E) but for its unweighted jump part h^-1 ||[u_h]||^2
    from ngdgfric.studies.manufactured import incompressible_contact_manufactured

    soft, stiff = (incompressible_contact_manufactured(E=E, c_n=10.0 * E / 1e3) for E in (1.0, 1e6))
    for variant, (low, high) in (("energy", (0.97, 1.03)), ("paper", (500, 2000))):
        ratio = _effectivity(*stiff, variant=variant) / _effectivity(*soft, variant=variant)
        assert low < ratio < high, (variant, ratio)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["nipg", "brezzi"])
def test_effectivity_is_robust_as_nu_tends_to_one_half(method):
    # div u = 0: the data do not depend on nu; NIPG and Brezzi et al. do not lock
    from ngdgfric.studies.manufactured import incompressible_contact_manufactured

    for order in (1, 2):
        values = [_effectivity(*incompressible_contact_manufactured(nu=nu), method=method, order=order)
                  for nu in (0.3, 0.4999)]
        assert all(1 < v < 8 for v in values) and max(values) / min(values) < 1.5, (order, values)


def test_unknown_variant_raises(solution):
    with pytest.raises(ValueError, match="variant must be one of"):
        ndf.estimate(solution, variant="energie")


def test_the_old_keyword_weights_selects_the_variant_with_a_deprecation_warning(solution):
    with pytest.warns(DeprecationWarning, match=r"estimate\(weights=...\) is deprecated.*variant='paper'"):
        old = ndf.estimate(solution, weights="paper")
    assert old.eta_h == ndf.estimate(solution, variant="paper").eta_h
    assert old.eta_h != ndf.estimate(solution).eta_h  # not the default "energy"
    with pytest.raises(ValueError, match="disagree"), pytest.warns(DeprecationWarning):
        ndf.estimate(solution, variant="energy", weights="paper")


def test_the_equilibrated_bound_refuses_a_variant_it_would_ignore(solution):
    with pytest.raises(ValueError, match="variant='paper' is a variant of the residual estimator"):
        ndf.estimate(solution, variant="paper", kind="equilibrated")
