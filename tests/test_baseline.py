"""The conforming baseline benchmarks/conforming.py: exact on polynomial solutions, converging to the stored
references, the contact laws at its points, and its error measurement."""

import importlib.util
from dataclasses import replace
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.problem import Polygon

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("conforming", ROOT / "benchmarks" / "conforming.py")
conforming = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(conforming)


def _stress(problem, u):
    """sigma(u) of a CoefficientFunction u of x, y (symbolic derivatives)."""
    g = ngs.CF((u[0].Diff(ngs.x), u[0].Diff(ngs.y), u[1].Diff(ngs.x), u[1].Diff(ngs.y)), dims=(2, 2))
    e = 0.5 * (g + g.trans)
    return 2 * problem.mu * e + problem.lam * ngs.Trace(e) * ngs.Id(2)


def polynomial_problem():
    """A quadratic u on the unit square that slips everywhere on Gamma_C = {y = 0} (u_x > 0 there, sigma_xy =
    c_tau) and penetrates everywhere (u_n = -u_y = 0.01 > g_a = 0, sigma_yy = -c_n u_n); u = u_D on x = 1,
    sigma n = g on x = 0 and y = 1, f = -div sigma(u)."""
    E, nu, c_tau, c_n, a, c0, e, k, e0 = 1000.0, 0.3, 5.0, 100.0, 1e-3, 1e-3, 2e-3, -1e-3, -0.01
    mu, lam = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))
    b = c_tau / mu                                   # sigma_xy(x, 0) = mu b = c_tau
    d = (-c_n * (-e0) - lam * a) / (lam + 2 * mu)    # sigma_yy(x, 0) = lam (a + d) + 2 mu d = -c_n u_n
    x, y = ngs.x, ngs.y
    u = ngs.CF((a * x + b * y + c0 + e * y * y, d * y + e0 + k * y * y))
    geometry = Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="clamped", top="top", left="left")
    base = ndf.ContactProblem(E=E, nu=nu, f=(0.0, 0.0), g=(0.0, 0.0), c_n=c_n, m_n=1.0, g_a=0.0, c_tau=c_tau,
                              geometry=geometry, dirichlet="clamped", traction=("top", "left"), contact="contact")
    sigma = _stress(base, u)
    f = -ngs.CF((sigma[0, 0].Diff(x) + sigma[0, 1].Diff(y), sigma[1, 0].Diff(x) + sigma[1, 1].Diff(y)))
    g = {"top": sigma * ngs.CF((0, 1)), "left": sigma * ngs.CF((-1, 0))}
    return replace(base, f=f, g=g, u_D=u), u


@pytest.mark.parametrize("order", [2, 3])
def test_polynomial_solution_with_slip_and_penetration_is_reproduced(order):
    problem, exact = polynomial_problem()
    level = next(conforming.run(problem, order, mesh=ndf.uniform_mesh(problem, 0.25)))
    mesh, u = level.mesh, level.u
    scale = ngs.Integrate(ngs.InnerProduct(exact, exact), mesh) ** 0.5
    error = ngs.Integrate(ngs.InnerProduct(u - exact, u - exact), mesh, order=2 * order + 2) ** 0.5
    assert error <= 1e-11 * scale
    assert level.contact.lam_tau == pytest.approx(np.ones(len(level.contact.lam_tau)), abs=1e-12)
    assert not level.contact.stick.any()


@pytest.fixture(scope="module")
def example_6_2():
    problem = ndf.example_6_2()
    return problem, ndf.load_reference(ROOT / "results" / "reference_6_2.npz", problem)


def test_example_6_2_converges_to_the_reference(example_6_2):
    problem, reference = example_6_2
    errors, estimates = [], []
    for level in conforming.run(problem, 3, max_levels=15):
        if level.level in (4, 9, 14):
            errors.append(conforming.true_error(problem, level.mesh, level.u, reference))
            estimates.append(level.eta_h)
    assert errors[0] > 1.5 * errors[1] > 2.25 * errors[2]
    assert errors[2] < 0.05   # |||u_ref||| = 34.1: 0.15 % relative
    # the ZZ estimator is efficient within a band
    assert all(0.3 < eta / error < 3 for eta, error in zip(estimates, errors, strict=True))


def test_friction_and_compliance_hold_at_the_contact_points():
    """Example 6.1 (sticking and slipping points): the equilibrium residual, assembled independently of the
    baseline's condensed and transformed system, with the contact terms by the Lobatto rule; |lam_tau| <= 1;
    u_tau = 0 where |lam_tau| < 1; lam_tau = sign(u_tau) where u_tau != 0."""
    problem, order = ndf.example_6_1(), 3
    *_, level = conforming.run(problem, order, max_levels=10)
    mesh, u, lam = level.mesh, level.u, level.lam_tau
    assert 0 < level.contact.stick.sum() < len(level.contact.stick)
    V = ngs.VectorH1(mesh, order=order, dirichlet=problem.where("dirichlet"))
    w, v = V.TnT()
    eps = ngs.Sym(ngs.Grad(w))
    a = ngs.BilinearForm(V)
    sigma = 2 * problem.mu * eps + problem.lam * ngs.Trace(eps) * ngs.Id(2)
    a += ngs.InnerProduct(sigma, ngs.Sym(ngs.Grad(v))) * ngs.dx
    a.Assemble()
    f = ngs.LinearForm(V)
    f += ndf.problem.coefficient(problem.g) * v * ngs.ds(definedon=mesh.Boundaries("traction"))
    f.Assemble()
    nodes, weights = conforming.lobatto_rule(order)
    rule = ngs.IntegrationRule([(s,) for s in nodes], list(weights))
    n = ngs.specialcf.normal(2)
    t = ngs.CF((-n[1], n[0]))
    gap = u * n - problem.g_a
    contact = ngs.LinearForm(V)
    contact += (problem.c_n * ngs.IfPos(gap, gap, 0) * (v * n) + problem.c_tau * lam * (v * t)) * ngs.ds(
        definedon=mesh.Boundaries("contact"), intrules={ngs.SEGM: rule})
    contact.Assemble()
    uh = ngs.GridFunction(V)
    uh.vec.data = u.vec
    residual = (a.mat * uh.vec - f.vec + contact.vec).Evaluate().FV().NumPy()
    free = np.array(list(V.FreeDofs()))
    assert np.abs(residual[free]).max() <= 1e-11 * np.abs(f.vec.FV().NumPy()).max()
    xy = level.points.xy[level.points.free]
    u_tau = np.array([(u * t)(mesh(px, py, VOL_or_BND=ngs.BND)) for px, py in xy])
    lam_tau = np.array([lam(mesh(px, py)) for px, py in xy])
    size = np.abs(u.vec.FV().NumPy()).max()
    assert np.abs(lam_tau).max() <= 1 + 1e-12
    sticking = np.abs(lam_tau) < 1 - 1e-8
    assert sticking.any() and np.abs(u_tau[sticking]).max() <= 1e-12 * size
    slipping = np.abs(u_tau) > 1e-10 * size
    assert slipping.any() and np.allclose(lam_tau[slipping], np.sign(u_tau[slipping]), rtol=0, atol=1e-12)


def test_true_error_of_the_reference_itself_is_zero(example_6_2):
    problem, reference = example_6_2
    own = ndf.reference.gridfunction_errors(problem, reference.mesh, reference.u, reference)
    assert own["energy_volume"] <= 1e-12 * own["energy"] / own["relative"]
    assert own["energy"] == pytest.approx(ndf.energy_error(reference, reference), rel=1e-12)
    conforming_ref = ngs.GridFunction(ngs.VectorH1(reference.mesh, order=int(reference.orders.max())))
    conforming_ref.Set(reference.u)
    error = conforming.true_error(problem, reference.mesh, conforming_ref, reference)
    assert error <= 1e-3 * own["energy"] / own["relative"]
