"""The fixed point on the friction bound for the quasi-variational inequality (1.4), m_t > 0.

    u^{k+1}: the solution of (3.3)-(3.4) with the bound c_tau (u^k_n - g_a)_+^{m_t} frozen,

i.e. of a reduced-law problem (m_t = 0) with a spatially varying friction bound
(:meth:`ngdgfric.Discretization.frozen_bound`), solved by the inner solver warm-started from
(u^k, l^k); stopped when ||u^{k+1} - u^k||_inf <= tol ||u^{k+1}||_inf.  It starts from u^0 = 0
(bound 0 where g_a > 0: the frictionless problem) or from ``initial``.

The map u^k -> u^{k+1} is a contraction only if the bound varies slowly with u_n compared with
the stiffness of the body: its Lipschitz constant grows like the slope c_tau m_t
(u_n - g_a)_+^{m_t - 1} of the bound (on Example 6.1, m_t = 1, h = 1/16: contraction factor
about 0.25 c_tau / 450; it stalled at c_tau = 1800 and 3600, results/mt.md).  For large c_tau
the iteration stalls, or a warm-started inner solve cycles because the frozen bound jumps
between outer iterations; the coupled semismooth Newton (:func:`ngdgfric.newton.newton`)
converged in all these cases.  For m_t = 0 the bound does not depend on u and one inner solve
is the answer.
"""

import time

import ngsolve as ngs
import numpy as np

from .contact import frozen_bound
from .errors import SolverError
from .newton import OPTIONS as NEWTON_OPTIONS
from .newton import newton
from .nonlinear import relative_change
from .options import callback, choice, positive_integer, positive_number, validate
from .uzawa import OPTIONS as UZAWA_OPTIONS
from .uzawa import uzawa

__all__ = ["fixed_point", "INNER", "OPTIONS"]

INNER = {"newton": (newton, NEWTON_OPTIONS), "uzawa": (uzawa, UZAWA_OPTIONS)}
OUTER = ("tol", "maxit", "progress")
OPTIONS = {**{name: check for spec in (NEWTON_OPTIONS, UZAWA_OPTIONS) for name, check in spec.items()},
           **dict(tol=positive_number, maxit=positive_integer, progress=callback, inner=choice(*INNER))}


def fixed_point(disc, tol=1e-8, maxit=100, initial=None, inner="newton", progress=None, **options):
    """The fixed point of the module docstring; returns (u, lam, info).

    tol: relative max-norm tolerance of the outer iteration, also passed to the inner solver.
    maxit: outer iterations; ``inner``: "newton" or "uzawa", with ``options`` passed to it.
    initial: optional (u, lam) GridFunctions on ``disc.V``, ``disc.Q`` to start from.
    progress: callable(iteration, change) called after each outer iteration, or None.
    info: ``iterations`` (outer), ``history`` (relative changes), ``inner_iterations`` (per outer
    iteration), ``factorizations`` (summed over the inner solves), ``timings``.
    Raises :class:`SolverError` (with the history) if it diverges or does not converge in maxit.
    """
    validate(OPTIONS, "fixed_point", tol=tol, maxit=maxit, progress=progress, inner=inner, **options)
    inner_solver, inner_options = INNER[inner]
    validate({name: check for name, check in inner_options.items() if name not in OUTER},
             f"fixed_point with inner={inner!r}", **options)
    start = time.perf_counter()
    u, lam = ngs.GridFunction(disc.V), ngs.GridFunction(disc.Q)
    if initial is not None:
        u.vec.data, lam.vec.data = initial[0].vec, initial[1].vec
    du = u.vec.CreateVector()
    history, inner_iterations, factorizations = [], [], 0
    for k in range(1, maxit + 1):
        try:
            u_new, lam_new, info = inner_solver(disc, tol=tol, initial=(u, lam), problem=frozen_bound(disc.problem, u),
                                                **options)
        except SolverError as error:
            raise SolverError(f"fixed point: the inner {inner} solve {k} failed: {error}", history=history,
                              solver="fixed_point") from error
        inner_iterations.append(info["iterations"])
        factorizations += info.get("factorizations", 0)
        du.data = u_new.vec - u.vec
        u.vec.data, lam.vec.data = u_new.vec, lam_new.vec
        history.append(relative_change(du, u.vec))
        if progress is not None:
            progress(k, history[-1])
        if history[-1] <= tol or disc.problem.m_t == 0:
            return u, lam, dict(iterations=k, history=history, inner_iterations=inner_iterations,
                                factorizations=factorizations, timings=dict(total=time.perf_counter() - start))
        if not np.isfinite(history[-1]) or (k >= 10 and history[-1] > 0.9 * history[-6]):
            break
    raise SolverError(f"fixed point on the friction bound did not converge: relative changes "
                      f"{', '.join(f'{h:.2e}' for h in history[-4:])} after {len(history)} iterations "
                      f"(not a contraction; use the coupled Newton, solver='newton')",
                      history=history, solver="fixed_point")
