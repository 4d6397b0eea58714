"""Convergence studies as plain functions returning records: uniform meshes (Tables 6.1, 6.2)
and refinement strategies measured against a reference solution (accuracy against DOFs and time)."""

import math
import time

import ngsolve as ngs

from .adaptivity import adapt
from .checks import check_size
from .estimator import estimate
from .meshes import estimated_elements, uniform_mesh
from .reference import energy_error, energy_norm, energy_norm_squared_parts
from .solution import solve

__all__ = ["uniform_study", "consecutive_differences", "difference_norms", "rates", "STRATEGIES", "strategy_run"]

STRATEGIES = ("uniform", "h", "hp")


def rates(errors, hs):
    """Observed orders log(e_k-1 / e_k) / log(h_k-1 / h_k) (None for the first entry)."""
    out = [None]
    for k in range(1, len(errors)):
        out.append(math.log(errors[k - 1] / errors[k]) / math.log(hs[k - 1] / hs[k]))
    return out


def difference_norms(coarse, fine):
    """Norms of u_coarse - u_fine on the finer mesh (coarse interpolated: exact for nested meshes).

    Returns a dict with ``energy`` (|||.|||_h of Section 3 on the fine mesh), its parts
    ``energy_volume`` and ``energy_jumps``, ``h1`` (broken H1 seminorm), ``l2``, and ``relative``
    (energy / |||u_fine|||_h).
    """
    w = ngs.GridFunction(fine.u.space)
    w.Set(coarse.u)
    w.vec.data -= fine.u.vec
    dx = ngs.dx(bonus_intorder=max(2 * w.space.globalorder + 2 - 5, 0))  # exact: degree 2 p + 2 (default 5)
    volume, jumps = energy_norm_squared_parts(fine.problem, fine.mesh, w)
    energy = math.sqrt(volume + jumps)
    return dict(
        energy=energy, energy_volume=math.sqrt(volume), energy_jumps=math.sqrt(jumps),
        h1=math.sqrt(ngs.Integrate(ngs.InnerProduct(ngs.Grad(w), ngs.Grad(w)) * dx, fine.mesh)),
        l2=math.sqrt(ngs.Integrate(w * w * dx, fine.mesh)),
        relative=energy / energy_norm(fine),
    )


def consecutive_differences(solutions):
    """:func:`difference_norms` of each pair of consecutive solutions (coarse, fine)."""
    return [difference_norms(c, f) for c, f in zip(solutions[:-1], solutions[1:], strict=True)]


def uniform_study(problem, method="sipg", order=1, levels=(1, 2, 3, 4, 5, 6), solver="newton",
                  diagonal="sw-ne", eta=None, warm_start=False, progress=None, **options):
    """Solve on uniform meshes h = 2^-k, k in ``levels``, and compare consecutive solutions.

    Returns (rows, solutions): one row per level but the last, with h, ndof, iterations,
    seconds, the norms of :func:`consecutive_differences` and the observed ``rate`` of the
    energy error.  ``progress``: callable(str) for one line per solved level.  The finest mesh's
    size is checked before the first solve (:func:`ngdgfric.checks.check_size`, ``max_ndof`` in
    ``options``).
    """
    check_size(order, options.get("max_ndof"), elements=estimated_elements(problem, h=2.0**-max(levels)))
    solutions, seconds = [], []
    for k in levels:
        h = 2.0**-k
        mesh = uniform_mesh(problem, h, diagonal=diagonal, max_elements=None)
        start = time.perf_counter()
        initial = solutions[-1] if (warm_start and solutions) else None
        sol = solve(problem, mesh, method=method, order=order, eta=eta, solver=solver, initial=initial, **options)
        seconds.append(time.perf_counter() - start)
        solutions.append(sol)
        if progress is not None:
            progress(f"  h = 2^-{k}: {sol.ndof} dofs, {solver} {sol.iterations} iterations, {seconds[-1]:.2f} s")
    diffs = consecutive_differences(solutions)
    hs = [2.0**-k for k in levels]
    observed = rates([d["energy"] for d in diffs], hs[:-1])
    rows = []
    for k, h, sol, sec, diff, rate in zip(levels, hs, solutions, seconds, diffs, observed, strict=False):
        rows.append(dict(k=k, h=h, ndof=sol.ndof, iterations=sol.iterations, seconds=sec, rate=rate, **diff))
    return rows, solutions


def strategy_run(problem, strategy, method="sipg", order=1, solver="newton", reference=None, max_ndof=10**5,
                 max_levels=60, tol=None, max_order=6, progress=None, keep=None, weights="energy", **options):
    """Records (ndof, eta, error, seconds, iterations per level) of one refinement strategy.

    ``strategy``: "uniform" (uniform meshes h = 2^-1, 2^-2, ... up to ``max_ndof``; ``seconds`` is
    the cold solve on that mesh alone: a user who knows h solves once), "h" (the adaptive loop of
    Section 6 in degree ``order``) or "hp" (:func:`ngdgfric.adapt` with ``hp=True`` from ``order``
    up to ``max_order``); for both adaptive strategies ``seconds`` is the cumulative time of
    solve + estimate + mark + refine up to that level.  ``error``: |||u_ref - u_h|||_h against a
    :class:`ngdgfric.Reference` (None without one); its evaluation is not timed.  ``keep``: as in
    :func:`ngdgfric.adapt` (adaptive strategies); ``weights``: the estimator's (:func:`ngdgfric.estimate`).
    """
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
    records = []

    def measure(sol, est):
        return dict(ndof=sol.ndof, eta=est.total, iterations=sol.iterations,
                    error=None if reference is None else energy_error(sol, reference))

    if strategy == "uniform":
        k = 1
        while len(records) < max_levels:
            mesh = uniform_mesh(problem, 2.0**-k)
            if mesh.ne * (order + 1) * (order + 2) > max_ndof and records:
                break
            start = time.perf_counter()
            sol = solve(problem, mesh, method=method, order=order, solver=solver, **options)
            seconds = time.perf_counter() - start
            records.append(dict(level=k, seconds=seconds, **measure(sol, estimate(sol, weights))))
            _say(progress, strategy, records[-1])
            if tol is not None and records[-1]["eta"] <= tol:
                break
            k += 1
        return records
    errors = {}

    def measure_and_keep(level, sol, est):
        errors[level] = measure(sol, est)
        if keep is not None:
            keep(level, sol, est)

    levels = adapt(problem, method=method, order=order, solver=solver, max_levels=max_levels, max_ndof=max_ndof,
                   tol=tol, hp=strategy == "hp", max_order=max_order, progress=progress, keep=measure_and_keep,
                   weights=weights, **options).levels
    elapsed = 0.0
    for record in levels:
        elapsed += record["solve_seconds"] + record["estimate_seconds"] + record["mark_refine_seconds"]
        records.append(dict(level=record["level"], seconds=elapsed, p_max=record["p_max"],
                            **errors[record["level"]]))
    return records


def _say(progress, strategy, record):
    if progress is not None:
        error = "" if record["error"] is None else f", error {record['error']:.4e}"
        progress(f"  {strategy} level {record['level']}: {record['ndof']} dofs, eta_h {record['eta']:.4e}{error}, "
                 f"{record['seconds']:.2f} s")
