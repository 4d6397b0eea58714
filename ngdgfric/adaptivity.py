"""SOLVE -> ESTIMATE -> MARK -> REFINE (Section 6): Doerfler marking, then h refinement by
bisection (:func:`ngdgfric.meshes.refine`) or the hp decision (:func:`ngdgfric.hp.hp_refine`); one level at a
time by :class:`ngdgfric.levels.AdaptiveLoop`.

Choice of the defaults of :func:`adapt` (issue 28: time to an answer): the conforming baseline where nu is
moderate (:func:`choose_method`), hp from p = 4 up to 8, theta = 0.8 and one geometric layer (``layers=1``):
a marked element that the hp decision bisects and that contains a singular point (a corner of the domain, an end
of the contact or the stick zone) is bisected twice more towards it in the same step.  Before, the levels were
paced by the grading towards the singular points: h_min halved on every level (5.3e-9 at level 27 on Example 6.1)
and eta_h fell by about 0.67 per level whatever else was refined, with DOFs growing ~1.1 per level (28 levels to
tol = 5e-4, about 10 linear solves of the final mesh).  With the layer h_min falls by 4 per level and theta = 0.8
lets the DOFs grow ~1.3 per level: 11-12 levels to true errors of 1e-4 on both examples (results/time_to_accuracy.md).
Exploratory runs (a loaded machine, not kept), to 1e-3 on Example 6.2 without the graded first mesh: p = 4, theta =
0.8, one layer 1.8-1.9 s; from p = 3 2.1-2.4 s; two layers 2.4-2.8 s (they grade faster than the p around can
follow); theta = 0.9-0.95 2.3-2.5 s; theta = 0.5 with two layers 3.1 s; no layers, theta = 0.8, 3.1 s.  The paper's loop
(``method="sipg", hp=False, order=1, theta=0.3, variant="paper"``) is unchanged: layers act in hp refinement only.
Earlier attempts at faster growth without the layers (Doerfler's set extended to a DOF growth of 1.3, marked h
elements bisected four times everywhere, a second Doerfler round on predicted indicators, p raised by 2) gave
more DOFs for the same accuracy or the same number of levels.

``gamma_lin`` is not the default: on Example 6.1 gamma_lin = 0.1 left 0-3 Newton iterations per
level, but the contact indicators eta_4, eta_6 of the inexact solutions steered the hp decisions
into bisecting Gamma_C (to tol = 1e-2: 91,760 DOFs and 54 s instead of 20,158 DOFs and 4.2 s,
results/time_to_accuracy.md), and gamma_lin = 0.01 kept the path but not the iterations.
"""

import functools
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .checks import MEMORY_BUDGET
from .dg.material import largest
from .dg.methods import get_method
from .estimator import KINDS, VARIANTS, deprecated_weights, estimate
from .files import check_writable, write_csv
from .hp import containing
from .levels import FIELDS, AdaptiveLoop, frozen_older_objects, record, timed
from .marking import dorfler_mark
from .meshes import grid_mesh, minimum_angle, netgen_mesh, refine
from .progress import log, reporter
from .threads import limited_blas

__all__ = ["dorfler_mark", "adapt", "Adaptation", "minimum_angle", "choose_method", "initial_mesh", "level_line",
           "FIELDS", "MAX_ORDER", "LAYERS", "INITIAL_LAYERS"]

MAX_ORDER = 8
"""The largest degree of hp-adaptivity unless :func:`adapt` is given ``max_order``.

Measured against lower caps (issue 38, 2026-12, with the PARDISO Cholesky path since reverted: CPU seconds of the
loop, one MKL thread, to the first level with a true error at or below 1e-2, 1e-3, 3e-4, 1.5e-4 on Examples 6.1 and
6.2, sipg and cg): max_order 7 and 8 take the same path down to the references' accuracy, and no lower cap is
faster throughout: to 1.5e-4 cap 4, 5, 6, 7, 8 took 9.1, 9.5, 8.4, 7.9, 7.8 s (sipg, 6.2), 9.8, 11.2, 11.0, 10.7,
11.0 s (sipg, 6.1), 4.2, 3.9, 3.4, 3.4, 3.3 s (cg, 6.2); cap 4 was 11-14 % faster on two of the eight sipg (example,
target) pairs and up to 1.25 times (sipg) and 1.9 times (cg) slower elsewhere."""
LAYERS = 1
"""The geometric layers per hp step unless :func:`adapt` is given ``layers`` (why: module docstring)."""
INITIAL_LAYERS = 2
"""Geometric layers towards the corners of the domain in :func:`initial_mesh` for hp-adaptivity."""


@dataclass
class Adaptation:
    """What :func:`adapt` returns.

    ``levels``: one record (dict with the keys of ``FIELDS``) per solved level; ``solution``: the
    :class:`~ngdgfric.solution.Solution` of the last level (its mesh is the final mesh, not refined
    after it); ``estimate``: its :class:`~ngdgfric.estimator.Estimate`; ``stopped``: why the loop
    ended ("tol", "max_levels", "max_ndof", "memory" or "max_seconds"); ``method``: the DG method used
    and ``method_reason`` why (:func:`choose_method` when none was given).
    """

    levels: list
    solution: object
    estimate: object
    stopped: str
    method: str = "sipg"
    method_reason: str = "given"


def choose_method(problem, mesh, order):
    """(method, reason): the discretisation :func:`adapt` uses when none is given, by where each method locks
    (:data:`ngdgfric.dg.methods.LOCKING`, results/locking.md; the data :class:`~ngdgfric.Discretization` warns with,
    so that adapt never warns about its own choice).  The conforming baseline ``cg`` (about half the DOFs of a DG
    method on the same mesh and orders, no skeleton terms, and the same contact solver, estimator and hp loop:
    results/time_to_accuracy.md) where it locks at no degree: below nu = 0.49, from where its error grows more than
    twice at p = 1-3.  At p = 4 its displacement does not lock (x1.84 at nu = 0.49999), but its stresses are worse: the
    estimator's effectivity (which sees them) rises from 2.0 at nu = 0.3 to 4.9 at nu = 0.49 and 6.6 at 0.4999 (Bassi
    et al.: 2.1-2.5), so adapt would stop far below tol (an exploratory run, not kept, to 1e-3 |||u||| on the
    divergence-free scene at nu = 0.4999: true error 0.05 tol, effectivity 18 on the hp meshes).  From nu = 0.49 the
    first of Bassi et al. (symmetric, error growth at most x1.08 up to nu = 0.49999) and Brezzi et al. (as robust at
    1.3-1.5 times Bassi's assembly cost) that does not lock at ``order``."""
    nu = largest(problem.on(mesh).nu, mesh)
    cg = get_method("cg")
    if not cg.locks(nu):
        return "cg", (f"nu = {nu:.6g} is moderate: the conforming baseline, half the DOFs of a DG method on the same "
                      f"mesh, is the cheapest adequate discretisation")
    name = next((name for name in ("bassi", "brezzi") if not get_method(name).locks(nu, order)), "brezzi")
    return name, (f"nu reaches {nu:.6g}: conforming elements lock from nu = {min(e.nu for e in cg.locking if e):g} "
                  f"(results/locking.md); the DG method {name!r} does not")


@limited_blas
def adapt(problem, mesh=None, method=None, order=4, theta=0.8, max_levels=100, max_ndof=10**6, tol=None,
          solver="newton", eta=None, csv_path=None, progress=log, keep=None, hp=True, max_order=None,
          variant=None, gamma_lin=None, solver_tol=None, max_seconds=None, rtol=None, layers=None,
          estimator="residual", max_bytes=MEMORY_BUDGET, weights=None, **options):
    """The adaptive loop of Section 6 (SOLVE -> ESTIMATE -> MARK -> REFINE); returns an :class:`Adaptation`.

    Stops as soon as eta_h <= ``tol`` or eta_h <= ``rtol`` |||u_h|||_h (:func:`ngdgfric.energy_norm`; the level's
    target is in the CSV as ``target``), after ``max_levels`` solves, when the next refined mesh would exceed
    ``max_ndof`` DOFs or ``max_bytes`` bytes of memory (the model of :func:`ngdgfric.checks.check_size`; default
    :data:`~ngdgfric.checks.MEMORY_BUDGET`, 8 GB; tried on a copy of the mesh, so the returned solution's mesh is never
    refined after its solve), or when the next level would end after ``max_seconds`` (the last level's time times its
    growth in DOFs; the first level always runs).  The command line's ``adaptive`` takes its defaults from here.

    Defaults (module docstring): ``hp`` from p = ``order`` = 4 up to ``max_order`` (None: :data:`MAX_ORDER` = 8),
    Doerfler ``theta`` = 0.8, ``layers`` geometric layers towards the singular points per hp step (None:
    :data:`LAYERS` = 1; :func:`ngdgfric.hp.hp_refine`); ``method`` None: :func:`choose_method`, reported.  The
    paper's loop is ``method="sipg", hp=False, order=1, theta=0.3, variant="paper"``.  ``max_order`` and ``layers``
    act in hp refinement only: given with ``hp=False`` they are refused (ValueError).
    ``eta``, ``solver``, ``solver_tol`` (the solver's tolerance) and further ``options`` go to :func:`ngdgfric.solve`.

    ``estimator``: "residual" (default; :func:`ngdgfric.estimate` with its ``variant``, None: "energy", so that eta_h
    estimates |||u - u_h|||_h and ``rtol=1e-3`` asks for 0.1 % of it; "paper": Section 4 as printed) or
    "equilibrated" (the guaranteed bound of :mod:`ngdgfric.equilibration`, which has no variants: ``variant`` is
    then refused); marking uses the estimator's indicators.  ``weights``: the old name of ``variant``
    (DeprecationWarning).

    ``gamma_lin`` (``solver="newton"`` only; refused with another solver, which has no inexact solves): solve every
    level but the returned one inexactly, until the linearisation estimate eta_lin <= ``gamma_lin`` eta_h (Ern &
    Vohralik, SISC 35, 2013; :mod:`ngdgfric.solvers.newton`), starting from gamma_lin x the previous level's eta_h.

    ``mesh``: the first mesh (default :func:`initial_mesh`), refined in place; every level after the first starts from
    the previous solution.  ``progress``: callable(str) receiving one line per level; the default
    :func:`ngdgfric.progress.log` sends them to the logger ``"ngdgfric"`` at INFO (silent unless logging is
    configured); None: no lines.  ``csv_path``: the CSV of the
    finished levels, rewritten atomically after every level (an interrupted run keeps them).  ``keep``:
    callable(level, solution, estimate) called at every level, e.g. to save a picture.
    """
    variant = deprecated_weights(variant, weights, "adapt")
    _check_arguments(order, max_order, hp, max_levels, max_ndof, (tol, rtol), gamma_lin, max_seconds, layers,
                     max_bytes)
    _check_applicable(solver, estimator, variant, gamma_lin, hp, max_order, layers)
    start, say = time.perf_counter(), reporter(progress)
    max_order, layers = (MAX_ORDER if max_order is None else max_order, LAYERS if layers is None else layers) \
        if hp else (None, 0)
    mesh = initial_mesh(problem, INITIAL_LAYERS if hp and layers else 0) if mesh is None else mesh
    if csv_path is not None:
        csv_path = Path(csv_path)
        check_writable(csv_path.parent)
    method, reason = choose_method(problem, mesh, order) if method is None else (get_method(method).name, "given")
    say(f"method {method}: {reason}")
    loop = AdaptiveLoop(problem, mesh, order, max_order, functools.partial(estimate, variant=variant, kind=estimator),
                        (tol, rtol), layers, gamma_lin,
                        dict(method=method, eta=eta, solver=solver, solver_tol=solver_tol, max_bytes=max_bytes,
                             **options))
    limits = dict(theta=theta, max_levels=max_levels, max_ndof=max_ndof, max_bytes=max_bytes,
                  max_seconds=max_seconds, start=start)
    stopped, records, sol, est = _levels(loop, limits, keep, csv_path, functools.partial(_say_level, say, solver))
    return Adaptation(records, sol, est, stopped, method, reason)


def _levels(loop, limits, keep, csv_path, show):
    """Run the levels of ``loop`` until it stops; returns (why, the records, the last solution and estimate).
    Every finished level is written to ``csv_path`` (:func:`write_levels`) and shown (``show(record)``)."""
    records = []
    with frozen_older_objects():
        for level in range(limits["max_levels"]):
            sol, est, seconds = loop.solve(level == limits["max_levels"] - 1)
            sol, est, stopped, refinement = loop.decide(level, sol, est, seconds, records, limits)
            records.append(record(level, sol, est, loop.state, seconds, loop.tol))
            if keep is not None:
                keep(level, sol, est)
            if stopped is None:
                sol = est = None
                timed(records[-1], "mark_refine_seconds", loop.refine, refinement)
            write_levels(csv_path, records)
            show(records[-1])
            if stopped is not None:
                return stopped, records, sol, est
    raise AssertionError("the last level always stops")  # pragma: no cover


def initial_mesh(problem, layers=0):
    """The first mesh of :func:`adapt`: on a rectangle cells of sides at most min(1/2, half its longest side)
    (:func:`~ngdgfric.meshes.grid_mesh`: uniform h = 1/2 on the paper's examples), else Netgen with maxh = min(1/2,
    a quarter of the domain's diameter, its longest extent); then ``layers`` geometric layers towards the domain's
    corners (the elements containing one bisected twice, ``layers`` times), where the solution is singular whatever
    the data: hp-adaptive runs start with ``INITIAL_LAYERS`` (exploratory runs, not kept: on Examples 6.1 and 6.2
    the true errors 1e-1 ... 1e-4 are reached in 35-65 % less time, 1e-1 one level sooner)."""
    size = problem.geometry.diameter()
    if problem.geometry.is_rectangle:
        mesh = grid_mesh(problem, min(0.5, size / 2))
    else:
        mesh = netgen_mesh(problem, min(0.5, size / 4))
    for _ in range(layers):
        refine(mesh, containing(mesh, problem.geometry.corners), bisections=2)
    return mesh


def _check_arguments(order, max_order, hp, max_levels, max_ndof, tolerances, gamma_lin, max_seconds, layers,
                     max_bytes):
    """ValueError naming the first argument of :func:`adapt` out of its range."""
    largest = MAX_ORDER if max_order is None else max_order
    if hp and not (isinstance(largest, int) and largest >= order):
        raise ValueError(f"max_order must be an integer >= order = {order}, got {max_order!r}"
                         f"{f' (the default {MAX_ORDER})' if max_order is None else ''}")
    if not (layers is None or (isinstance(layers, (int, np.integer)) and not isinstance(layers, bool) and layers >= 0)):
        raise ValueError(f"layers must be an integer >= 0, got {layers!r}")
    for name, value in (("max_levels", max_levels), ("max_ndof", max_ndof)):
        if not (isinstance(value, (int, np.integer)) and value >= 1):
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    for name, value in (("tol", tolerances[0]), ("rtol", tolerances[1]), ("max_seconds", max_seconds)):
        if value is not None and not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive number or None, got {value!r}")
    if not (isinstance(max_bytes, (int, float)) and math.isfinite(max_bytes) and max_bytes > 0):
        raise ValueError(f"max_bytes must be a positive number of bytes, got {max_bytes!r}")
    if gamma_lin is not None and not (isinstance(gamma_lin, (int, float)) and 0 < gamma_lin < 1):
        raise ValueError(f"gamma_lin must be a number in (0, 1) or None, got {gamma_lin!r}")


def _check_applicable(solver, estimator, variant, gamma_lin, hp, max_order, layers):
    """ValueError for an option of :func:`adapt` that the chosen solver, estimator or refinement would ignore."""
    if estimator not in KINDS:
        raise ValueError(f"estimator must be one of {KINDS}, got {estimator!r}")
    if variant is not None and variant not in VARIANTS:
        raise ValueError(f"variant must be one of {VARIANTS}, got {variant!r}")
    if variant is not None and estimator != "residual":
        raise ValueError(f"variant={variant!r} selects a variant of the residual estimator; estimator={estimator!r} "
                         f"has none and would ignore it")
    if gamma_lin is not None and solver != "newton":
        raise ValueError(f"gamma_lin={gamma_lin!r} needs solver='newton' (inexact Newton solves); solver={solver!r} "
                         f"would ignore it")
    for name, value in (("max_order", max_order), ("layers", layers)):
        if value is not None and not hp:
            raise ValueError(f"{name}={value!r} acts in hp refinement only; hp=False would ignore it")


def write_levels(csv_path, records):
    """The CSV of the levels so far (columns :data:`FIELDS`), written atomically; nothing for ``csv_path`` None."""
    if csv_path is not None:
        write_csv(csv_path, records, FIELDS)


def level_line(level_record, solver):
    """The progress line of a level: DOFs, orders, eta_h, iterations and times."""
    r = level_record
    orders = f"p {r['p_min']}..{r['p_max']}, " if r["p_max"] > r["p_min"] else ""
    return (f"level {r['level']:3d}: {r['ndof']:7d} dofs, {orders}eta_h = {r['eta_h']:.4e}, {solver} "
            f"{r['iterations']} iterations, {r['solve_seconds']:.2f} s solve ({r['assemble_seconds']:.2f} s of it "
            f"assembly), {r['estimate_seconds'] + r['mark_refine_seconds']:.2f} s estimate+refine")


def _say_level(say, solver, level_record):
    say(level_line(level_record, solver))
