r"""The contact problem condensed onto the Gauss points of :math:`\Gamma_C`: the laws, their residual and Jacobian.

Unknowns: the contact forces :math:`f = (f_n, f_t)` at the :math:`M` Gauss points (:math:`f = \omega \times`
traction density, :mod:`ngdgfric.contact.traces`), with the traces :math:`w(f) = w_0 - W f` of the displacement
(:math:`W` the Delassus operator, :mod:`ngdgfric.solvers.condensation`).  The compliance law (1.8), the friction
law (1.9) and Lemma 3.1 hold at every point :math:`q` iff :math:`G(f) = 0`, where

.. math::

    G_n = f_n - N(w_n), \qquad N(w_n) = \omega c_n (w_n - g_a)_+^{m_n},

    G_t = f_t - P_{[-\beta, \beta]}(f_t + r w_t), \qquad \beta(w_n) = \omega c_\tau (w_n - g_a)_+^{m_t}

(:math:`\beta = \omega c_\tau` for the reduced law :math:`m_t = 0`); the multiplier is
:math:`\lambda_\tau = f_t / \beta`, so :math:`|\lambda_\tau| \le 1` and :math:`\lambda_\tau u_\tau = |u_\tau|`
(3.4).  Any :math:`r > 0` gives the same solutions; :math:`r_q = 1 / W_{t_q t_q}`, the point's own tangential
stiffness, makes the stick/slip decision scale-free (the Alart-Curnier choice; Acary, Bremond & Huber, "On
solving contact problems with Coulomb friction: formulations and numerical comparisons", 2018).

**Newton step.**  :math:`J d = -G` with :math:`J` an element of the generalised Jacobian of :math:`G`: the
identity row for a point without penetration (:math:`G_n = f_n`) or slipping with a fixed bound
(:math:`G_t = f_t \mp \beta`), :math:`e_q + N'(w_n) W_q` for a penetrating point, :math:`r W_q` for a sticking
one (:math:`G_t = -r w_t`), and :math:`e_q \pm \beta'(w_n) W_q` for a slipping one with :math:`m_t > 0`.
Identity rows are eliminated, so the dense system has one row per penetrating or sticking point.  The globalised
iteration is ``solve`` of :mod:`ngdgfric.solvers.semismooth`; for a symmetric :math:`B_h` and :math:`m_t = 0` it
descends the complementary energy of :mod:`ngdgfric.solvers.complementary_energy` over the set :math:`K` of
``ReducedContact.project``.

**Stopping test** (on the KKT system, not on the change of :math:`f`):
:math:`W_{qq} |G_q| \le \max(\mathrm{solver\_tol}\, D, W_{qq} e_q)` at every point: each point's residual force
measured by the displacement it causes there (at a sticking point :math:`W_{tt} |G_t| = |u_\tau|`, the
complementarity of (3.4)), relative to the largest trace :math:`D` (``ReducedContact.trace_scale``), and
:math:`e_q` the round-off in evaluating :math:`G_q` (:math:`8 \epsilon` times the sizes of its terms; it matters
for stiff compliance, :math:`c_n \to 10^{10}`).

**Redundant points** (``redundant``: an element with two edges on :math:`\Gamma_C`, or :math:`p_T < p` on hp
meshes): :math:`W` is singular and the forces at those points are not unique (the displacement is).  For
:math:`m_t = 0` (with or without energy) the proximal point method of :mod:`ngdgfric.solvers.semismooth` handles
them; for :math:`m_t > 0` the sticking rows of :math:`J` get :math:`10^{-8}` on the diagonal instead
(:math:`r W_{qq} = 1` there), which leaves the solutions unchanged (:math:`d = 0` iff :math:`G = 0`) and picks a
small step in the kernel.
"""

import numpy as np

from ..contact.laws import bound_rate, law_forces, pressure_rate_values, pressure_values, project_unit_values
from ..errors import SolverError, SolverWarning, warn
from ..threads import dense_threads

__all__ = ["ReducedContact", "PointState", "point_state", "multiplier_of", "trace_scale", "pair_forces",
           "independent", "dense_solve", "EPS"]

EPS = np.finfo(float).eps
DIAGONAL_FLOOR = 1e-14  # W_qq below this times the largest: raised to it (r_q = 1 / W_tt stays finite)
NEGATIVE_DIAGONAL = 1e-10  # W_qq below -this times the largest: not round-off, A is not coercive


def dense_solve(matrix, rhs, diagnostics=None):
    """matrix^-1 rhs by LU, on all cores when large; if the matrix is singular or LU gives non-finite values,
    the least-squares solution (rcond 1e-13), counted in ``diagnostics["least_squares_solves"]`` (a
    :attr:`ReducedContact.diagnostics`) when given.

    The solves are Newton systems: their solution is a direction that the globalisation of
    :mod:`ngdgfric.solvers.semismooth` accepts only if it lowers its merit, and convergence is decided by the
    KKT residual, so a least-squares direction cannot make a wrong answer pass; the count tells that the
    Jacobian was singular there (:class:`~ngdgfric.errors.SolverWarning` from the solver)."""
    with dense_threads(len(rhs)):
        try:
            solution = np.linalg.solve(matrix, rhs)
        except np.linalg.LinAlgError:
            solution = None
        if solution is None or not np.all(np.isfinite(solution)):
            solution = np.linalg.lstsq(matrix, rhs, rcond=1e-13)[0]
            if diagnostics is not None:
                diagnostics["least_squares_solves"] += 1
    return solution


def _floored_diagonal(W):
    """(diag W with entries below DIAGONAL_FLOOR x the largest raised to that floor, the number raised).
    SolverError if an entry is negative beyond round-off (B_h not coercive)."""
    diagonal = np.diag(W).copy()
    largest = np.max(np.abs(diagonal), initial=0.0)
    negative = np.flatnonzero(diagonal < -NEGATIVE_DIAGONAL * largest)
    if negative.size:
        raise SolverError(f"the Delassus operator W = B A^-1 B^T has {negative.size} negative diagonal entries "
                          f"(the most negative {diagonal.min():.3e}, the largest {largest:.3e}): A is not coercive "
                          "(is the penalty eta large enough?)", solver="newton")
    floor = DIAGONAL_FLOOR * largest if largest > 0 else 1.0
    low = diagonal < floor
    return np.where(low, floor, diagonal), int(np.sum(low))


class PointState:
    """Everything Newton needs at one f (:meth:`ReducedContact.evaluate`): the forces ``f``, traces ``w``,
    residual ``G``, pressure ``N`` and its derivative ``dN``, friction bound ``beta`` and ``dbeta``, the
    sets ``stick``, ``penetrating`` and the slip direction ``sign``."""

    __slots__ = ("f", "w", "G", "N", "dN", "beta", "dbeta", "stick", "sign", "penetrating")

    def replace(self, **changes):
        """A new state with the arrays ``changes`` (keyword per field), the other arrays shared."""
        other = PointState()
        for name in self.__slots__:
            setattr(other, name, changes.pop(name) if name in changes else getattr(self, name))
        if changes:
            raise TypeError(f"PointState has no field {sorted(changes)[0]!r}")
        return other


def _exponents(law):
    """(m_n, m_t) of ``law`` as arrays of one entry per point."""
    M = len(law.omega)
    return (np.broadcast_to(np.asarray(m, dtype=float), (M,)) for m in (law.m_n, law.m_t))


def point_state(law, f, w, r):
    """The :class:`PointState` of the laws at forces f and traces w (module docstring): N, N', beta, beta', the
    stick and slip sets and G.  ``law``: the point data omega, g_a, c_n, c_tau, m_n, m_t (a :class:`ReducedContact`,
    or the :class:`~ngdgfric.contact.traces.ContactTraces` of the full-space solver); ``r``: r_q per point.  The one
    implementation of the laws for both contact solvers."""
    M, s = len(law.omega), PointState()
    m_n, m_t = _exponents(law)
    s.f, s.w = f, w
    gap = w[:M] - law.g_a
    s.penetrating = gap > 0
    s.N = pressure_values(gap, law.omega * law.c_n, m_n)
    s.dN = pressure_rate_values(gap, law.omega * law.c_n, m_n)
    s.beta, s.dbeta = bound_rate(gap, law.omega * law.c_tau * np.ones(M), m_t)
    z = f[M:] + r * w[M:]
    s.stick = np.abs(z) < s.beta
    s.sign = np.where(z >= 0, 1.0, -1.0)
    s.G = np.concatenate([f[:M] - s.N, np.where(s.stick, -r * w[M:], f[M:] - s.sign * s.beta)])
    return s


def multiplier_of(s, r):
    """lam_tau at the points of the :class:`PointState` s: f_t / beta (clipped to [-1, 1]) where the point sticks,
    the slip direction sign(f_t + r w_t) where it slips or beta = 0 (Lemma 3.1).  The slip direction is taken from
    the law rather than from f_t / beta: where beta is below the force tolerance (c_tau or the penetration tiny)
    f_t carries no information about the direction, w_t does."""
    M = len(s.beta)
    ratio = s.f[M:] / np.where(s.beta > 0, s.beta, 1.0)
    direction = np.where(s.f[M:] + r * s.w[M:] != 0, s.sign, 0.0)
    return np.where(s.stick, project_unit_values(ratio), direction)


def trace_scale(s, g_a):
    """D = max(max_q |w_q|, eps max |g_a| over the penetrating points) of the :class:`PointState` s: the largest
    trace, which at a solution is the size of u on Gamma_C.  A body loaded by an initial penetration only (f = 0,
    g = 0, g_a < 0) starts from w = 0: there the penetrated gap keeps D, and the relative residual, finite."""
    gaps = EPS * np.abs(g_a[s.penetrating])
    return max(float(np.max(np.abs(s.w), initial=0.0)), float(np.max(gaps, initial=0.0)), np.finfo(float).tiny)


class ReducedContact:
    """The condensed problem of the module docstring.

    W (2M x 2M, rows and columns ordered n_1 ... n_M, t_1 ... t_M) and w0 (2M) from the
    condensation; omega, g_a, c_n, c_tau: arrays of length M; m_n >= 1, m_t >= 0 (numbers, or arrays of length M:
    the exponents of several contact sides); symmetric: W is
    symmetric (B_h symmetric); redundant: see the module docstring.  ``energy_merit``: whether the
    iteration descends the complementary energy (symmetric and m_t = 0).  Keywords only (ten arrays and
    numbers that are easy to swap); :meth:`condensed` builds it from a condensation and its traces.

    ``diagonal``: diag W, entries below 1e-14 times the largest raised to that floor (a point whose
    traces hardly move under its own force; SolverError if an entry is negative beyond round-off: A not
    coercive).  ``diagnostics``: counts shared with every :meth:`variant` (the proximal and continuation
    subproblems): ``least_squares_solves`` (:func:`dense_solve`) and ``clamped_points`` (diagonal entries
    raised; a :class:`~ngdgfric.errors.SolverWarning` when there are any).
    """

    def __init__(self, *, W, w0, omega, g_a, c_n, c_tau, m_n, m_t, symmetric, redundant=False, diagnostics=None):
        self.M = M = len(omega)
        self.W, self.w0 = np.asarray(W, dtype=float), np.asarray(w0, dtype=float)
        self.absW = np.abs(self.W)
        self.omega, self.g_a = np.asarray(omega, dtype=float), np.asarray(g_a, dtype=float)
        self.c_n, self.c_tau = np.asarray(c_n, dtype=float), np.asarray(c_tau, dtype=float)
        self.m_n, self.m_t = (np.broadcast_to(np.asarray(m, dtype=float), (M,)).copy() for m in (m_n, m_t))
        self.quasi_variational = bool(np.any(self.m_t > 0))  # the bound depends on the gap somewhere
        self.diagonal, clamped = _floored_diagonal(self.W)
        if diagnostics is None:  # the original problem, not a variant
            diagnostics = dict(least_squares_solves=0, clamped_points=clamped)
            if clamped:
                warn(f"the Delassus operator has {clamped} of {2 * M} diagonal entries below 1e-14 times the largest "
                     "(points whose traces hardly move under their own force, e.g. a row of B near zero): raised "
                     "to that floor", SolverWarning)
        self.diagnostics = diagnostics
        self.r = 1.0 / self.diagonal[M:]
        self.energy_symmetric = bool(symmetric)
        self.energy_merit = bool(symmetric and not self.quasi_variational)
        self.redundant = bool(redundant)
        self.regularization = 1e-8 if redundant else 0.0
        # forces of the size that the traces w0 of the loads, or the initial penetrations (w0_n - g_a)_+, cause
        penetration = np.concatenate([np.maximum(self.w0[:M] - self.g_a, 0.0), np.zeros(M)])
        self.force_scale = max(float(np.max(np.maximum(np.abs(self.w0), penetration) / self.diagonal, initial=0.0)),
                               np.finfo(float).tiny)
        self.compliant = self.c_n > 0
        self.beta_fixed = None if self.quasi_variational else self.omega * self.c_tau

    @classmethod
    def condensed(cls, condensation, traces, symmetric, checked=False):
        """The problem of a :class:`~ngdgfric.solvers.condensation.Condensation` (W, w0) at the points of its
        :class:`~ngdgfric.contact.traces.ContactTraces` ``traces`` (weights, law data, redundancy); ``symmetric``:
        B_h symmetric; ``checked``: with contact pairs, the points are redundant only where W is singular
        (``independent``; not checked for the proximal steps of a floating body, whose W carries its compliance
        1 / eps)."""
        redundant = traces.redundant and not (checked and traces.foundation < traces.M and independent(condensation.W))
        return cls(W=condensation.W, w0=condensation.w0, omega=traces.omega, g_a=traces.g_a, c_n=traces.c_n,
                   c_tau=traces.c_tau, m_n=traces.m_n, m_t=traces.m_t, symmetric=symmetric, redundant=redundant)

    def variant(self, W=None, w0=None, c_tau=None, m_t=None, symmetric=None, redundant=None):
        """This problem with some of W, w0, c_tau, m_t, the symmetry and redundancy replaced (sharing its
        ``diagnostics``)."""
        def pick(value, own):
            return own if value is None else value

        return ReducedContact(W=pick(W, self.W), w0=pick(w0, self.w0), omega=self.omega, g_a=self.g_a,
                              c_n=self.c_n, c_tau=pick(c_tau, self.c_tau), m_n=self.m_n, m_t=pick(m_t, self.m_t),
                              symmetric=pick(symmetric, self.energy_symmetric),
                              redundant=pick(redundant, self.redundant), diagnostics=self.diagnostics)

    # ------------------------------------------------------------------ the laws and G
    def evaluate(self, f):
        """The :class:`PointState` at forces f (:func:`point_state` at the traces w0 - W f)."""
        return point_state(self, f, self.w0 - self.W @ f, self.r)

    def residual(self, s):
        """The relative KKT residual max_q W_qq |G_q| / D: each point's residual force measured by the
        displacement it causes at that point, relative to the displacement scale D of :meth:`trace_scale`."""
        return float(np.max(self.diagonal * np.abs(s.G), initial=0.0)) / self.trace_scale(s)

    def trace_scale(self, s):
        """D of :func:`trace_scale`."""
        return trace_scale(s, self.g_a)

    def scale(self, s):
        """The force scale S = max(|f|_inf, max_q max(|w0_q|, (w0_n - g_a)_+) / W_qq) (for the projected Newton's
        epsilon): the forces the loads, or the initial penetrations, cause."""
        return max(self.force_scale, float(np.max(np.abs(s.f), initial=0.0)))

    def linearization(self, s):
        """eta_lin = (sum_q W_qq G_q^2)^(1/2): each point's residual force G_q times the displacement
        W_qq G_q it causes there, an estimate of the energy norm |||u* - u|||_h of the change of u that
        solving the laws exactly would make (the diagonal of the Delassus operator in place of W;
        W_qq G_q^2 is work, the units of |||.|||_h^2)."""
        return float(np.sqrt(np.sum(self.diagonal * s.G * s.G)))

    def done(self, s, solver_tol, energy_tol=None):
        """The stopping test: :meth:`converged` to ``solver_tol``, or eta_lin <= ``energy_tol`` (if given)."""
        return (energy_tol is not None and self.linearization(s) <= energy_tol) or self.converged(s, solver_tol)

    def converged(self, s, solver_tol):
        """W_qq |G_q| <= max(solver_tol max|w|, W_qq x round-off in G_q) at every point."""
        M = self.M
        size = np.abs(self.w0) + self.absW @ np.abs(s.f)  # magnitude of the terms summed into w
        roundoff = 8 * EPS * np.concatenate([
            np.abs(s.f[:M]) + s.N + s.dN * size[:M],
            np.where(s.stick, self.r * size[M:], np.abs(s.f[M:]) + s.beta + np.abs(s.dbeta) * size[:M])])
        weighted = self.diagonal * np.abs(s.G)
        return bool(np.all(weighted <= np.maximum(solver_tol * self.trace_scale(s), self.diagonal * roundoff)))

    # ------------------------------------------------------------------ Newton direction
    def newton_direction(self, s):
        """d with J d = -G (identity rows eliminated; least squares if the rest is singular, counted by
        :func:`dense_solve`)."""
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
        d[rows] = dense_solve(block, rhs, self.diagnostics)
        return d

    def jacobian(self, s):
        """The full generalised Jacobian J (2M x 2M)."""
        M, W = self.M, self.W
        J = np.empty((2 * M, 2 * M))
        J[:M] = s.dN[:, None] * W[:M]
        J[M:] = np.where(s.stick[:, None], self.r[:, None] * W[M:], (s.sign * s.dbeta)[:, None] * W[:M])
        diagonal = np.concatenate([np.ones(M), np.where(s.stick, self.regularization, 1.0)])
        J[np.arange(2 * M), np.arange(2 * M)] += diagonal
        return J

    # ------------------------------------------------------------------ the set K (m_t = 0)
    def project(self, f):
        """P_K(f): f_n >= 0 (= 0 where c_n = 0), |f_t| <= beta."""
        M = self.M
        return np.concatenate([np.where(self.compliant, np.maximum(f[:M], 0.0), 0.0),
                               np.clip(f[M:], -self.beta_fixed, self.beta_fixed)])

    def bounds(self):
        """The lower and upper bounds of f in K (m_t = 0)."""
        lower = np.concatenate([np.zeros(self.M), -self.beta_fixed])
        upper = np.concatenate([np.where(self.compliant, np.inf, 0.0), self.beta_fixed])
        return lower, upper

    # ------------------------------------------------------------------ forces <-> displacement, multiplier
    def forces(self, w, lam_tau):
        """The forces of the laws at traces w with multiplier values ``lam_tau`` (:func:`law_forces`; a warm start),
        projected onto K where the iteration descends the energy."""
        f = law_forces(self, w, lam_tau)
        return self.project(f) if self.energy_merit else f

    def traces(self, f):
        """w(f) = w0 - W f."""
        return self.w0 - self.W @ f

    def shift(self, mismatch):
        """w0 += mismatch (:class:`ngdgfric.solvers.newton.NewtonState`: make w(f) the traces of the computed u)."""
        self.w0 = self.w0 + mismatch

    def multiplier(self, f):
        """lam_tau at the points (:func:`multiplier_of` at f)."""
        return multiplier_of(self.evaluate(f), self.r)


INDEPENDENT = 1e-12
"""The rows of B are independent when the least eigenvalue of the symmetric part of D^-1/2 W D^-1/2 (D = diag W)
is above this."""
INDEPENDENCE_CHECKED = 4000
"""The largest W (rows) whose eigenvalues ``independent`` computes; above, the points stay redundant."""


def independent(W):
    """Whether the Delassus operator W = B A^-1 B^T is nonsingular, so that the rows of B are independent and the
    forces unique (the least eigenvalue of its scaled symmetric part above ``INDEPENDENT``); False for W larger than
    ``INDEPENDENCE_CHECKED``.  ``ContactTraces`` marks the points of contact pairs redundant (the rows of a piece of
    an edge may repeat another's); where they are not, the plain iteration takes far fewer steps than the
    proximal point method that redundant points take."""
    W = np.asarray(W)
    if len(W) > INDEPENDENCE_CHECKED:
        return False
    scale = 1.0 / np.sqrt(np.maximum(np.abs(np.diag(W)), np.finfo(float).tiny))
    scaled = scale[:, None] * W * scale[None, :]
    return bool(np.linalg.eigvalsh(0.5 * (scaled + scaled.T))[0] > INDEPENDENT)


def pair_forces(traces, f):
    """The forces (normal, tangential) at the contact pairs' points (those after the foundation's,
    ``traces.foundation``) of the forces ``f`` at every point: an array (2, points of the pairs), on the pair's side
    (the other side takes them with the opposite sign)."""
    M, start = traces.M, traces.foundation
    return np.stack([np.asarray(f)[start:M], np.asarray(f)[M + start:]])
