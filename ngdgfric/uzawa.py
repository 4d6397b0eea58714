"""The Uzawa iteration of Section 6 for the characterisation (3.3)-(3.4).

    l^{k+1} = P_[-1,1](l^k + rho c_tau u_tau^k)    at the contact Gauss points,
    u^{k+1}:  B_h(u, v) + j_n(u, v) = (f, v) - g(l^{k+1}, v)   (Newton on the compliance term),

stopped when ||u^{k+1} - u^k||_inf <= tol ||u^{k+1}||_inf (the paper's relative max-norm
criterion, here on the coefficient vector of u_h).
"""

import time

import ngsolve as ngs
import numpy as np

from .contact import evaluate_on_contact, normal_tangent, penetration, project_unit
from .errors import SolverError
from .linalg import BlockSum, direct_inverse

__all__ = ["uzawa", "default_rho", "ComplianceSolver"]


class ComplianceSolver:
    """Solves B_h(u, v) + j_n(u, v) = rhs(v) by Newton's method, reusing factorizations.

    The Jacobian A + K(u) differs from A only in the blocks of the contact elements.  For
    m_n = 1 it depends only on the set of penetrating Gauss points (u_n > g_a), so it is
    refactorised only when that set changes and a step with an unchanged set is exact.
    """

    def __init__(self, disc):
        self.disc = disc
        self.form = disc.compliance
        self.sum = BlockSum(disc.A, disc.contact_groups())
        self.points = disc.contact_points()
        self.linear = disc.problem.m_n == 1
        self._state = None
        self._inverse = None
        self._gaps = {}
        self.factorizations = 0
        self.solves = 0
        self.factor_time = 0.0
        self._work = disc.A.CreateColVector()
        self._du = disc.A.CreateColVector()

    def _active(self, u):
        """Gauss points of Gamma_C where u_n > g_a."""
        if id(u) not in self._gaps:
            self._gaps[id(u)] = penetration(self.disc.problem, u)
        return evaluate_on_contact(self._gaps[id(u)], self.points) > 0

    def jacobian_inverse(self, u):
        """Factorised A + K(u), refactorised only if K changed; returns (inverse, changed)."""
        state = self._active(u)
        if self._inverse is not None and self.linear and np.array_equal(state, self._state):
            return self._inverse, False
        start = time.perf_counter()
        with ngs.TaskManager():
            self.form.AssembleLinearization(u.vec)
            J = self.sum.update(self.form.mat)
            self._inverse = direct_inverse(J, self.disc.symmetric)
        self.factor_time += time.perf_counter() - start
        self.factorizations += 1
        self._state = state
        return self._inverse, True

    def residual(self, u, rhs):
        """r = A u + j_n(u, .) - rhs."""
        r = self._work
        self.form.Apply(u.vec, r)
        r.data += self.disc.A * u.vec - rhs
        return r

    def solve(self, u, rhs, tol=1e-13, maxit=50):
        """Newton for u (in place); returns the number of Newton steps."""
        inverse, _ = self.jacobian_inverse(u)
        for step in range(1, maxit + 1):
            r = self.residual(u, rhs)
            du = self._du
            with ngs.TaskManager():
                du.data = inverse * r
            self.solves += 1
            u.vec.data -= du
            size = np.max(np.abs(du.FV().NumPy()))
            scale = max(np.max(np.abs(u.vec.FV().NumPy())), 1e-300)
            inverse, changed = self.jacobian_inverse(u)
            if (self.linear and not changed) or size <= tol * scale:
                return step
        raise SolverError(f"Newton for the compliance term did not converge in {maxit} steps",
                          history=[], solver="uzawa (inner Newton)")


def _friction_update_form(disc, u, lam, rho):
    """Linear form of the pointwise update int P(l + rho c_tau u.t) q ds (Gauss rule)."""
    _, t = normal_tangent()
    q = disc.Q.TestFunction()
    form = ngs.LinearForm(disc.Q)
    form += project_unit(lam + rho * disc.c_tau * (u * t)) * q * disc.dS
    return form


def default_rho(disc, inner=None, iterations=30, safety=1.5):
    """rho = safety / L with L the largest eigenvalue of the linearised Uzawa map.

    The map l -> c_tau u_tau(l) of the linear problem (compliance inactive) has the matrix
    H = M^-1 G^T A^-1 G; projected gradient ascent on the dual converges for rho < 2/L.  L is
    estimated by ``iterations`` power iterations with the factorised A; the compliance term
    only adds stiffness and lowers L, so rho = 1.5/L is safe with margin.
    """
    if disc.Q.ndof == 0:
        return 1.0
    if inner is None:
        inverse = direct_inverse(disc.A, disc.symmetric)
    else:
        inverse, _ = inner.jacobian_inverse(ngs.GridFunction(disc.V))
    x = ngs.GridFunction(disc.Q).vec
    rng = np.random.default_rng(0)
    x.FV().NumPy()[:] = rng.random(len(x)) + 0.5
    y = x.CreateVector()
    estimate = 0.0
    for _ in range(iterations):
        y.data = disc.M_inv * (disc.G.T * (inverse * (disc.G * x)))
        norm_y = np.linalg.norm(y.FV().NumPy())
        norm_x = np.linalg.norm(x.FV().NumPy())
        if norm_y == 0 or norm_x == 0:
            return 1.0
        estimate = norm_y / norm_x
        x.data = (1 / norm_y) * y
    return safety / estimate


def uzawa(disc, tol=1e-8, rho=None, maxit=100000, initial=None, progress=None):
    """Uzawa's method of Section 6; returns (u, lam, info) with info a dict of diagnostics.

    ``initial``: optional (u, lam) GridFunctions on ``disc.V``, ``disc.Q`` to start from.
    ``rho``: step size; None picks :func:`default_rho`.
    ``progress``: callable(iteration, change) called every 100 iterations, or None.
    Raises :class:`SolverError` (with the history of changes) on divergence or after ``maxit``.
    """
    start = time.perf_counter()
    u, lam = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    if initial is not None:
        u.vec.data, lam.vec.data = initial[0].vec, initial[1].vec
    inner = ComplianceSolver(disc)
    if rho is None:
        rho = default_rho(disc, inner)
    elif not (np.isfinite(rho) and rho > 0):
        raise ValueError(f"rho must be a positive number, got {rho!r}")
    update = _friction_update_form(disc, u, lam, rho)
    rhs = disc.F.CreateVector()
    u_old = u.vec.CreateVector()
    history = []
    inner_steps = 0
    for k in range(1, maxit + 1):
        if k > 1 or initial is not None:
            update.Assemble()
            lam.vec.data = disc.M_inv * update.vec
        u_old.data = u.vec
        rhs.data = disc.F - disc.G * lam.vec
        inner_steps += inner.solve(u, rhs)
        du = np.max(np.abs(u.vec.FV().NumPy() - u_old.FV().NumPy()))
        scale = np.max(np.abs(u.vec.FV().NumPy()))
        change = du / scale if scale > 0 else du
        history.append(change)
        if progress is not None and k % 100 == 0:
            progress(k, change)
        if not np.isfinite(change) or (k > 50 and change > 1e3 * min(history)):
            raise SolverError(f"Uzawa diverged at iteration {k} (relative change {change:.3e}); "
                              f"rho = {rho:.4g} is probably too large (it must be below 2/L, see default_rho)",
                              history=history, solver="uzawa")
        if change <= tol and k > 1:
            break
    else:
        raise SolverError(f"Uzawa did not reach tol = {tol:g} in {maxit} iterations "
                          f"(last relative change {history[-1]:.3e}, rho = {rho:.4g})",
                          history=history, solver="uzawa")
    info = dict(iterations=k, history=history, rho=rho, inner_steps=inner_steps,
                factorizations=inner.factorizations, solves=inner.solves,
                timings=dict(factor=inner.factor_time, total=time.perf_counter() - start))
    return u, lam, info
