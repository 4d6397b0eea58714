"""Refinement strategies measured against a reference solution: accuracy against DOFs and time
(uniform meshes, the adaptive loop of Section 6, hp-adaptivity) as plain records."""

import time

from ..adaptivity import adapt
from ..dg.discretization import space
from ..dg.methods import get_method
from ..estimator import deprecated_weights, estimate
from ..meshes import uniform_mesh
from ..progress import log, reporter
from ..reference import energy_error
from ..solution import solve

__all__ = ["STRATEGIES", "strategy_run"]

STRATEGIES = ("uniform", "h", "hp")


def strategy_run(problem, strategy, method="sipg", order=1, solver="newton", reference=None, max_ndof=10**5,
                 max_levels=60, max_order=6, progress=log, keep=None, variant=None, weights=None, **options):
    """Records (ndof, eta_h, error, seconds, iterations per level) of one refinement strategy.

    ``strategy``: "uniform" (uniform meshes h = 2^-1, 2^-2, ... up to ``max_ndof`` DOFs of ``method``'s V_h;
    ``seconds`` is the cold solve on that mesh alone: a user who knows h solves once), "h" (the adaptive loop of
    Section 6 in degree ``order``) or "hp" (:func:`ngdgfric.adapt` with ``hp=True`` from ``order``
    up to ``max_order``, None: adapt's default); for both adaptive strategies ``seconds`` is the cumulative time of
    solve + estimate + mark + refine up to that level.  ``error``: |||u_ref - u_h|||_h against a
    :class:`ngdgfric.Reference` (None without one); its evaluation is not timed.  ``keep``: as in
    :func:`ngdgfric.adapt` (adaptive strategies); ``variant``: the estimator's (:func:`ngdgfric.estimate`);
    ``progress``: callable(str) receiving one line per level (default :func:`ngdgfric.progress.log`: the logger
    "ngdgfric" at INFO; None: none).  ``weights``: the old name of ``variant`` (DeprecationWarning).
    """
    variant = deprecated_weights(variant, weights, "strategy_run")
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
    records = []

    def measure(sol, est):
        return dict(ndof=sol.ndof, eta_h=est.eta_h, iterations=sol.iterations,
                    error=None if reference is None else energy_error(sol, reference))

    if strategy == "uniform":
        k = 1
        while len(records) < max_levels:
            mesh = uniform_mesh(problem, 2.0**-k)
            if space(problem, mesh, order, get_method(method)).ndof > max_ndof and records:
                break
            start = time.perf_counter()
            sol = solve(problem, mesh, method=method, order=order, solver=solver, **options)
            seconds = time.perf_counter() - start
            records.append(dict(level=k, seconds=seconds, **measure(sol, estimate(sol, variant))))
            _say(progress, strategy, records[-1])
            k += 1
        return records
    errors = {}

    def measure_and_keep(level, sol, est):
        errors[level] = measure(sol, est)
        if keep is not None:
            keep(level, sol, est)

    if "tol" not in options and "rtol" not in options:
        options["rtol"] = 0.0  # a study of the strategy: its budgets end it, not adapt's default accuracy
    levels = adapt(problem, method=method, order=order, solver=solver, max_levels=max_levels, max_ndof=max_ndof,
                   hp=strategy == "hp", max_order=max_order if strategy == "hp" else None, progress=progress,
                   keep=measure_and_keep, variant=variant, **options).levels
    elapsed = 0.0
    for record in levels:
        elapsed += record["solve_seconds"] + record["estimate_seconds"] + record["mark_refine_seconds"]
        records.append(dict(level=record["level"], seconds=elapsed, p_max=record["p_max"],
                            **errors[record["level"]]))
    return records


def _say(progress, strategy, record):
    error = "" if record["error"] is None else f", error {record['error']:.4e}"
    reporter(progress)(f"  {strategy} level {record['level']}: {record['ndof']} dofs, eta_h {record['eta_h']:.4e}"
                       f"{error}, {record['seconds']:.2f} s")
