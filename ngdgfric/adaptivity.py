"""SOLVE -> ESTIMATE -> MARK -> REFINE (Section 6): Doerfler marking, then h refinement by
bisection (:func:`ngdgfric.meshes.refine`) or the hp decision (:func:`ngdgfric.hp.hp_refine`).

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
(``method="sipg", hp=False, order=1, theta=0.3, weights="paper"``) is unchanged: layers act in hp refinement only.
Earlier attempts at faster growth without the layers (Doerfler's set extended to a DOF growth of 1.3, marked h
elements bisected four times everywhere, a second Doerfler round on predicted indicators, p raised by 2) gave
more DOFs for the same accuracy or the same number of levels.

``gamma_lin`` is not the default: on Example 6.1 gamma_lin = 0.1 left 0-3 Newton iterations per
level, but the contact indicators eta_4, eta_6 of the inexact solutions steered the hp decisions
into bisecting Gamma_C (to tol = 1e-2: 91,760 DOFs and 54 s instead of 20,158 DOFs and 4.2 s,
results/time_to_accuracy.md), and gamma_lin = 0.01 kept the path but not the iterations.
"""

import contextlib
import dataclasses
import functools
import gc
import math
import time
from dataclasses import dataclass
from pathlib import Path

import ngsolve as ngs
import numpy as np

from .checks import MEMORY_BUDGET, estimated_bytes
from .contact import transitions
from .dg.methods import get_method
from .estimator import KINDS, WEIGHTS, estimate
from .files import check_writable, write_csv
from .hp import HPState, containing, hp_refine
from .meshes import element_diameters, netgen_mesh, refine, smallest_angles, uniform_mesh
from .reference import energy_norm
from .solution import finish, solve
from .threads import limited_blas
from .transfer import WarmStart, copy_orders, discontinuous, multiplier_snapshot

__all__ = ["dorfler_mark", "adapt", "Adaptation", "minimum_angle", "choose_method"]


def dorfler_mark(element_indicators, theta=0.3):
    """The smallest set M with sum_M eta_T^2 >= theta sum_T eta_T^2 (boolean mask).

    ``element_indicators``: the squared indicators eta_T^2.  Largest indicators are taken first;
    ties at the threshold are broken by element number.
    """
    if not (isinstance(theta, (int, float)) and 0 < theta <= 1):
        raise ValueError(f"theta must be in (0, 1], got {theta!r}")
    values = np.asarray(element_indicators, dtype=float)
    if values.ndim != 1 or np.any(values < 0) or not np.all(np.isfinite(values)):
        raise ValueError("element indicators must be a 1-d array of finite nonnegative numbers")
    marked = np.zeros(values.size, dtype=bool)
    total = values.sum()
    if total == 0:
        return marked
    order = np.argsort(-values, kind="stable")
    cumulative = np.cumsum(values[order])
    count = int(np.searchsorted(cumulative, theta * total * (1 - 1e-14))) + 1
    marked[order[:min(count, values.size)]] = True
    return marked


def minimum_angle(mesh):
    """The smallest interior angle of the mesh's triangles, in degrees."""
    return float(np.degrees(smallest_angles(mesh).min()))


FIELDS = ["level", "ndof", "elements", "eta_h", "eta1", "eta2", "eta3", "eta4", "eta5", "eta6", "eta_lin",
          "iterations", "solve_seconds", "estimate_seconds", "mark_refine_seconds", "h_min", "min_angle",
          "p_min", "p_max"]


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
    """(method, reason): the discretisation :func:`adapt` uses when none is given.  The conforming baseline ``cg``
    (about half the DOFs of a DG method on the same mesh and orders, no skeleton terms, and the same contact solver,
    estimator and hp loop: results/time_to_accuracy.md) unless nu is close to 1/2: where SIPG's coercivity
    threshold t_p (2 mu + lam) at degree ``order`` reaches its default penalty 30 mu somewhere (t_1 (2 mu + lam) >=
    30 mu from nu = 0.42, t_2 from nu = 0.46) conforming elements of low degree lock like SIPG with its raised
    penalty (results/effectivity.md: errors 1.75 times the best method's at nu = 0.49, 6 times at 0.4999); then
    Bassi et al., which does not lock there (error growth x1.0-1.1 from nu = 0.3 to 0.4999 in both regimes of
    results/stability.md and effectivity.md) and is symmetric (Brezzi et al. is as robust at 1.3-1.5 times Bassi's
    assembly cost)."""
    nu = _largest(problem.on(mesh).nu, mesh)
    law, sipg = dataclasses.replace(problem, E=1.0, nu=nu), get_method("sipg")  # the thresholds scale with E
    if sipg.default(law, order) == sipg.default_eta * sipg.eta_scale(law):  # not raised
        return "cg", (f"nu = {nu:.6g} is moderate: the conforming baseline, half the DOFs of a DG method on the same "
                      f"mesh, is the cheapest adequate discretisation")
    return "bassi", (f"nu reaches {nu:.6g}: conforming elements of low degree lock, and so does SIPG, whose penalty "
                     f"would be raised above 30 mu to stay coercive; Bassi et al. does not")


def _largest(datum, mesh):
    """The largest value of a scalar datum (a number, or a CoefficientFunction at the mesh's Gauss points)."""
    if not isinstance(datum, ngs.CoefficientFunction):
        return float(datum)
    rule = ngs.IntegrationRule(ngs.TRIG, 4)
    return float(np.max(np.asarray(datum(mesh.MapToAllElements({ngs.TRIG: rule}, ngs.VOL)))))


@limited_blas
def adapt(problem, mesh=None, method=None, order=4, theta=0.8, max_levels=100, max_ndof=10**6, tol=None,
          solver="newton", eta=None, csv_path=None, progress=print, keep=None, hp=True, max_order=8,
          weights="energy", gamma_lin=None, solver_tol=None, max_seconds=None, rtol=None, layers=1,
          estimator="residual", **options):
    """The adaptive loop of Section 6 (SOLVE -> ESTIMATE -> MARK -> REFINE); returns an :class:`Adaptation`.

    Stops as soon as eta_h <= ``tol`` or eta_h <= ``rtol`` |||u_h|||_h (a relative tolerance: with the default
    ``weights="energy"`` eta_h estimates the energy error |||u - u_h|||_h, :func:`ngdgfric.estimate`, so
    ``rtol=1e-3`` asks for 0.1 % of the solution's energy norm, :func:`ngdgfric.energy_norm`; the level's
    target is in the CSV as ``target``), after ``max_levels`` solves, or when
    the next refined mesh would exceed ``max_ndof`` degrees of freedom or the memory budget of
    :func:`ngdgfric.checks.check_size` (tried on a copy of the mesh, so the returned solution's mesh
    is never refined after its solve), or when the next level would end after ``max_seconds`` (its time
    predicted as the last level's times its growth in DOFs; the first level always runs).  Defaults:
    hp-adaptive from p = ``order`` = 4 up to ``max_order`` = 8, Doerfler theta = 0.8, ``layers`` = 1 geometric
    layer towards the singular points in each hp step (:func:`ngdgfric.hp.hp_refine`; why: module docstring),
    ``method`` chosen by :func:`choose_method` (the conforming baseline ``cg``, or Bassi et al. for nearly
    incompressible material) and reported; the paper's loop is
    ``method="sipg", hp=False, order=1, theta=0.3, weights="paper"``.  ``eta``, ``solver``, ``solver_tol``
    (the solver's tolerance) and further options go to :func:`ngdgfric.solve`.  The command line's
    ``adaptive`` takes its defaults from this signature.

    ``estimator``: "residual" (default, :func:`ngdgfric.estimate`) or "equilibrated" (the guaranteed upper bound
    of :mod:`ngdgfric.equilibration`: stopping at eta_h <= tol then certifies |||u - u_h|||_h <= tol where its
    assumptions hold, ``Estimate.guaranteed``); marking uses the chosen estimator's indicators.

    ``gamma_lin`` (Newton solver only): solve every level but the returned one inexactly, until the
    linearisation estimate eta_lin is at most ``gamma_lin`` times eta_h (adaptive inexact Newton:
    Ern & Vohralik, SISC 35, 2013; :mod:`ngdgfric.solvers.newton`), starting from eta_lin <= gamma_lin x the
    previous level's eta_h; the returned level is solved to the full tolerance.

    mesh: initial mesh (default: :func:`initial_mesh`, uniform h = 1/2 on a rectangle, Netgen maxh = 1/2
    otherwise, graded towards the corners for hp); it is refined in place.  Every level after the first starts
    from the previous solution transferred to the refined mesh.  ``progress``: callable receiving one line per
    level (None for silence); ``csv_path``: the CSV of the finished levels is rewritten (atomically) after every
    level, so an interrupted run keeps every finished level and an earlier file is replaced only
    once the first level is done.  ``keep``: callable(level, solution, estimate) called at every
    level, e.g. to save a picture.
    """
    _check_arguments(order, max_order, hp, weights, max_levels, max_ndof, (tol, rtol), gamma_lin, max_seconds)
    if estimator not in KINDS:
        raise ValueError(f"estimator must be one of {KINDS}, got {estimator!r}")
    if not (isinstance(layers, (int, np.integer)) and not isinstance(layers, bool) and layers >= 0):
        raise ValueError(f"layers must be an integer >= 0, got {layers!r}")
    start = time.perf_counter()
    if mesh is None:
        mesh = initial_mesh(problem, INITIAL_LAYERS if hp and layers else 0)
    if csv_path is not None:
        csv_path = Path(csv_path)
        check_writable(csv_path.parent)
    method, reason = choose_method(problem, mesh, order) if method is None else (get_method(method).name, "given")
    if progress is not None:
        progress(f"method {method}: {reason}")
    estimator = functools.partial(estimate, weights=weights, kind=estimator)
    loop = _Loop(problem, mesh, order, max_order if hp else None, estimator, (tol, rtol), layers,
                 gamma_lin if solver == "newton" else None,
                 dict(method=method, eta=eta, solver=solver, solver_tol=solver_tol, **options))
    limits, records = dict(theta=theta, max_levels=max_levels, max_ndof=max_ndof, max_seconds=max_seconds,
                           start=start), []
    with _older_objects_frozen():
        for level in range(max_levels):
            sol, est, seconds = loop.solve(level == max_levels - 1)
            sol, est, stopped, refinement = loop.decide(level, sol, est, seconds, records, limits)
            records.append(_record(level, sol, est, loop.state, seconds, loop.tol))
            if keep is not None:
                keep(level, sol, est)
            if stopped is None:
                sol = est = None
                _timed(records[-1], "mark_refine_seconds", loop.refine, refinement)
            _report(records, csv_path, progress, solver)
            if stopped is not None:
                return Adaptation(records, sol, est, stopped, method, reason)


@contextlib.contextmanager
def _older_objects_frozen():
    """The objects alive on entry moved out of the garbage collector's view until exit (``gc.freeze``): the full
    collection of every level (:meth:`_Loop.refine`) then scans only what the loop made, 17 ms -> about 1 ms."""
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


LANDING = 0.7
"""The fraction of the tolerance :func:`landing_theta` aims the last level at."""


def landing_theta(theta, eta_h, tol):
    """The Doerfler parameter of a level with estimate ``eta_h`` that has not reached ``tol``: ``theta``, but near the
    tolerance no more than the share of eta_h^2 that must go for the rest to be (LANDING tol)^2, at least 0.3 (the
    paper's): with theta = 0.8 and big hp steps (eta_h falling 3-8 times per level) the last level would
    otherwise overshoot to errors of tol/20 at the cost of the largest solve of the loop."""
    if tol is None:
        return theta
    return min(theta, max(0.3, 1.0 - (LANDING * tol / eta_h) ** 2))


def _out_of_time(records, sol, seconds, start, max_seconds):
    """Whether the next level would end after ``max_seconds`` from ``start``: the time so far plus this
    level's ``seconds`` times its growth in DOFs over the last level (2 after the first)."""
    if max_seconds is None:
        return False
    growth = sol.ndof / records[-1]["ndof"] if records else 2.0
    return time.perf_counter() - start + sum(seconds.values()) * max(growth, 1.0) > max_seconds


class _Loop:
    """The state the levels of :func:`adapt` hand on: the mesh and its :class:`HPState`, the previous
    solution on the refined mesh (a warm start) and the eta_h the next level starts from."""

    def __init__(self, problem, mesh, order, max_order, estimator, tolerances, layers, gamma_lin, solve_options):
        self.problem, self.mesh, self.order, self.max_order, self.layers = problem, mesh, order, max_order, layers
        self.estimator, self.gamma_lin, self.solve_options = estimator, gamma_lin, solve_options
        self.tolerances, self.tol = tolerances, None
        self.state, self.previous, self.predicted, self.sol = HPState.uniform(mesh, order), None, None, None
        self.singular = None  # the points the next hp refinement grades towards (set by solve)
        # u survives refinement in an autoupdating GridFunction; it must be one space for the whole
        # loop (a space created on an already refined mesh is prolongated wrongly by NGSolve 6.2.2608)
        self.carrier_order = order if max_order is None else max_order
        self.carrier = ngs.GridFunction(ngs.L2(mesh, order=self.carrier_order, autoupdate=True) ** 2, autoupdate=True)

    def solve(self, last):
        """Solve and estimate this level (inexactly unless ``last``); returns (sol, est, seconds)."""
        start = time.perf_counter()
        inexact = {} if self.gamma_lin is None or self.predicted is None else dict(energy_tol=self.gamma_lin
                                                                                    * self.predicted)
        orders = self.order if self.max_order is None else self.state.orders
        sol = solve(self.problem, self.mesh, order=orders, initial=self.previous, **inexact, **self.solve_options)
        self.tol = target(self.tolerances, sol)
        seconds = dict(solve=time.perf_counter() - start, estimate=0.0, mark_refine=0.0)
        sol, est = self.settle(sol, None, last, seconds)
        self.sol, self.predicted = sol, est.eta_h
        # the points the next refinement grades towards (hp_refine): corners and ends of the contact and stick zones
        graded = self.layers and self.max_order is not None
        self.singular = np.vstack([self.problem.geometry.corners, transitions(sol)]) if graded else None
        return sol, est, seconds

    def decide(self, level, sol, est, seconds, records, limits):
        """(sol, est, why the loop stops or None, the refinement to make): eta_h <= tol, the last level, the
        time limit (:func:`_out_of_time`), else Doerfler marking and the size of the refined mesh
        (:meth:`too_large`); a level the loop stops at is solved to the full tolerance (:meth:`settle`).
        ``limits``: theta, max_levels, max_ndof, max_seconds and the loop's start time."""
        refinement = None
        if self.tol is not None and est.eta_h <= self.tol:
            stopped = "tol"
        elif level == limits["max_levels"] - 1:
            stopped = "max_levels"
        elif _out_of_time(records, sol, seconds, limits["start"], limits["max_seconds"]):
            stopped = "max_seconds"
        else:
            theta = landing_theta(limits["theta"], est.eta_h, self.tol)
            marked = _timed(seconds, "mark_refine", dorfler_mark, est.eta_T_squared, theta)
            refinement = dict(indicators=est.eta_T_squared, marked=marked)
            stopped = _timed(seconds, "mark_refine", self.too_large, limits["max_ndof"], refinement)
        if stopped not in (None, "tol", "max_levels"):
            sol, est = self.settle(sol, est, True, seconds)
        return sol, est, stopped, refinement

    def settle(self, sol, est, returned, seconds):
        """:func:`_settle` with this loop's estimator, tolerances and gamma_lin."""
        return _settle(sol, est, self.estimator, (self.tol, self.solve_options["solver_tol"]), self.gamma_lin, returned,
                       seconds)

    def too_large(self, max_ndof, refinement):
        """:func:`_too_large` for this mesh and state."""
        return _too_large(self.mesh, self.state, max_ndof, self.max_order is not None, self._refine, refinement)

    def refine(self, refinement):
        """Carry the solution over, then refine the mesh in place (h or hp) and update the state."""
        copy_orders(*discontinuous(self.sol), self.carrier, np.full(self.mesh.ne, self.carrier_order))
        self.previous = WarmStart(u=self.carrier, mesh=self.mesh, multiplier=multiplier_snapshot(self.sol))
        self.sol = None  # compressed spaces on Gamma_C must be gone before the mesh changes;
        gc.collect()  # reference cycles may keep them alive (seen in dask workers); adapt froze the older objects
        self.state = self._refine(self.mesh, self.state, **refinement)

    def _refine(self, mesh, state, indicators, marked):
        """Refine ``mesh`` in place (h: one bisection; hp: :func:`hp_refine`); returns the new HPState."""
        if self.max_order is not None:
            return hp_refine(mesh, state, indicators, marked, self.max_order, singular=self.singular,
                             layers=self.layers)
        refine(mesh, marked)
        return HPState.uniform(mesh, self.order)


def _record(level, sol, est, state, seconds, tol):
    """The CSV row of a level (keys ``FIELDS``; ``tol``: the level's target eta_h, :func:`target`)."""
    mesh = sol.mesh
    return dict(level=level, ndof=sol.ndof, elements=mesh.ne, eta_h=est.eta_h,
                **{k: math.sqrt(v) for k, v in est.terms_squared.items()}, eta_lin=sol.info.get("linearization", 0.0),
                iterations=sol.iterations, solve_seconds=seconds["solve"], estimate_seconds=seconds["estimate"],
                mark_refine_seconds=seconds["mark_refine"], h_min=float(element_diameters(mesh).min()),
                min_angle=minimum_angle(mesh), p_min=int(state.orders.min()), p_max=int(state.orders.max()),
                target=math.nan if tol is None else tol)


def target(tolerances, sol):
    """The eta_h a level must reach for ``tolerances`` (tol, rtol) (either may be None): the larger of tol and
    rtol |||u_h|||_h (:func:`ngdgfric.energy_norm`), None if both are None."""
    tol, rtol = tolerances
    relative = None if rtol is None else rtol * energy_norm(sol)
    given = [value for value in (tol, relative) if value is not None]
    return max(given) if given else None


INITIAL_LAYERS = 2
"""Geometric layers towards the corners of the domain in :func:`initial_mesh` for hp-adaptivity."""


def initial_mesh(problem, layers=0):
    """The first mesh of :func:`adapt`: uniform h = 1/2 on a rectangle, else Netgen with maxh = min(1/2, a
    quarter of the domain's diameter); then ``layers`` geometric layers towards the domain's corners (the elements
    containing one bisected twice, ``layers`` times), where the solution is singular whatever the data: hp-adaptive
    runs start with ``INITIAL_LAYERS`` (exploratory runs, not kept: on Examples 6.1 and 6.2 the true errors 1e-1 ...
    1e-4 are reached in 35-65 % less time, 1e-1 one level sooner)."""
    if problem.geometry.is_rectangle:
        mesh = uniform_mesh(problem, 0.5)
    else:
        mesh = netgen_mesh(problem, min(0.5, problem.geometry.diameter() / 4))
    for _ in range(layers):
        refine(mesh, containing(mesh, problem.geometry.corners), bisections=2)
    return mesh


def _check_arguments(order, max_order, hp, weights, max_levels, max_ndof, tolerances, gamma_lin, max_seconds):
    if hp and not (isinstance(max_order, int) and max_order >= order):
        raise ValueError(f"max_order must be an integer >= order = {order}, got {max_order!r}")
    if weights not in WEIGHTS:
        raise ValueError(f"weights must be one of {WEIGHTS}, got {weights!r}")
    for name, value in (("max_levels", max_levels), ("max_ndof", max_ndof)):
        if not (isinstance(value, (int, np.integer)) and value >= 1):
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    for name, value in (("tol", tolerances[0]), ("rtol", tolerances[1]), ("max_seconds", max_seconds)):
        if value is not None and not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive number or None, got {value!r}")
    if gamma_lin is not None and not (isinstance(gamma_lin, (int, float)) and 0 < gamma_lin < 1):
        raise ValueError(f"gamma_lin must be a number in (0, 1) or None, got {gamma_lin!r}")


def _settle(sol, est, estimator, tolerances, gamma_lin, returned, seconds):
    """The estimate of a level, and an inexact solve made good enough (Ern & Vohralik's adaptive
    inexact loop): if eta_lin > gamma_lin eta_h, solved on to eta_lin <= gamma_lin eta_h and
    re-estimated (then, if still short, to the full tolerance); solved to the full tolerance at once
    where it is returned (``returned``, or eta_h <= tol; ``tolerances``: (tol, solver_tol)).  ``estimator``:
    callable(sol) -> Estimate.  ``est``: the
    estimate of ``sol`` if known;
    ``seconds``: its "solve" and "estimate" entries are increased.  Returns (sol, est)."""
    tol, solver_tol = tolerances
    if est is None:
        est = _timed(seconds, "estimate", estimator, sol)
    for partial in (True, False):
        if sol.state is None:
            break
        full = not partial or returned or (tol is not None and est.eta_h <= tol)
        if not full and sol.info["linearization"] <= gamma_lin * est.eta_h:
            break
        sol = _timed(seconds, "solve", finish, sol, solver_tol=solver_tol,
                     energy_tol=None if full else gamma_lin * est.eta_h)
        est = _timed(seconds, "estimate", estimator, sol)
    return sol, est


def _timed(seconds, key, function, *args, **kwargs):
    """function(*args, **kwargs), its seconds added to ``seconds[key]``."""
    start = time.perf_counter()
    result = function(*args, **kwargs)
    seconds[key] += time.perf_counter() - start
    return result


def _too_large(mesh, state, max_ndof, hp, refine_mesh, refinement):
    """"max_ndof" if the refined mesh would have more than ``max_ndof`` DOFs, "memory" if its solve
    would need more than :data:`ngdgfric.checks.MEMORY_BUDGET` (:func:`ngdgfric.checks.check_size`),
    else None.

    One pass of bisection with closure gives an element at most 4 children (hp_refine makes two
    passes) and raising p_T to p_T + 1 at most doubles its n_T = (p_T + 1)(p_T + 2) DOFs (so at most
    quadruples its memory n_T (1000 + 270 n_T)); near the limits the refinement is done on a copy
    of the mesh (Netgen's copy keeps the bisection data, so the copy refines exactly as the mesh would).
    """
    growth, memory_growth = (32, 64) if hp else (4, 4)
    if state.ndof * growth <= max_ndof and estimated_bytes(state.orders) * memory_growth <= MEMORY_BUDGET:
        return None
    refined = refine_mesh(ngs.Mesh(mesh.ngmesh.Copy()), state, **refinement)
    if refined.ndof > max_ndof:
        return "max_ndof"
    return "memory" if estimated_bytes(refined.orders) > MEMORY_BUDGET else None


def _report(records, csv_path, progress, solver):
    record = records[-1]
    if csv_path is not None:
        write_csv(csv_path, records, FIELDS)
    if progress is not None:
        orders = f"p {record['p_min']}..{record['p_max']}, " if record["p_max"] > record["p_min"] else ""
        progress(f"level {record['level']:3d}: {record['ndof']:7d} dofs, {orders}eta_h = {record['eta_h']:.4e}, "
                 f"{solver} {record['iterations']} iterations, {record['solve_seconds']:.2f} s solve, "
                 f"{record['estimate_seconds'] + record['mark_refine_seconds']:.2f} s estimate+refine")
