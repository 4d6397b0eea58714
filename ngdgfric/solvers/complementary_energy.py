r"""The complementary energy :math:`\Theta` of the condensed contact problem and its descent step.

For a symmetric :math:`B_h` and the reduced law :math:`m_t = 0` the forces :math:`f` of ``ReducedContact``
(:mod:`ngdgfric.solvers.reduced`) minimise the convex complementary energy

.. math::

    \Theta(f) = \tfrac12 f \cdot W f - w_0 \cdot f + \sum_q \Phi_q^*(f_{n,q})
    \quad \text{over} \quad K = \{f_n \ge 0, |f_t| \le \beta\},

with :math:`\Phi^*(s) = g_a s + \frac{m}{m+1} (\omega c_n)^{-1/m} s^{(m+1)/m}` the conjugate of the compliance
energy (``pressure_conjugate_values`` of :mod:`ngdgfric.contact.laws` with the weight :math:`\omega c_n`;
:math:`f_n = 0` where :math:`c_n = 0`).  One step of the iteration (``energy_step``): the Newton point,
projected onto :math:`K`, is accepted when it lowers :math:`\Theta` by a fixed fraction :math:`\sigma` of what a
diagonally scaled projected-gradient step promises (:math:`\delta = -\nabla\Theta \cdot p` with
:math:`p = P_K(f - D^{-1} \nabla\Theta) - f`), or, once the relative KKT residual is below :math:`10^{-6}`, when
the next Newton point from it does (a watchdog: near the solution a step with a few wrong stick/slip guesses may
raise :math:`\Theta` by more than its round-off while the next step lands on the solution); otherwise a projected
Newton step with Armijo backtracking (``projected_newton_step``).  :math:`\Theta` decreases by at least
:math:`\sigma` times a forcing function of the projected gradient at every step, so every limit point minimises
:math:`\Theta` (Bertsekas, Nonlinear Programming, 2nd ed., Prop. 2.3.3); near the solution the Newton steps are
accepted, the sets settle, and for :math:`m_n = 1` (:math:`G` piecewise affine) the step with the final sets is
exact.
"""

import numpy as np

from ..contact.laws import pressure_conjugate_values, pressure_inverse_rate_values, pressure_inverse_values
from .reduced import EPS, dense_solve

__all__ = ["SIGMA", "WATCHDOG", "conjugate", "gradient", "energy_change", "energy_step", "projected_newton_step"]

SIGMA = 1e-4  # sufficient-decrease fraction (also of the other globalisations, :mod:`ngdgfric.solvers.semismooth`)
WATCHDOG = 1e-6  # relative KKT residual below which a rejected Newton step gets a second chance


def conjugate(problem, fn):
    """Phi*(f_n) per point (f_n >= 0; 0 where c_n = 0)."""
    return pressure_conjugate_values(fn, problem.g_a, problem.omega * problem.c_n, problem.m_n)


def gradient(problem, s):
    """grad Theta = -w + (g_a + (f_n / (omega c_n))^{1/m}, 0) (0 in the f_n fixed at 0) at the state s."""
    M = problem.M
    inverse = pressure_inverse_values(s.f[:M], problem.omega * problem.c_n, problem.m_n)
    normal = np.where(problem.compliant, -s.w[:M] + problem.g_a + inverse, 0.0)
    return np.concatenate([normal, -s.w[M:]])


def _gradient_scaling(problem, s):
    """D = diag(W) + the curvature of Phi* (capped), for the scaled projected gradient."""
    M = problem.M
    fn = np.maximum(s.f[:M], 1e-300)
    curvature = pressure_inverse_rate_values(fn, problem.omega * problem.c_n, problem.m_n)
    normal = problem.diagonal[:M] + np.minimum(curvature, 1e12 * problem.diagonal[:M])
    return np.concatenate([normal, problem.diagonal[M:]])


def energy_change(problem, s, f_new):
    """Theta(f_new) - Theta(f) for the state s at f, evaluated as a difference (not of two large numbers),
    and its round-off."""
    M = problem.M
    d = f_new - s.f
    Wd = problem.W @ d
    conj_new, conj_old = conjugate(problem, f_new[:M]), conjugate(problem, s.f[:M])
    terms = np.array([-s.w @ d, 0.5 * d @ Wd, np.sum(conj_new - conj_old)])
    size = np.abs(s.w) @ np.abs(d) + 0.5 * np.abs(d) @ np.abs(Wd) + np.sum(np.abs(conj_new) + np.abs(conj_old))
    return float(np.sum(terms)), 64 * EPS * size


def energy_step(problem, s, d):
    """The next f from the state s and its Newton direction d: the Newton point if it lowers Theta enough,
    else a projected Newton step (module docstring); returns (f, kind of step)."""
    grad = gradient(problem, s)
    scaling = _gradient_scaling(problem, s)
    p = problem.project(s.f - grad / scaling) - s.f
    delta = max(float(-grad @ p), 0.0)
    residual = problem.residual(s)

    def lowers(trial):
        # a change within round-off must at least halve the KKT residual instead (else two states
        # whose Theta differ by less than the round-off bound can alternate for ever)
        change, roundoff = energy_change(problem, s, trial)
        return change <= -SIGMA * delta or (change <= -SIGMA * delta + roundoff
                                            and problem.residual(problem.evaluate(trial)) <= 0.5 * residual)

    trial = problem.project(s.f + d)
    if lowers(trial):
        return trial, "newton"
    # watchdog (Chamberlain, Powell, Lemarechal & Pedersen, Math. Prog. Study 16, 1982): near the
    # solution a Newton step with a few wrong sets may raise Theta and the next one repair it
    if residual <= WATCHDOG:
        after = problem.evaluate(trial)
        second = problem.project(trial + problem.newton_direction(after))
        if lowers(second):
            return second, "newton (watchdog)"
        # degenerate points (z = +-beta: stick and slip both hold at the solution) flip between
        # Newton iterates; hold the ones that flip at their bound (slip) and step once more
        flips = (s.stick != after.stick) & (np.abs(s.f[problem.M:]) >= problem.beta_fixed * (1 - 1e-8))
        if flips.any():
            third = problem.project(s.f + problem.newton_direction(_held_at_bound(problem, s, flips)))
            if lowers(third):
                return third, "newton (degenerate points held)"
    return projected_newton_step(problem, s, grad, scaling, p)


def _held_at_bound(problem, s, points):
    """A copy of state s in which the friction variables ``points`` (at their bound) count as slip."""
    M = problem.M
    sign = np.where(points, np.sign(s.f[M:]), s.sign)
    G = s.G.copy()
    G[M:][points] = s.f[M:][points] - sign[points] * s.beta[points]
    return s.replace(stick=s.stick & ~points, sign=sign, G=G)


def projected_newton_step(problem, s, grad, scaling, projected_gradient):
    """Bertsekas' projected Newton step (SIAM J. Control Optim. 20, 1982): variables within epsilon of
    a bound that the gradient pushes out stay there (scaled gradient step), the others take the Newton
    step of Theta restricted to them; Armijo search along the projection arc.  ``projected_gradient`` is
    the scaled projected-gradient step P_K(f - D^-1 grad) - f; epsilon is set per variable relative to
    its own size (forces vary with the edge length: graded meshes).  Returns (f, kind of step)."""
    M, f = problem.M, s.f
    lower, upper = problem.bounds()
    size = np.concatenate([np.maximum(np.abs(f[:M]), np.abs(problem.w0[:M]) / problem.diagonal[:M]),
                           np.where(upper[M:] > 0, upper[M:], np.abs(problem.w0[M:]) / problem.diagonal[M:])])
    size = np.maximum(size, 1e-300)
    epsilon = min(1e-2, float(np.max(np.abs(projected_gradient) / size))) * size
    bound = ((f <= lower + epsilon) & (grad > 0)) | ((f >= upper - epsilon) & (grad < 0)) | (lower == upper)
    free = np.flatnonzero(~bound)
    direction = np.where(bound, -grad / scaling, 0.0)
    if free.size:
        curvature = np.concatenate([scaling[:M] - problem.diagonal[:M], np.zeros(M)])  # Phi*'' (capped)
        hessian = problem.W[np.ix_(free, free)]
        on_diagonal = np.arange(free.size)
        hessian[on_diagonal, on_diagonal] += curvature[free] + problem.regularization * problem.diagonal[free]
        direction[free] = dense_solve(hessian, -grad[free], problem.diagnostics)
    free_decrease = float(-grad[free] @ direction[free])
    t = 1.0
    for _ in range(50):
        trial = problem.project(f + t * direction)
        predicted = t * free_decrease + float(grad[bound] @ (f[bound] - trial[bound]))
        if -energy_change(problem, s, trial)[0] >= SIGMA * predicted:
            break
        t *= 0.5
    return trial, "projected newton" if t == 1 else f"projected newton x{t:g}"
