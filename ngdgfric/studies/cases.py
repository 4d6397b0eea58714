"""Single cases of the stability study (scripts/stability.py): plain dict in, plain dict out.

Each function builds everything from the case's parameters, so it can run in any dask worker
(:mod:`ngdgfric.studies.runner`).  A solver that fails is a result, not an error: ``status`` records it.
"""

import dataclasses
import time

import ngsolve as ngs
import numpy as np

from .. import contact_state, kkt_residuals
from ..contact import Contact
from ..contact.boundary import normal_tangent
from ..dg.discretization import Discretization, dg_space
from ..dg.methods import get_method
from ..energy import energy_matrix
from ..errors import SolverError
from ..estimator import estimate
from ..examples import example
from ..meshes import uniform_mesh
from ..problem import strain_of, stress
from ..reference import energy_error, energy_norm, load_reference
from ..solution import solve
from ..solvers.uzawa import UzawaOptions, default_rho, uzawa
from .manufactured import elasticity_manufactured

__all__ = ["penalty_value", "energy_gram", "coercivity", "penalty_threshold", "threshold_case", "penalty_case",
           "locking_case", "compliance_case", "friction_case", "rho_case"]


def penalty_value(problem, method, ratio):
    """eta for a study value eta/mu: ratio * mu for the edge-penalty methods; for Bassi and Brezzi
    eta multiplies (C r_e, r_e), which already carries the material, so eta = ratio."""
    return ratio * get_method(method).eta_scale(problem)


def _dense(problem, mesh, method, order, eta):
    """The matrix of the linear part of B_h (Section 3) as a dense array."""
    return Discretization(problem, mesh, method, order, eta, penalty_check="ignore").A.ToDense().NumPy()


def energy_gram(problem, mesh, order):
    """The matrix of the inner product of |||.|||_h (Section 3) on V_h of degree ``order``, dense: the Gram matrix
    of :func:`ngdgfric.energy.energy_matrix`, the norm of :func:`ngdgfric.energy_norm` (h_e = |e|, the problem's
    C pointwise)."""
    return energy_matrix(problem, mesh, dg_space(mesh, order)).ToDense().NumPy()


def coercivity(problem, mesh, method, order, eta, gram=None):
    """min over v of B_h(v, v) / |||v|||_h^2 for the linear part of B_h (generalised eigenvalue).

    ``gram``: :func:`energy_gram` of (problem, mesh, order), if it is at hand.
    """
    A = _dense(problem, mesh, method, order, eta)
    lower = np.linalg.cholesky(energy_gram(problem, mesh, order) if gram is None else gram)
    scaled = np.linalg.solve(lower, np.linalg.solve(lower, 0.5 * (A + A.T)).T)
    return float(np.linalg.eigvalsh(0.5 * (scaled + scaled.T))[0])


def _solve(problem, mesh, **kwargs):
    """(Solution or None, status, seconds)."""
    start = time.perf_counter()
    try:
        sol = solve(problem, mesh, penalty_check="ignore", **kwargs)
        return sol, "converged", time.perf_counter() - start
    except SolverError as error:
        return None, _failed(error), time.perf_counter() - start


def _failed(error):
    """The status of a case whose solver raised ``error``."""
    return f"failed: {str(error).splitlines()[0][:120]}"


def penalty_case(case):
    """case: example, method, order, ratio (eta/mu), h_eig, h, reference (path)."""
    problem = example(case["example"])
    eta = penalty_value(problem, case["method"], case["ratio"])
    lam_min = coercivity(problem, uniform_mesh(problem, case["h_eig"]), case["method"], case["order"], eta)
    sol, status, seconds = _solve(problem, uniform_mesh(problem, case["h"]), method=case["method"],
                                  order=case["order"], eta=eta, maxit=30)
    error = energy_error(sol, load_reference(case["reference"], problem)) if sol is not None else None
    return dict(case, eta=eta, lam_min=lam_min, status=status, seconds=seconds, error=error,
                iterations=None if sol is None else sol.iterations)


def locking_case(case):
    """case: method, order, nu, h.  Relative energy error on the smooth manufactured solution."""
    problem, u_exact = elasticity_manufactured(E=1000.0, nu=case["nu"])
    sol, status, seconds = _solve(problem, uniform_mesh(problem, case["h"]), method=case["method"],
                                  order=case["order"])
    e = strain_of(u_exact)
    exact = ngs.Integrate(ngs.InnerProduct(stress(problem, e), e), sol.mesh, order=12) ** 0.5
    return dict(case, status=status, seconds=seconds, relative_error=energy_norm(sol, u_exact) / exact)


def _contact_summary(sol):
    state = contact_state(sol)
    stick = np.abs(state["lam_tau"]) < 1 - 1e-8
    return dict(penetration=float(np.max(np.maximum(state["gap"], 0.0), initial=0.0)),
                contact_fraction=float(np.mean(state["gap"] > 0)), stick_fraction=float(np.mean(stick)),
                max_slip=float(np.max(np.abs(state["u_tau"]))), **kkt_residuals(sol))


def compliance_case(case):
    """case: example, c_n, solver, h.  Iterations, penetration, eta_h (the paper's weights), and the condition number of
    A + c_n (u.n, v.n)_{Gamma_C}, the Jacobian with the whole of Gamma_C in contact (m_n = 1)."""
    problem = dataclasses.replace(example(case["example"]), c_n=case["c_n"])
    mesh = uniform_mesh(problem, case["h"])
    sol, status, seconds = _solve(problem, mesh, solver=case["solver"], maxit=case.get("maxit", 5000))
    disc = Discretization(problem, mesh) if sol is None else sol.discretization
    contact = Contact(disc) if sol is None else sol.contact
    n, _ = normal_tangent()
    u, v = disc.V.TnT()
    stiff = ngs.BilinearForm(disc.V)
    stiff += case["c_n"] * (u * n) * (v * n) * contact.dS
    stiff.Assemble()
    condition = float(np.linalg.cond(disc.A.ToDense().NumPy() + stiff.mat.ToDense().NumPy()))
    out = dict(case, status=status, seconds=seconds, condition=condition)
    if sol is not None:
        out.update(iterations=sol.iterations, eta_h=estimate(sol, variant="paper").eta_h, **_contact_summary(sol))
    return out


def friction_case(case):
    """case: example, c_tau, solver, h.  Iterations, stick/slip shares, KKT residuals."""
    problem = dataclasses.replace(example(case["example"]), c_tau=case["c_tau"])
    sol, status, seconds = _solve(problem, uniform_mesh(problem, case["h"]), solver=case["solver"],
                                  maxit=case.get("maxit", 5000))
    out = dict(case, status=status, seconds=seconds)
    if sol is not None:
        out.update(iterations=sol.iterations, **_contact_summary(sol))
    return out


def rho_case(case):
    """case: example, factor, h.  Uzawa with rho = factor * default_rho (the paper's solver)."""
    problem = example(case["example"])
    disc = Discretization(problem, uniform_mesh(problem, case["h"]))
    contact = Contact(disc)
    rho = case["factor"] * default_rho(disc, contact)
    start = time.perf_counter()
    try:
        _, _, info = uzawa(disc, contact, UzawaOptions(rho=rho, maxit=case.get("maxit", 3000)))
        status, iterations = "converged", info["iterations"]
    except SolverError as error:
        status, iterations = _failed(error), len(error.history)
    return dict(case, rho=rho, status=status, iterations=iterations, seconds=time.perf_counter() - start)


def penalty_threshold(problem, mesh, method, order, low=1e-2, high=1e3, steps=14):
    """The smallest eta/mu (see :func:`penalty_value`) with a coercive linear part on ``mesh``, by
    bisection in log eta between ``low`` and ``high`` (``low`` if already coercive there)."""
    gram = energy_gram(problem, mesh, order)

    def coercive(ratio):
        return coercivity(problem, mesh, method, order, penalty_value(problem, method, ratio), gram) > 0

    if coercive(low):
        return low
    if not coercive(high):
        return float("inf")
    for _ in range(steps):
        middle = (low * high) ** 0.5
        low, high = (low, middle) if coercive(middle) else (middle, high)
    return high


def threshold_case(case):
    """case: example, method, order, h, nu (optional: overrides the example's).  The measured
    threshold as eta/mu and as eta/(2 mu + lam)."""
    problem = example(case["example"])
    if case.get("nu") is not None:
        problem = dataclasses.replace(problem, nu=case["nu"])
    ratio = penalty_threshold(problem, uniform_mesh(problem, case["h"]), case["method"], case["order"])
    return dict(case, threshold_mu=ratio, threshold_2mu_lam=ratio * problem.mu / (2 * problem.mu + problem.lam))
