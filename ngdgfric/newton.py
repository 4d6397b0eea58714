"""Semismooth Newton (primal-dual active set) for (3.3)-(3.4), with factorisation reuse.

With the friction bound b(u) = c_tau (u_n - g_a)_+^{m_t} of (1.9) (b = c_tau for the reduced
law m_t = 0) and the friction force psi = b l, Lemma 3.1 with |l| <= 1 is the semismooth system

    A u + j_n(u) + int psi v_tau ds = F,     psi = P_[-b(u), b(u)](psi + c u_tau)   at the contact Gauss points,

for any c > 0; for m_t > 0 it is the quasi-variational inequality (1.4).  One Newton step from
(u_k, l_k) freezes the sets it implies, with b_k = b(u_k) and z = b_k l_k + c u_tau(u_k),

    stick  chi = 1 where |z| < b_k:   u_tau = 0, psi free,
    slip   chi = 0 elsewhere:         psi = b(u) s,  s = sign(z),

linearises the compliance and the slip force b(u) s at u_k, and solves the resulting
saddle-point problem for (u_{k+1}, l_{k+1}) exactly.  For m_t > 0 the slip force couples the
bound to u_n: b(u) s ~ (b_k + b'_k (u - u_k) . n) s adds the nonsymmetric term
b'_k s (du . n)(v . t) to the Jacobian, the fully coupled Newton step.  Where b_k = 0 (no
contact) a point is never stick: it carries no force, and l = s = sign(u_tau).  The linear
problem is solved by the iterated penalty (augmented Lagrangian) method with the matrix
A + K_n(u_k) + gamma chi (t.)(t.) + (1 - chi) b'_k s (n.)(t.): solve for u with the friction force
chi (b_k l + gamma u_tau) + (1 - chi) (b_k + b'_k (u - u_k) . n) s, update
l <- chi (l + gamma u_tau / b_k) + (1 - chi) s, repeat until the stick constraint holds to
round-off.  All these solves share one matrix, so one factorisation (Cholesky where it
is symmetric, see :class:`ngdgfric.nonlinear.ReusedFactorization`) serves a Newton step, and consecutive Newton
steps with the same sets (and, for m_n > 1 or m_t not in {0, 1}, the same penetrations) share it too.

gamma = kappa (2 mu + lam) / h_e makes the stick penalty kappa times stiffer than the elastic
boundary stiffness E/h, so each penalty sweep reduces the constraint violation by about 1/kappa.
The active-set parameter is c = c0 (2 mu + lam) / h_e; a large c lets wrongly slipping points
return quickly, but primal-dual active set methods can then cycle, a few points flipping between
stick and slip: a non-monotone line search on the merit function :class:`Merit` stops that.
"""

import time

import ngsolve as ngs
import numpy as np

from .contact import contact_rule, evaluate_on_contact, friction_bound_slope, normal_tangent
from .errors import SolverError
from .linalg import diagonal
from .nonlinear import ContactOperator, ReusedFactorization, multiplier_update, newton_step, relative_change

__all__ = ["newton", "Merit"]


def newton(disc, tol=1e-8, maxit=50, initial=None, kappa=1e4, c0=1.0, reuse=True, low_rank=True,
           progress=None, max_sweeps=20):
    """Semismooth Newton (module docstring); returns (u, lam, info).

    tol: stop when the active sets (and the penetrating points) are those of the previous step
    and finishing that step's linear solve changes u by at most tol (relative max norm).
    ``iterations`` counts Newton steps, i.e. set updates; ``sweeps`` and ``solves`` count the
    back-substitutions, ``factorizations`` the matrices factorised; ``stick_points`` is the size
    of the stick set decided at each step (of ``contact_points`` Gauss points) and ``timings``
    the seconds spent (factor, solve, jacobian, total).
    initial: optional (u, lam) GridFunctions on ``disc.V``, ``disc.Q`` to start from.
    kappa, c0: penalty and active-set parameters (module docstring).
    reuse: keep the factorisation while the active sets stay (False: factorise every Newton step).
    low_rank: keep it also when the sets change, correcting it by low-rank updates where that is
    cheaper than a new factorisation (:class:`ngdgfric.nonlinear.ReusedFactorization`).
    progress: callable(iteration, change) called after each iteration, or None.
    Raises :class:`SolverError` with the history of changes if it does not converge in maxit.
    """
    if not (np.isfinite(kappa) and kappa > 0):
        raise ValueError(f"kappa must be a positive number, got {kappa!r}")
    start = time.perf_counter()
    u, lam = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    u_k, lam_k = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    if initial is not None:
        u.vec.data, lam.vec.data = initial[0].vec, initial[1].vec
    stiffness = (2 * disc.problem.mu + disc.problem.lam) / disc.h_e
    gamma = kappa * stiffness
    n, t = normal_tangent()
    b_k = disc.bound(u_k)
    coupled = disc.problem.m_t > 0  # the slip force depends on u_n: nonsymmetric Jacobian, s and b'_k enter it
    decide, stick, slip_sign = _frozen_sets(disc, b_k, b_k * lam_k + c0 * stiffness * (u_k * t), coupled)
    slope_k = friction_bound_slope(disc.problem, u_k) if coupled else None
    slip = (lambda trial: b_k + slope_k * ((trial - u_k) * n)) if coupled else (lambda trial: b_k)
    psi = lambda trial: stick * (b_k * lam + gamma * (trial * t)) + (1 - stick) * slip(trial) * slip_sign
    op = ContactOperator(disc, u, psi, switches=decide, coefficients=[slope_k] if coupled else [])
    linear_solver = ReusedFactorization(disc.symmetric and not coupled, low_rank=reuse and low_rank)
    update = multiplier_update(disc, lam, stick * (lam + gamma / ngs.IfPos(b_k, b_k, 1) * (u * t))
                               + (1 - stick) * slip_sign)
    modulus = 2 * disc.problem.mu + disc.problem.lam
    if isinstance(modulus, ngs.CoefficientFunction):  # spatially varying E: its largest value on Gamma_C
        modulus = float(np.max(np.asarray(modulus(disc.gauss.points))))
    merit = Merit(disc, u, lam, c0 * modulus)
    du, lam_old = u.vec.CreateVector(), lam.vec.CreateVector()
    history, sweeps, steps, stick_points = [], [], [], []
    sets, value, values = None, merit(), []
    points = len(op.points)
    for k in range(maxit + 1):
        u_k.vec.data, lam_k.vec.data = u.vec, lam.vec
        sets, previous = op.sets(), sets
        stick_points.append(int(np.sum(sets[points:2 * points])))
        if history and np.array_equal(sets, previous):
            # the last step used the right sets: finish its linear solve (for m_t > 0: one more
            # Newton step with these sets)
            count, solved = _solve_frozen_sets(op, linear_solver, update, du, lam, lam_old, max_sweeps, forcing=0.0)
            sweeps[-1] += count
            du.data = u.vec - u_k.vec
            if solved and relative_change(du, u.vec) <= tol:
                info = dict(iterations=k, history=history, sweeps=sweeps, step_sizes=steps, stick_points=stick_points,
                            contact_points=points, **linear_solver.counts,
                            timings=dict(**linear_solver.times, total=time.perf_counter() - start))
                return u, lam, info
            u_k.vec.data, lam_k.vec.data = u.vec, lam.vec
            sets, value = op.sets(), merit()
        if k == maxit or (history and not np.isfinite(history[-1])):
            break
        if not reuse:
            linear_solver.forget()
        sweeps.append(_solve_frozen_sets(op, linear_solver, update, du, lam, lam_old, max_sweeps)[0])
        values = (values + [value])[-4:]
        value, step = merit.line_search(u_k, lam_k, max(values))
        steps.append(step)
        du.data = u.vec - u_k.vec
        history.append(relative_change(du, u.vec))
        if progress is not None:
            progress(k + 1, history[-1])
    raise SolverError(f"semismooth Newton did not reach tol = {tol:g} in {len(history)} iterations "
                      f"(last change {history[-1]:.3e}, last step sizes {steps[-3:]})",
                      history=history, solver="newton")


def _frozen_sets(disc, b_k, z, coupled):
    """The stick set chi = {|z| < b_k} and the slip sign s = sign(z), decided once per Newton step.

    Returns (decide, chi, s): ``decide()`` evaluates b_k and z at the contact Gauss points, stores
    chi and s in the multiplier space (whose functions are fixed by their Gauss values) and
    returns the decisions as a boolean array; chi and s are those GridFunctions.  Deciding once
    keeps the solve and the multiplier update consistent: with IfPos(b_k^2 - z^2) evaluated in
    each form separately, a point with |z| = b_k up to round-off could be stick in the matrix and
    slip in the update (or the reverse), and the penalty sweeps then grew by gamma / b_k per sweep.
    """
    gauss = disc.gauss
    stick, slip_sign = ngs.GridFunction(disc.Q), ngs.GridFunction(disc.Q)

    def decide():
        b, zq = evaluate_on_contact(b_k, gauss.points), evaluate_on_contact(z, gauss.points)
        is_stick = b * b - zq * zq > 0
        gauss.set_values(stick, is_stick.astype(float))
        gauss.set_values(slip_sign, np.where(zq > 0, 1.0, -1.0))
        return np.concatenate([is_stick] + ([zq > 0] if coupled else []))

    return decide, stick, slip_sign


class Merit:
    """Merit function of the semismooth system for the line search, in energy units.

    Phi(u, l) = sum_i R_i^2 / A_ii + sum_q w_q / c (psi - P_[-b, b](psi + c u_tau))^2 over the Gauss
    points, with R = A u + j_n(u) + g(l) - F the residual of (3.3), b the friction bound at u and
    psi = b l; both terms vanish exactly at the solution.  ``c_times_h``: c h_e (a number).
    """

    def __init__(self, disc, u, lam, c_times_h):
        self.disc, self.u, self.lam = disc, u, lam
        d = diagonal(disc.A)
        self.inverse_diagonal = 1 / np.where(d > 0, d, 1.0)
        gauss = disc.gauss
        _, t = normal_tangent()
        self.u_tau, self.bound = u * t, disc.bound(u)
        lengths = np.linalg.norm(gauss.ends[:, 1] - gauss.ends[:, 0], axis=1)
        weights = np.asarray(contact_rule(disc.order)[ngs.SEGM].weights)
        self.c = np.repeat(c_times_h / lengths, gauss.q)
        self.weights = (lengths[:, None] * weights[None, :]).ravel() / self.c
        self._r = disc.F.CreateVector()
        self._u_start, self._lam_start = u.vec.CreateVector(), lam.vec.CreateVector()

    def __call__(self):
        r = self.disc.residual(self.u, self.lam, out=self._r).FV().NumPy()
        gauss = self.disc.gauss
        b = evaluate_on_contact(self.bound, gauss.points)
        psi = b * gauss.values(self.lam).ravel()
        r2 = psi - np.clip(psi + self.c * evaluate_on_contact(self.u_tau, gauss.points), -b, b)
        return float(np.sum(r * r * self.inverse_diagonal) + np.sum(self.weights * r2 * r2))

    def line_search(self, u_start, lam_start, value_start, halvings=6):
        """Backtrack from the full step (the current u, l) towards (u_start, lam_start) until Phi
        is below (1 - 1e-4 t) ``value_start``; returns (Phi, step size t).  With ``value_start``
        the largest of the last few merit values this is a non-monotone line search (Grippo,
        Lampariello, Lucidi 1986): full steps may increase Phi for a while, cycles cannot repeat."""
        self._u_start.data = self.u.vec - u_start.vec  # the step
        self._lam_start.data = self.lam.vec - lam_start.vec
        step = 1.0
        for _ in range(halvings):
            value = self()
            if value <= (1 - 1e-4 * step) * value_start or value_start == 0:
                return value, step
            step /= 2
            self.u.vec.data = u_start.vec + step * self._u_start
            self.lam.vec.data = lam_start.vec + step * self._lam_start
        return self(), step


def _solve_frozen_sets(op, linear_solver, update, du, lam, lam_old, max_sweeps, forcing=1e-3):
    """One Newton step: the linear saddle-point problem of the frozen sets, by iterated penalty.

    Each sweep is a Newton step for u with the current l (exact when the penetrating set does
    not change, m_n = 1) followed by the multiplier update.  The sweeps stop when their changes
    of u and l have dropped below ``forcing`` times the first sweep's (an inexact Newton step,
    accurate to a fraction of its own size) or stop decreasing (round-off); returns the count and
    whether they stopped so (False: ``max_sweeps`` reached).
    """
    first = previous = None
    for sweep in range(1, max_sweeps + 1):
        state, _ = newton_step(op, linear_solver, du)
        op.u.vec.data -= du
        lam_old.data = lam.vec
        update()
        lam_old.data -= lam.vec
        changes = np.array([relative_change(du, op.u.vec), np.max(np.abs(lam_old.FV().NumPy()), initial=0.0)])
        first = changes if first is None else first
        settled = not op.linear_compliance or np.array_equal(op.state(), state)
        stagnated = previous is not None and np.any(changes > 0.1 * previous)
        if settled and (stagnated or np.all(changes <= np.maximum(forcing * first, [1e-13, 1e-10]))):
            return sweep, True
        previous = changes
    return max_sweeps, False
