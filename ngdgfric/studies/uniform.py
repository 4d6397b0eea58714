r"""Convergence on uniform meshes :math:`h = 2^{-k}` (Tables 6.1, 6.2): solutions, differences and rates.

The norms of the differences of consecutive solutions and the observed rates, as plain records.
"""

import math
import time

import ngsolve as ngs

from ..checks import check_size
from ..meshes import grid_counts, grid_mesh
from ..progress import log, reporter
from ..reference import energy_norm, energy_norm_squared_parts
from ..solution import solve
from ..transfer import interpolate
from .measures import rates

__all__ = ["uniform_study", "consecutive_differences", "difference_norms", "finest_elements"]


def difference_norms(coarse, fine):
    """Norms of u_coarse - u_fine on the finer mesh (coarse interpolated: exact for nested meshes).

    Returns a dict with ``energy`` (|||.|||_h of Section 3 on the fine mesh), its parts
    ``energy_volume`` and ``energy_jumps``, ``h1`` (broken H1 seminorm), ``l2``, and ``relative``
    (energy / |||u_fine|||_h).
    """
    w = ngs.GridFunction(fine.u.space)
    interpolate(w, coarse.u)
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


def finest_elements(problem, levels):
    """The triangles of the finest mesh of :func:`uniform_study` over ``levels`` (before meshing)."""
    return 2 * math.prod(grid_counts(problem, 2.0**-min(levels), int(max(levels) - min(levels))))


def uniform_study(problem, method="sipg", order=1, levels=(1, 2, 3, 4, 5, 6), solver="newton",
                  diagonal="sw-ne", eta=None, progress=log, **options):
    """Solve on uniform meshes h = 2^-k, k in ``levels``, and compare consecutive solutions.

    The meshes are :func:`~ngdgfric.meshes.grid_mesh` (2^-min(levels), k - min(levels)): squares of side 2^-k where
    2^-min(levels) divides the rectangle's sides (the paper's), else ceil(side 2^min(levels)) cells per side halved
    at every level, nested, of sides at most 2^-k (the rates take h = 2^-k).

    Returns (rows, solutions): one row per level but the last, with h, ndof, iterations,
    seconds, the norms of :func:`consecutive_differences` and the observed ``rate`` of the
    energy error.  ``progress``: callable(str) receiving one line per solved level (default
    :func:`ngdgfric.progress.log`: the logger "ngdgfric" at INFO, silent unless logging is configured; None: none).
    The finest mesh's size is checked before the first solve (:func:`ngdgfric.checks.check_size`, ``max_ndof`` in
    ``options``).
    """
    check_size(order, options.get("max_ndof"), elements=finest_elements(problem, levels))
    solutions, seconds, say = [], [], reporter(progress)
    for k in levels:
        h = 2.0**-k
        mesh = grid_mesh(problem, 2.0**-min(levels), int(k - min(levels)), diagonal=diagonal, max_elements=None)
        start = time.perf_counter()
        sol = solve(problem, mesh, method=method, order=order, eta=eta, solver=solver, **options)
        seconds.append(time.perf_counter() - start)
        solutions.append(sol)
        say(f"  h = 2^-{k}: {sol.ndof} dofs, {solver} {sol.iterations} iterations, {seconds[-1]:.2f} s")
    diffs = consecutive_differences(solutions)
    hs = [2.0**-k for k in levels]
    observed = rates([d["energy"] for d in diffs], hs[:-1])
    rows = []
    for k, h, sol, sec, diff, rate in zip(levels, hs, solutions, seconds, diffs, observed, strict=False):
        rows.append(dict(k=k, h=h, ndof=sol.ndof, iterations=sol.iterations, seconds=sec, rate=rate, **diff))
    return rows, solutions
