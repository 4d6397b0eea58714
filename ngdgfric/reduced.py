"""The contact problem condensed onto the Gauss points of Gamma_C, and its semismooth Newton method.

Unknowns: the contact forces f = (f_n, f_t) at the M Gauss points (f = omega x traction density,
:mod:`ngdgfric.traces`), with the traces w(f) = w0 - W f of the displacement (W the Delassus
operator, :mod:`ngdgfric.condensation`).  The compliance law (1.8), the friction law (1.9) and
Lemma 3.1 hold at every point q iff G(f) = 0, where

    G_n = f_n - N(w_n),                N(w_n) = omega c_n (w_n - g_a)_+^{m_n},
    G_t = f_t - P_[-beta, beta](f_t + r w_t),   beta(w_n) = omega c_tau (w_n - g_a)_+^{m_t}

(beta = omega c_tau for the reduced law m_t = 0); the multiplier is l = f_t / beta, so
|l| <= 1 and l u_tau = |u_tau| (3.4).  Any r > 0 gives the same solutions; r_q = 1 / W_{t_q t_q},
the point's own tangential stiffness, makes the stick/slip decision scale-free (the Alart-Curnier
choice; Acary, Bremond & Huber, "On solving contact problems with Coulomb friction:
formulations and numerical comparisons", 2018).

**Newton step.**  J d = -G with J an element of the generalised Jacobian of G: the identity row
for a point without penetration (G_n = f_n) or slipping with a fixed bound (G_t = f_t -+ beta),
e_q + N'(w_n) W_q for a penetrating point, r W_q for a sticking one (G_t = -r w_t), and
e_q +- beta'(w_n) W_q for a slipping one with m_t > 0.  Identity rows are eliminated, so the dense
system has one row per penetrating or sticking point.

**Globalisation.**
* B_h symmetric and m_t = 0: the solution minimises the convex complementary energy
  Theta(f) = 1/2 f.W f - w0.f + sum_q Phi_q*(f_n,q) over K = {f_n >= 0, |f_t| <= beta}, with
  Phi*(s) = g_a s + m/(m+1) (omega c_n)^{-1/m} s^{(m+1)/m} the conjugate of the compliance energy
  (f_n = 0 where c_n = 0).  The Newton point, projected onto K, is accepted when it lowers Theta by
  a fixed fraction sigma of what a diagonally scaled projected-gradient step promises (delta =
  -grad Theta . p with p = P_K(f - D^-1 grad Theta) - f), or, once the relative KKT residual is
  below 1e-6, when the next Newton point from it does (a watchdog: near the solution a step with
  a few wrong stick/slip guesses may raise Theta by more than its round-off while the next step
  lands on the solution); otherwise a projected Newton step with Armijo backtracking.  Theta
  decreases by at least sigma x (a forcing function of the projected gradient) at every step, so
  every limit point minimises Theta (Bertsekas, Nonlinear Programming, 2nd ed., Prop. 2.3.3); near
  the solution the Newton steps are accepted, the sets settle, and for m_n = 1 (G piecewise
  affine) the step with the final sets is exact.
* NIPG with m_t = 0 (no energy): merit Psi(f) = 1/2 sum_q W_qq G_q^2 (energy units).  Newton steps
  with non-monotone Armijo backtracking (reference: the largest of the last five Psi; Grippo,
  Lampariello & Lucidi 1986); when that fails, a Levenberg-Marquardt step
  (J^T S J + mu diag(J^T S J)) d = -J^T S G with mu raised until Psi decreases (More 1978; for
  semismooth equations Facchinei & Kanzow 1997).  For a coercive B_h (W's symmetric part positive
  definite) J is nonsingular, so Psi's smooth stationary points solve G = 0; Psi's kinks can still
  stop it (seen from poor starting points with c_n = 1e6).  Then a continuation from the symmetric
  problem: W(s) = sym(W) + s skew(W), s = 0 (solved by the energy method above), 1/16, 1/8, ... 1,
  the step in s doubled after a success and halved after a failure, each solve started from the last.
* m_t > 0 (a quasi-variational inequality, (1.4)): let T(f) be the solution with the friction bound
  frozen at beta(w_n(f)) (the reduced law with a spatially varying c_tau, solved by this method with
  its own globalisation).  The merit is the fixed-point residual r(f) = |f - T(f)|_inf: the Newton
  point (or half a step) is taken if it lowers r by the fraction sigma, else the fixed-point step
  f <- T(f).  Where T is a contraction with constant L, the regime in which the QVI is known to have
  a unique solution (small c_tau m_t (u_n - g_a)^{m_t - 1}), r falls at least by max(1 - sigma/2, L)
  per step, and the coupled Newton finishes quadratically.  (The merit Psi stalled here: seen with
  c_n = 0, m_t = 2.)  If r stops falling (T no contraction, no Newton progress: seen with c_n = 0,
  m_t = 1, where T cycles between two states), a continuation in c_tau follows: c_tau scaled by
  s = 1e-6, then s multiplied by 4 (the factor squared after a success, square-rooted after a
  failure) up to 1, so the solution branch is followed from the contractive regime of small c_tau.

**Stopping test** (on the KKT system, not on the change of f): W_qq |G_q| <= max(tol max_q |w_q|,
W_qq e_q) at every point: each point's residual force measured by the displacement it causes there
(at a sticking point W_tt |G_t| = |u_tau|, the complementarity of (3.4)), relative to the largest
trace, and e_q the round-off in evaluating G_q (8 eps times the sizes of its terms; it matters for
stiff compliance, c_n -> 1e10).

**Redundant points** (``redundant``: an element with two edges on Gamma_C, or p_T < p on hp
meshes): W is singular and the forces at those points are not unique (the displacement is).  The
energy method then stalls: whole groups of points are degenerate (stick and slip both hold for
some of the optimal forces) and the Newton iterates wander along the set of minimisers (captured
final hp level of Example 6.1, M = 1926: the stick set swinging by 200 points, no convergence in
100 iterations; 83 iterations on the level before).  So a redundant problem with energy is solved
by the proximal point method (Rockafellar, SIAM J. Control Optim. 14, 1976):

    f_{k+1} = argmin_K Theta(f) + mu_k/2 (f - f_k).D (f - f_k),    D = diag(W),

each a problem of this class with W + mu_k D and w0 + mu_k D f_k (strictly convex: unique forces,
a well-conditioned Newton system), solved by the energy method from f_k; mu_0 = 1e-3, mu_{k+1} =
mu_k / 100 (the steps 1 / mu_k grow, so the outer iteration converges superlinearly: Luque, SIAM J.
Control Optim. 22, 1984), back to 10 mu_k after an inner failure.  The iteration stops as soon as
the original problem meets the stopping test.  The proximal map is nonexpansive, so which of the
optimal forces is returned depends continuously on the data and the start; the multiplier
l = f_t / beta enters the estimator (eta_4), and with the plain iteration Example 6.1 to
tol = 5e-4 with E x (1 +- 1e-13) gave final eta_h differing by 3e-3 relative (now 4e-7).
Measured on the captured levels of Example 6.1 (M = 945 ... 1926): 20-27 Newton steps in all where
the plain iteration took 42, 44, 83 and failed.  (Also tried: mu_0 = 1e-2, 1e-1 or mu / 10 per
step: 19-33 steps; a smaller r in the stick/slip decision needed fewer steps only because it
loosened the stopping test at sticking points.)
Without energy (NIPG, m_t > 0) the sticking rows of J get 1e-8 on the diagonal instead
(r W_qq = 1 there), which leaves the solutions unchanged (d = 0 iff G = 0) and picks a small
step in the kernel.
"""

import numpy as np

from .errors import SolverError
from .linalg import dense_threads

__all__ = ["ReducedContact", "SIGMA"]

SIGMA = 1e-4  # sufficient-decrease fraction
WATCHDOG = 1e-6  # relative KKT residual below which a rejected Newton step gets a second chance
PROXIMAL_START, PROXIMAL_DECREASE = 1e-3, 100.0  # mu_0 and mu_k / mu_{k+1} of the proximal point method
EPS = np.finfo(float).eps


def _positive_power(x, m):
    """x_+^m for any real m (1 where x > 0 for m = 0; 0 where x <= 0, also for m < 0)."""
    out = np.zeros_like(x, dtype=float)
    positive = x > 0
    out[positive] = x[positive] if m == 1 else x[positive] ** m
    return out


def _dense_solve(matrix, rhs):
    """matrix^-1 rhs by LU (least squares if singular or not finite), on all cores when large."""
    with dense_threads(len(rhs)):
        try:
            solution = np.linalg.solve(matrix, rhs)
        except np.linalg.LinAlgError:
            solution = None
        if solution is None or not np.all(np.isfinite(solution)):
            solution = np.linalg.lstsq(matrix, rhs, rcond=1e-13)[0]
    return solution


class _State:
    """Everything Newton needs at one f: traces, residual, sets and derivatives."""

    __slots__ = ("f", "w", "G", "N", "dN", "beta", "dbeta", "stick", "sign", "penetrating")


class ReducedContact:
    """The condensed problem of the module docstring.

    W (2M x 2M, rows and columns ordered n_1 ... n_M, t_1 ... t_M) and w0 (2M) from the
    condensation; omega, g_a, c_n, c_tau: arrays of length M; m_n >= 1, m_t >= 0; symmetric: W is
    symmetric (B_h symmetric); redundant: see the module docstring.
    """

    def __init__(self, W, w0, omega, g_a, c_n, c_tau, m_n, m_t, symmetric, redundant=False):
        self.M = M = len(omega)
        self.W, self.w0 = np.asarray(W, dtype=float), np.asarray(w0, dtype=float)
        self.absW = np.abs(self.W)
        self.omega, self.g_a = np.asarray(omega, dtype=float), np.asarray(g_a, dtype=float)
        self.c_n, self.c_tau = np.asarray(c_n, dtype=float), np.asarray(c_tau, dtype=float)
        self.m_n, self.m_t = float(m_n), float(m_t)
        diagonal = np.diag(self.W).copy()
        largest = np.max(np.abs(diagonal), initial=0.0)
        self.diagonal = np.maximum(diagonal, 1e-14 * largest if largest > 0 else 1.0)
        self.r = 1.0 / self.diagonal[M:]
        self.energy_symmetric = bool(symmetric)
        self.energy_merit = bool(symmetric and self.m_t == 0)
        self.regularization = 1e-8 if redundant else 0.0
        self.force_scale = max(float(np.max(np.abs(self.w0) / self.diagonal, initial=0.0)), np.finfo(float).tiny)
        self.compliant = self.c_n > 0
        self.beta_fixed = self.omega * self.c_tau if self.m_t == 0 else None

    # ------------------------------------------------------------------ the laws and G
    def evaluate(self, f):
        """The :class:`_State` at forces f."""
        M, s = self.M, _State()
        s.f = f
        s.w = self.w0 - self.W @ f
        gap = s.w[:M] - self.g_a
        s.penetrating = gap > 0
        if self.m_n == 1:
            s.N = self.omega * self.c_n * np.maximum(gap, 0.0)
            s.dN = np.where(s.penetrating, self.omega * self.c_n, 0.0)
        else:
            s.N = self.omega * self.c_n * _positive_power(gap, self.m_n)
            s.dN = self.omega * self.c_n * self.m_n * _positive_power(gap, self.m_n - 1)
        if self.m_t == 0:
            s.beta, s.dbeta = self.beta_fixed, np.zeros(M)
        else:
            s.beta = self.omega * self.c_tau * _positive_power(gap, self.m_t)
            s.dbeta = self.omega * self.c_tau * self.m_t * _positive_power(gap, self.m_t - 1)
        z = f[M:] + self.r * s.w[M:]
        s.stick = np.abs(z) < s.beta
        s.sign = np.where(z >= 0, 1.0, -1.0)
        s.G = np.concatenate([f[:M] - s.N, np.where(s.stick, -self.r * s.w[M:], f[M:] - s.sign * s.beta)])
        return s

    def residual(self, s):
        """The relative KKT residual max_q W_qq |G_q| / max_q |w_q|: each point's residual force measured
        by the displacement it causes at that point, relative to the largest trace."""
        return float(np.max(self.diagonal * np.abs(s.G), initial=0.0)) / self._trace_scale(s)

    @staticmethod
    def _trace_scale(s):
        return max(float(np.max(np.abs(s.w), initial=0.0)), np.finfo(float).tiny)

    def scale(self, s):
        """The force scale S = max(|f|_inf, max |w0| / W_qq) (for the projected Newton's epsilon)."""
        return max(self.force_scale, float(np.max(np.abs(s.f), initial=0.0)))

    def linearization(self, s):
        """eta_lin = (sum_q W_qq G_q^2)^(1/2): each point's residual force G_q times the displacement
        W_qq G_q it causes there, an estimate of the energy norm |||u* - u|||_h of the change of u that
        solving the laws exactly would make (the diagonal of the Delassus operator in place of W;
        W_qq G_q^2 is work, the units of |||.|||_h^2)."""
        return float(np.sqrt(np.sum(self.diagonal * s.G * s.G)))

    def done(self, s, tol, energy_tol=None):
        """The stopping test: :meth:`converged` to ``tol``, or eta_lin <= ``energy_tol`` (if given)."""
        return (energy_tol is not None and self.linearization(s) <= energy_tol) or self.converged(s, tol)

    def converged(self, s, tol):
        """W_qq |G_q| <= max(tol max|w|, W_qq x round-off in G_q) at every point."""
        M = self.M
        size = np.abs(self.w0) + self.absW @ np.abs(s.f)  # magnitude of the terms summed into w
        roundoff = 8 * EPS * np.concatenate([
            np.abs(s.f[:M]) + s.N + s.dN * size[:M],
            np.where(s.stick, self.r * size[M:], np.abs(s.f[M:]) + s.beta + np.abs(s.dbeta) * size[:M])])
        weighted = self.diagonal * np.abs(s.G)
        return bool(np.all(weighted <= np.maximum(tol * self._trace_scale(s), self.diagonal * roundoff)))

    # ------------------------------------------------------------------ Newton direction
    def newton_direction(self, s):
        """d with J d = -G (identity rows eliminated; least squares if the rest is singular)."""
        M, W = self.M, self.W
        identity = np.concatenate([s.dN == 0, ~s.stick & (s.dbeta == 0)])
        d = np.where(identity, -s.G, 0.0)
        rows = np.flatnonzero(~identity)
        if rows.size == 0:
            return d
        # row of J = coefficient x (a row of W) + unit x e_row
        normal = rows < M
        t = rows[~normal] - M
        stick = s.stick[t]
        source, coefficient, unit = rows.copy(), np.empty(rows.size), np.ones(rows.size)
        coefficient[normal] = s.dN[rows[normal]]
        source[~normal] = np.where(stick, rows[~normal], t)  # stick: r W_t; slip (m_t > 0): s beta' W_n
        coefficient[~normal] = np.where(stick, self.r[t], s.sign[t] * s.dbeta[t])
        unit[~normal] = np.where(stick, self.regularization, 1.0)
        rhs = -s.G[rows] - coefficient * (W @ np.where(identity, d, 0.0))[source]
        block = W[np.ix_(source, rows)]
        block *= coefficient[:, None]
        block[np.arange(rows.size), np.arange(rows.size)] += unit
        d[rows] = _dense_solve(block, rhs)
        return d

    # ------------------------------------------------------------------ the energy (symmetric, m_t = 0)
    def project(self, f):
        """P_K(f): f_n >= 0 (= 0 where c_n = 0), |f_t| <= beta."""
        M = self.M
        return np.concatenate([np.where(self.compliant, np.maximum(f[:M], 0.0), 0.0),
                               np.clip(f[M:], -self.beta_fixed, self.beta_fixed)])

    def _conjugate(self, fn):
        """Phi*(f_n) per point (f_n >= 0; 0 where c_n = 0)."""
        m, safe = self.m_n, np.where(self.compliant, self.omega * self.c_n, 1.0)
        power = fn * fn / (2 * safe) if m == 1 else m / (m + 1) * safe ** (-1 / m) * fn ** ((m + 1) / m)
        return np.where(self.compliant, self.g_a * fn + power, 0.0)

    def gradient(self, s):
        """grad Theta = -w + (g_a + (f_n / (omega c_n))^{1/m}, 0) (0 in the f_n fixed at 0)."""
        M = self.M
        safe = np.where(self.compliant, self.omega * self.c_n, 1.0)
        normal = np.where(self.compliant, -s.w[:M] + self.g_a + (s.f[:M] / safe) ** (1 / self.m_n), 0.0)
        return np.concatenate([normal, -s.w[M:]])

    def _gradient_scaling(self, s):
        """D = diag(W) + the curvature of Phi* (capped), for the scaled projected gradient."""
        M, m = self.M, self.m_n
        safe = np.where(self.compliant, self.omega * self.c_n, 1.0)
        fn = np.maximum(s.f[:M], 1e-300)
        curvature = 1 / safe if m == 1 else (1 / m) * safe ** (-1 / m) * fn ** (1 / m - 1)
        normal = self.diagonal[:M] + np.minimum(curvature, 1e12 * self.diagonal[:M])
        return np.concatenate([normal, self.diagonal[M:]])

    def energy_change(self, s, f_new):
        """Theta(f_new) - Theta(f), evaluated as a difference (not of two large numbers), and its round-off."""
        M = self.M
        d = f_new - s.f
        Wd = self.W @ d
        conj_new, conj_old = self._conjugate(f_new[:M]), self._conjugate(s.f[:M])
        terms = np.array([-s.w @ d, 0.5 * d @ Wd, np.sum(conj_new - conj_old)])
        size = np.abs(s.w) @ np.abs(d) + 0.5 * np.abs(d) @ np.abs(Wd) + np.sum(np.abs(conj_new) + np.abs(conj_old))
        return float(np.sum(terms)), 64 * EPS * size

    def _bounds(self):
        lower = np.concatenate([np.zeros(self.M), -self.beta_fixed])
        upper = np.concatenate([np.where(self.compliant, np.inf, 0.0), self.beta_fixed])
        return lower, upper

    def _energy_step(self, s, d):
        """The Newton point if it lowers Theta enough, else a projected Newton step (module docstring)."""
        grad = self.gradient(s)
        scaling = self._gradient_scaling(s)
        p = self.project(s.f - grad / scaling) - s.f
        delta = max(float(-grad @ p), 0.0)
        residual = self.residual(s)

        def lowers(trial):
            # a change within round-off must at least halve the KKT residual instead (else two states
            # whose Theta differ by less than the round-off bound can alternate for ever)
            change, roundoff = self.energy_change(s, trial)
            return change <= -SIGMA * delta or (change <= -SIGMA * delta + roundoff
                                                and self.residual(self.evaluate(trial)) <= 0.5 * residual)

        trial = self.project(s.f + d)
        if lowers(trial):
            return trial, "newton"
        # watchdog (Chamberlain, Powell, Lemarechal & Pedersen, Math. Prog. Study 16, 1982): near the
        # solution a Newton step with a few wrong sets may raise Theta and the next one repair it
        if residual <= WATCHDOG:
            after = self.evaluate(trial)
            second = self.project(trial + self.newton_direction(after))
            if lowers(second):
                return second, "newton (watchdog)"
            # degenerate points (z = +-beta: stick and slip both hold at the solution) flip between
            # Newton iterates; hold the ones that flip at their bound (slip) and step once more
            flips = (s.stick != after.stick) & (np.abs(s.f[self.M:]) >= self.beta_fixed * (1 - 1e-8))
            if flips.any():
                held = self._held_at_bound(s, flips)
                third = self.project(s.f + self.newton_direction(held))
                if lowers(third):
                    return third, "newton (degenerate points held)"
        return self._projected_newton_step(s, grad, scaling, p)

    def _held_at_bound(self, s, points):
        """A copy of state s in which the friction variables ``points`` (at their bound) count as slip."""
        held = _State()
        for name in _State.__slots__:
            setattr(held, name, getattr(s, name))
        M = self.M
        held.stick = s.stick & ~points
        held.sign = np.where(points, np.sign(s.f[M:]), s.sign)
        held.G = s.G.copy()
        held.G[M:][points] = s.f[M:][points] - held.sign[points] * s.beta[points]
        return held

    def _projected_newton_step(self, s, grad, scaling, projected_gradient):
        """Bertsekas' projected Newton step (SIAM J. Control Optim. 20, 1982): variables within epsilon of
        a bound that the gradient pushes out stay there (scaled gradient step), the others take the Newton
        step of Theta restricted to them; Armijo search along the projection arc.  `projected_gradient` is
        the scaled projected-gradient step P_K(f - D^-1 grad) - f; epsilon is set per variable relative to
        its own size."""
        M, f = self.M, s.f
        lower, upper = self._bounds()
        # epsilon per variable, relative to its own size (forces vary with the edge length: graded meshes)
        size = np.concatenate([np.maximum(np.abs(f[:M]), np.abs(self.w0[:M]) / self.diagonal[:M]),
                               np.where(upper[M:] > 0, upper[M:], np.abs(self.w0[M:]) / self.diagonal[M:])])
        size = np.maximum(size, 1e-300)
        epsilon = min(1e-2, float(np.max(np.abs(projected_gradient) / size))) * size
        bound = ((f <= lower + epsilon) & (grad > 0)) | ((f >= upper - epsilon) & (grad < 0)) | (lower == upper)
        free = np.flatnonzero(~bound)
        direction = np.where(bound, -grad / scaling, 0.0)
        if free.size:
            curvature = np.concatenate([scaling[:M] - self.diagonal[:M], np.zeros(M)])  # Phi*'' (capped)
            hessian = self.W[np.ix_(free, free)]
            on_diagonal = np.arange(free.size)
            hessian[on_diagonal, on_diagonal] += curvature[free] + self.regularization * self.diagonal[free]
            direction[free] = _dense_solve(hessian, -grad[free])
        free_decrease = float(-grad[free] @ direction[free])
        t = 1.0
        for _ in range(50):
            trial = self.project(f + t * direction)
            predicted = t * free_decrease + float(grad[bound] @ (f[bound] - trial[bound]))
            if -self.energy_change(s, trial)[0] >= SIGMA * predicted:
                break
            t *= 0.5
        return trial, "projected newton" if t == 1 else f"projected newton x{t:g}"

    # ------------------------------------------------------------------ the merit function (otherwise)
    def merit(self, s):
        return 0.5 * float(np.sum(self.diagonal * s.G * s.G))

    def _merit_step(self, s, d, recent):
        psi = self.merit(s)
        reference = max(recent[-5:] + [psi])
        alpha = 1.0
        for _ in range(9):
            trial = s.f + alpha * d
            if self.merit(self.evaluate(trial)) <= reference - SIGMA * alpha * 2 * psi:
                return trial, "newton" if alpha == 1 else f"newton x{alpha:g}"
            alpha *= 0.5
        # Levenberg-Marquardt on the Gauss-Newton model of Psi
        J = self._jacobian(s)
        JtS = J.T * self.diagonal
        H = JtS @ J
        g = JtS @ s.G
        scaling = np.maximum(np.diag(H), 1e-300)
        mu = 1e-6
        for _ in range(24):
            step = np.linalg.lstsq(H + mu * np.diag(scaling), -g, rcond=None)[0]
            trial = s.f + step
            if self.merit(self.evaluate(trial)) < psi:
                return trial, "levenberg-marquardt"
            mu *= 10
        return None, "stalled"

    def _qvi_step(self, s, d, fixed_point):
        """m_t > 0: the Newton point if it lowers the fixed-point residual r(f) = |f - T(f)|_inf (T: the
        solution with the bound frozen at f), else T(f).  ``fixed_point``: T(s.f).  Returns
        (new f, kind, T(new f) or None)."""
        residual = np.max(np.abs(s.f - fixed_point))
        for alpha in (1.0, 0.5):
            trial = s.f + alpha * d
            trial_fixed_point = self._fixed_point_step(self.evaluate(trial))
            if np.max(np.abs(trial - trial_fixed_point)) <= (1 - SIGMA * alpha) * residual:
                return trial, "newton" if alpha == 1 else f"newton x{alpha:g}", trial_fixed_point
        return fixed_point, "fixed point", None

    def _fixed_point_step(self, s):
        """The solution of the problem with the friction bound frozen at its value at f (m_t = 0, a
        spatially varying c_tau = beta / omega), by this solver's own globalised Newton method."""
        return self._variant(c_tau=s.beta / self.omega, m_t=0.0).solve(s.f, tol=1e-13, maxit=200)[0]

    def _variant(self, W=None, w0=None, c_tau=None, m_t=None, symmetric=None, redundant=None):
        """This problem with some of W, w0, c_tau, m_t, the symmetry and redundancy replaced."""
        def pick(value, own):
            return own if value is None else value

        return ReducedContact(pick(W, self.W), pick(w0, self.w0), self.omega, self.g_a, self.c_n,
                              pick(c_tau, self.c_tau), self.m_n, pick(m_t, self.m_t),
                              pick(symmetric, self.energy_symmetric), pick(redundant, self.regularization > 0))

    def _jacobian(self, s):
        """The full generalised Jacobian J (2M x 2M)."""
        M, W = self.M, self.W
        J = np.empty((2 * M, 2 * M))
        J[:M] = s.dN[:, None] * W[:M]
        J[M:] = np.where(s.stick[:, None], self.r[:, None] * W[M:], (s.sign * s.dbeta)[:, None] * W[:M])
        diagonal = np.concatenate([np.ones(M), np.where(s.stick, self.regularization, 1.0)])
        J[np.arange(2 * M), np.arange(2 * M)] += diagonal
        return J

    # ------------------------------------------------------------------ forces <-> displacement, multiplier
    def forces(self, w, lam_tau):
        """The forces of the laws at traces w with multiplier values l = ``lam_tau``: (N(w_n), beta(w_n) l)
        (a warm start)."""
        M = self.M
        gap = w[:M] - self.g_a
        normal = self.omega * self.c_n * _positive_power(gap, self.m_n)
        beta = self.beta_fixed if self.m_t == 0 else self.omega * self.c_tau * _positive_power(gap, self.m_t)
        f = np.concatenate([normal, beta * np.clip(lam_tau, -1.0, 1.0)])
        return self.project(f) if self.energy_merit else f

    def traces(self, f):
        """w(f) = w0 - W f."""
        return self.w0 - self.W @ f

    def shift(self, mismatch):
        """w0 += mismatch (:func:`ngdgfric.newton.newton`: make w(f) the traces of the computed u)."""
        self.w0 = self.w0 + mismatch

    def multiplier(self, f):
        """l at the points: f_t / beta (clipped to [-1, 1]) where the point sticks, the slip direction
        sign(f_t + r w_t) where it slips or beta = 0 (Lemma 3.1).  The slip direction is taken from the
        law rather than from f_t / beta: where beta is below the force tolerance (c_tau or the
        penetration tiny) f_t carries no information about the direction, w_t does."""
        s = self.evaluate(f)
        M = self.M
        ratio = f[M:] / np.where(s.beta > 0, s.beta, 1.0)
        direction = np.where(f[M:] + self.r * s.w[M:] != 0, s.sign, 0.0)
        return np.where(s.stick, np.clip(ratio, -1.0, 1.0), direction)

    # ------------------------------------------------------------------ the iteration
    def solve(self, f0=None, tol=1e-12, maxit=100, progress=None, energy_tol=None):
        """Globalised semismooth Newton from f0 (default 0); returns (f, info).

        Stops when :meth:`converged` to ``tol`` or, if ``energy_tol`` is given, as soon as the
        linearisation estimate :meth:`linearization` is at most ``energy_tol`` (an inexact solve).

        info: ``iterations``; ``history``: relative KKT residual (:meth:`residual`) after each
        iteration; ``initial_residual``; ``linearization`` (eta_lin at the end); ``converged`` (``tol``
        met); ``steps``: the kind of each step ("newton", "newton x0.5",
        "projected newton", "levenberg-marquardt", "fixed point", "continuation s = ..."); ``penetrating``,
        ``stick``: set sizes at the end; ``residual``.
        For m_t > 0, if the iteration stalls, a continuation in c_tau (module docstring) follows.
        Raises :class:`SolverError` if the stopping test is not met within ``maxit`` iterations.
        """
        f = np.zeros(2 * self.M) if f0 is None else np.asarray(f0, dtype=float).copy()
        if self.energy_merit and self.regularization > 0:
            return self._proximal(self.project(f), tol, maxit, progress, energy_tol)
        try:
            return self._iterate(f, tol, maxit, progress, energy_tol)
        except SolverError as error:
            if self.energy_merit:
                raise
            return self._continuation(tol, maxit, progress, error)

    def _homotopy(self, s):
        """The problem at continuation parameter s in [0, 1] (s = 1: this one): for m_t > 0 c_tau scaled
        by s; otherwise (NIPG) W = sym(W) + s skew(W), symmetric at s = 0."""
        if self.m_t > 0:
            return self._variant(c_tau=s * self.c_tau)
        symmetric_part = 0.5 * (self.W + self.W.T)
        return self._variant(W=symmetric_part + s * (self.W - symmetric_part), symmetric=s == 0)

    def _continuation(self, tol, maxit, progress, error):
        """After a failure without energy: follow the solution from an easy problem to this one
        (:meth:`_homotopy`).  NIPG: s = 0 (the symmetric problem, solved by the energy method), then
        steps in s doubled after a success and halved after a failure, from 1/16.  m_t > 0: s = 1e-6
        (c_tau tiny: the bound map contracts), then s multiplied by a factor (4 at first) that is squared
        after a success and square-rooted after a failure.  Each solve starts from the last solution.
        Raises the original ``error`` (with a note) when the step (factor) falls below 1/1024 (1.001)."""
        f, iterations, steps, history = np.zeros(2 * self.M), 0, [], []
        geometric = self.m_t > 0
        done, step = (0.0, 1e-6) if geometric else (-1.0, 1.0)  # s = 1e-6, or s = 0 first

        def next_value():
            return min(1.0, step if done == 0 and geometric else done * step if geometric else done + step)

        while done < 1:
            s = next_value() if done >= 0 else 0.0
            try:
                f, info = self._homotopy(s)._iterate(f.copy(), tol, maxit, progress)
            except SolverError:
                if done < 0 or (geometric and done == 0):
                    raise SolverError(f"{error} (and the continuation failed at its start s = {s:g})",
                                      history=error.history, solver="newton") from error
                step = np.sqrt(step) if geometric else step / 2
                if (geometric and step < 1.001) or (not geometric and step < 1 / 1024):
                    raise SolverError(f"{error} (and the continuation stopped at s = {done:g})",
                                      history=error.history, solver="newton") from error
                continue
            iterations += info["iterations"]
            steps += [f"continuation s = {s:g}"] + info["steps"]
            history += info["history"]
            if geometric:
                step = 4.0 if done == 0 else step * step
            elif done < 0:
                step = 1 / 16
            else:
                step *= 2
            done = s
        info.update(iterations=iterations, steps=steps, history=history)
        return f, info

    def _proximal(self, f, tol, maxit, progress, energy_tol):
        """The proximal point method of the module docstring (redundant points, with energy), from f."""
        mu, iterations, history, steps = PROXIMAL_START, 0, [], []
        initial = self.residual(self.evaluate(f))
        while not self.done(self.evaluate(f), tol, energy_tol):
            if iterations >= maxit:
                raise SolverError(f"semismooth Newton on the contact points (proximal point method) did not reach "
                                  f"tol = {tol:g} in {maxit} iterations (relative KKT residual {history[-1]:.3e})",
                                  history=history, solver="newton")
            problem = self._variant(W=self.W + np.diag(mu * self.diagonal), w0=self.w0 + mu * self.diagonal * f,
                                    redundant=False)
            steps.append(f"proximal mu = {mu:g}")
            report = None if progress is None else (lambda k, residual, done=iterations: progress(done + k, residual))
            try:
                f, info = problem._iterate(f, tol, maxit - iterations, report, energy_tol, outer=self)
            except SolverError as error:
                iterations += len(error.history)
                history += error.history
                mu *= 10.0
                continue
            iterations += info["iterations"]
            history += info["history"]
            steps += info["steps"]
            mu /= PROXIMAL_DECREASE
        return f, self._info(self.evaluate(f), tol, iterations, history, initial, steps)

    def _info(self, s, tol, iterations, history, initial, steps):
        """The ``info`` of :meth:`solve` at the final state s."""
        return dict(iterations=iterations, history=history, initial_residual=initial, steps=steps,
                    penetrating=int(np.sum(s.penetrating)), stick=int(np.sum(s.stick)), residual=self.residual(s),
                    linearization=self.linearization(s), converged=self.converged(s, tol))

    def _iterate(self, f, tol, maxit, progress, energy_tol=None, outer=None):
        """The iteration of :meth:`solve` from f.  ``outer``: the problem whose stopping test also ends it
        and whose KKT residual is recorded (a proximal subproblem's original problem); default self."""
        if self.energy_merit:
            f = self.project(f)
        outer = self if outer is None else outer
        s = self.evaluate(f)
        history, steps, recent = [], [], []
        fixed_point, fixed_point_changes = None, []  # m_t > 0: T(f), and |f - T(f)| per iteration
        initial = self.residual(s)
        for k in range(maxit + 1):
            outer_done = outer is not self and outer.done(outer.evaluate(s.f), tol, energy_tol)
            if outer_done or self.done(s, tol, energy_tol):
                return s.f, self._info(s, tol, k, history, initial, steps)
            if k == maxit:
                break
            d = self.newton_direction(s)
            if self.energy_merit:
                f, kind = self._energy_step(s, d)
            elif self.m_t > 0:
                fixed_point = self._fixed_point_step(s) if fixed_point is None else fixed_point
                change = np.max(np.abs(s.f - fixed_point)) / self.scale(s)
                fixed_point_changes.append(change)
                if len(fixed_point_changes) > 10 and min(fixed_point_changes[-5:]) > min(fixed_point_changes[:-5]):
                    raise SolverError(f"semismooth Newton on the contact points: neither Newton steps nor the fixed "
                                      f"point on the friction bound reduce |f - T(f)| (now {change:.3e} after {k} "
                                      "iterations): the bound map is not a contraction here, and the quasi-variational "
                                      "inequality (m_t > 0) may have no solution or several", history=history,
                                      solver="newton")
                f, kind, fixed_point = self._qvi_step(s, d, fixed_point)
            else:
                recent.append(self.merit(s))
                f, kind = self._merit_step(s, d, recent)
                if f is None:
                    raise SolverError(f"semismooth Newton on the contact points stalled at iteration {k + 1}: no "
                                      f"Levenberg-Marquardt step lowers the merit function (KKT residual "
                                      f"{self.residual(s):.3e}); the problem may have no solution",
                                      history=history, solver="newton")
            s = self.evaluate(f)
            steps.append(kind)
            history.append(outer.residual(s if outer is self else outer.evaluate(f)))
            if progress is not None:
                progress(k + 1, history[-1])
        raise SolverError(f"semismooth Newton on the contact points did not reach tol = {tol:g} in {maxit} "
                          f"iterations (relative KKT residual {history[-1] if history else initial:.3e}; "
                          f"last steps {steps[-3:]})", history=history, solver="newton")
