r"""The fixed point on the friction bound for the quasi-variational inequality (1.4), :math:`m_t > 0`.

.. math::

    u^{k+1}: \text{ the solution of (3.3)-(3.4) with the bound } c_\tau (u^k_n - g_a)_+^{m_t} \text{ frozen},

i.e. of a reduced-law problem (:math:`m_t = 0`) with a spatially varying friction bound
(``frozen_bound`` of ``ngdgfric.contact.forms``), solved by the inner solver on the same discretisation,
warm-started from :math:`(u^k, \lambda_\tau^k)`; stopped when
:math:`\|u^{k+1} - u^k\|_\infty \le` ``solver_tol`` :math:`\|u^{k+1}\|_\infty`.
It starts from :math:`u^0 = 0` (bound 0 where :math:`g_a > 0`: the frictionless problem) or from ``initial``.

The map :math:`u^k \mapsto u^{k+1}` is a contraction only if the bound varies slowly with :math:`u_n` compared
with the stiffness of the body: its Lipschitz constant grows like the slope
:math:`c_\tau m_t (u_n - g_a)_+^{m_t - 1}` of the bound (on Example 6.1, :math:`m_t = 1`, :math:`h = 1/16`:
contraction factor about :math:`0.25\, c_\tau / 450`; it stalled at :math:`c_\tau = 1800` and 3600, the results
page *Friction bound depending on the penetration*).  For large :math:`c_\tau` the iteration stalls, or a
warm-started inner solve cycles because the frozen bound jumps between outer iterations; the coupled semismooth
Newton (:mod:`ngdgfric.solvers.newton`) converged in all these cases.  For :math:`m_t = 0` the bound does not
depend on :math:`u` and one inner solve is the answer.

Contact pairs (:class:`~ngdgfric.ContactPair`) with the reduced law (:math:`m_t = 0`) are solved by the inner
solver with the rest (their multiplier restarts from 0 in each inner solve; ``info["pair_multiplier"]`` and
``info["pair_forces"]`` are those of the last); the friction bound of a pair with :math:`m_t > 0` is not frozen
here (ValueError: the coupled Newton solves it).
"""

import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..checks import callback, choice, optional, positive_integer, positive_number
from ..contact.forms import frozen_bound
from ..errors import SolverError, TimeLimitError, check_deadline, deadline
from ..problem import exponents
from ..transfer import starting_point
from .newton import NewtonOptions, newton
from .nonlinear import relative_change
from .options import SolverOptions
from .uzawa import UzawaOptions, uzawa

__all__ = ["fixed_point", "FixedPointOptions", "INNER"]

INNER = {"newton": (newton, NewtonOptions), "uzawa": (uzawa, UzawaOptions)}
OUTER = ("solver_tol", "maxit", "progress", "max_seconds")


def _inner_options(value, name):
    if value is not None and not isinstance(value, (NewtonOptions, UzawaOptions)):
        raise ValueError(f"{name} must be None, NewtonOptions or UzawaOptions, got {value!r}")


@dataclass(frozen=True)
class FixedPointOptions(SolverOptions):
    r"""The options of the fixed point on the friction bound (the keywords of ``solve(solver="fixed_point")``).

    The solver of :mod:`ngdgfric.solvers.fixed_point` (:func:`ngdgfric.solve`), for :math:`m_t > 0`.

    Parameters
    ----------
    solver_tol : float, optional
        The relative max-norm change of :math:`u` at which the outer iteration stops.  Default ``1e-8``.
    maxit : int, optional
        Outer iterations.  Default ``100``.
    progress : callable or None, optional
        ``progress(message)`` is called after each outer iteration with a line such as
        ``"fixed point 3: relative change 1.2e-05"``.  Default ``None``: no messages.
    inner : NewtonOptions or UzawaOptions or None, optional
        The options of the inner solver, :class:`ngdgfric.NewtonOptions` or :class:`ngdgfric.UzawaOptions`,
        whose type chooses it, used as given (their own ``solver_tol``, ``maxit``, ``progress``,
        ``max_seconds``).  Default ``None``: Newton with the outer ``solver_tol`` (the property
        ``inner_options``).  As keywords of :func:`ngdgfric.solve` (``from_keywords``): ``inner="newton"`` or
        ``"uzawa"`` and that solver's options other than ``solver_tol``, ``maxit``, ``progress`` and
        ``max_seconds``, with the outer ``solver_tol``.
    max_seconds : float or None, optional
        Stop with :class:`ngdgfric.TimeLimitError` (a :class:`ngdgfric.SolverError`) after this long (each inner
        solve stops at its own ``max_seconds`` or at the time that is left, whichever comes first).  Default
        ``None``: no limit.

    Attributes
    ----------
    inner_options : NewtonOptions or UzawaOptions
        The options of the inner solves: ``inner``, or for ``None`` Newton's defaults with the outer
        ``solver_tol``.

    Raises
    ------
    ValueError
        A value out of its range, named with the value.

    See Also
    --------
    ngdgfric.NewtonOptions, ngdgfric.UzawaOptions : The options of the other solvers.

    Examples
    --------
    >>> options = ndf.FixedPointOptions.from_keywords(inner="uzawa", rho=0.5)
    >>> options.inner.solver, options.inner.rho, options.inner.solver_tol
    ('uzawa', 0.5, 1e-08)
    """

    solver = "fixed_point"
    checks = dict(solver_tol=positive_number, maxit=positive_integer, progress=callback, inner=_inner_options,
                  max_seconds=optional(positive_number))

    solver_tol: float = 1e-8
    maxit: int = 100
    progress: Callable[[str], None] | None = None
    inner: NewtonOptions | UzawaOptions | None = None
    max_seconds: float | None = None

    @property
    def inner_options(self):
        """The inner solves' options (``inner``, or for None Newton's defaults with the outer solver_tol)."""
        return NewtonOptions(solver_tol=self.solver_tol) if self.inner is None else self.inner

    @classmethod
    def from_keywords(cls, **options):
        """The options from the keywords of ``solve(solver="fixed_point", ...)`` (None means the default):
        ``solver_tol``, ``maxit``, ``progress``, ``inner`` ("newton" or "uzawa") and the inner solver's
        options, which must be its own (ValueError naming any other); the inner solve gets the outer solver_tol."""
        outer = {name: options.pop(name, None) for name in OUTER}
        outer = {name: value for name, value in outer.items() if value is not None}
        inner = options.pop("inner", None)
        inner = "newton" if inner is None else inner
        choice(*INNER)(inner, "inner")
        solver_tol = outer.get("solver_tol", cls.solver_tol)
        positive_number(solver_tol, "solver_tol")
        inner_options = INNER[inner][1].from_keywords(f"fixed_point with inner={inner!r}", solver_tol=solver_tol,
                                                      **options)
        if inner_options == cls(**outer).inner_options:
            inner_options = None  # what None means: FixedPointOptions.from_keywords() == FixedPointOptions()
        return cls(**outer, inner=inner_options)


def _time_limited(options, until):
    """The inner solver's ``options`` with max_seconds at most the time left before ``until`` (None: no limit)."""
    if until is None:
        return options
    left = max(until - time.perf_counter(), 1e-9)
    return dataclasses.replace(options, max_seconds=left if options.max_seconds is None else
                               min(options.max_seconds, left))


def fixed_point(disc, contact, options=None, initial=None):
    """The fixed point of the module docstring with the ``FixedPointOptions`` ``options`` (default:
    the defaults); returns (u, lam_tau, info).

    initial: None or a pair of GridFunctions (u, lam_tau) on ``disc.V``, ``contact.Q`` to start from.
    info: ``iterations`` (outer), ``history`` (relative changes), ``inner_iterations`` (per outer
    iteration), ``factorizations`` (summed over the inner solves), ``timings``, and with contact pairs
    ``pair_multiplier`` and ``pair_forces`` (of the last inner solve).
    Raises ``SolverError`` (with the history) if it diverges or does not converge in maxit; ValueError for a
    contact pair with m_t > 0 (module docstring).
    """
    options = FixedPointOptions() if options is None else options
    coupled = [pair.m_t for pair in disc.problem.pairs if pair.m_t != 0]
    if coupled:
        raise ValueError(f"fixed_point does not freeze the friction bound of a contact pair (m_t = {coupled[0]:g} "
                         "> 0): use solver='newton' (the coupled semismooth Newton)")
    inner_options = options.inner_options
    inner_solver, inner = INNER[inner_options.solver][0], inner_options.solver
    start = time.perf_counter()
    until = deadline(options.max_seconds)
    u, lam_tau = starting_point(contact, initial)
    du = u.vec.CreateVector()
    history, inner_iterations, factorizations = [], [], 0
    for k in range(1, options.maxit + 1):
        check_deadline(until, "fixed point", history, f"after {k - 1} iterations")
        try:
            u_new, lam_tau_new, info = inner_solver(disc, contact, _time_limited(inner_options, until),
                                                    initial=(u, lam_tau), problem=frozen_bound(disc.problem, u))
        except TimeLimitError:
            raise
        except SolverError as error:
            raise SolverError(f"fixed point: the inner {inner} solve {k} failed: {error}", history=history,
                              solver="fixed_point") from error
        inner_iterations.append(info["iterations"])
        factorizations += info.get("factorizations", 0)
        du.data = u_new.vec - u.vec
        u.vec.data, lam_tau.vec.data = u_new.vec, lam_tau_new.vec
        history.append(relative_change(du, u.vec))
        if options.progress is not None:
            options.progress(f"fixed point {k}: relative change {history[-1]:.2e}")
        if history[-1] <= options.solver_tol or max(exponents(disc.problem.m_t)) == 0:
            pairs = {key: info[key] for key in ("pair_multiplier", "pair_forces") if key in info}
            return u, lam_tau, dict(iterations=k, history=history, inner_iterations=inner_iterations,
                                    factorizations=factorizations, timings=dict(total=time.perf_counter() - start),
                                    **pairs)
        if not np.isfinite(history[-1]) or (k >= 10 and history[-1] > 0.9 * history[-6]):
            break
    raise SolverError(f"fixed point on the friction bound did not converge: relative changes "
                      f"{', '.join(f'{h:.2e}' for h in history[-4:])} after {len(history)} iterations "
                      f"(not a contraction; use the coupled Newton, solver='newton')",
                      history=history, solver="fixed_point")
