r"""One level of the adaptive loop of Section 6 (SOLVE -> ESTIMATE -> MARK -> REFINE), for :func:`ngdgfric.adapt`.

A level is a ``Level`` record, made by ``AdaptiveLoop.solve`` (solve and estimate, inexactly where
``gamma_lin`` allows: ``settle``) and completed by ``AdaptiveLoop.decide`` (why the loop stops, or Doerfler's
``Marking``, :mod:`ngdgfric.marking`, after the size of the next mesh: ``too_large``, ``out_of_time``), whose
marking ``AdaptiveLoop.refine`` refines by (h or hp).  ``AdaptiveLoop`` holds what the levels hand on (the mesh,
its ``HPState``, the previous solution as a warm start, the :math:`\eta_h` the next level starts from); its
settings are one ``LoopSettings``.  ``record`` is a level's row of the CSV (``FIELDS``).
"""

import contextlib
import gc
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, replace
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

from .checks import estimated_bytes
from .contact.boundary import law_elements
from .contact.state import transitions
from .dg.discretization import space
from .dg.methods import get_method
from .estimator import Estimate
from .hp import HPState, hp_refine
from .marking import dorfler_mark, landing_theta
from .meshes import element_diameters, minimum_angle, refine
from .reference import energy_norm
from .solution import Solution, finish, solve
from .transfer import WarmStart, copy_orders, discontinuous, multiplier_snapshot

if TYPE_CHECKING:  # adaptivity imports this module
    from .adaptivity import AdaptOptions

__all__ = ["AdaptiveLoop", "LoopSettings", "Level", "Seconds", "Marking", "FIELDS", "record", "target",
           "out_of_time", "settle", "too_large", "timed", "frozen_older_objects"]

FIELDS = ["level", "ndof", "elements", "eta_h", "eta1", "eta2", "eta3", "eta4", "eta5", "eta6", "eta_lin",
          "iterations", "changed_points", "solve_seconds", "assemble_seconds", "estimate_seconds",
          "mark_refine_seconds", "h_min", "min_angle", "p_min", "p_max"]


@dataclass(frozen=True)
class LoopSettings:
    """What every level of :func:`ngdgfric.adapt` is solved, estimated, marked and refined with.

    ``options``: the :class:`ngdgfric.AdaptOptions` of the run (theta, tol, rtol, max_levels, max_ndof, max_bytes,
    max_seconds) with the hp defaults given: ``max_order`` and ``layers`` numbers for hp, None for h.  ``order``: the
    degree of the first level (of every level for h).  ``estimator``: callable(sol) -> Estimate.  ``gamma_lin``:
    the inexact solves' eta_lin <= gamma_lin eta_h (None: exact solves).  ``solve_options``: the keywords of every
    :func:`ngdgfric.solve` (``method``, ``solver_tol``, ...).  ``start``: the ``time.perf_counter()`` that
    ``max_seconds`` counts from.
    """

    options: "AdaptOptions"
    order: int
    estimator: Callable
    gamma_lin: float | None
    solve_options: Mapping
    start: float

    @property
    def tolerances(self):
        """(tol, rtol): the targets of :func:`target`."""
        return self.options.tol, self.options.rtol


@dataclass(frozen=True)
class Seconds:
    """The seconds of a level by phase: solving (with the finishing of inexact solves), estimating, and marking and
    refining (with the trial refinement of :func:`too_large`); the columns ``solve_seconds``, ``estimate_seconds``,
    ``mark_refine_seconds`` of its record."""

    solve: float = 0.0
    estimate: float = 0.0
    mark_refine: float = 0.0

    def plus(self, **seconds):
        """These seconds with ``seconds`` (keywords: phases) added."""
        return replace(self, **{phase: getattr(self, phase) + value for phase, value in seconds.items()})


@dataclass(frozen=True, eq=False)
class Marking:
    r"""The refinement a level asks for: the squared indicators :math:`\eta_T^2` it was marked by and Doerfler's
    marked set (a boolean per element, :func:`ngdgfric.dorfler_mark`)."""

    indicators: np.ndarray
    marked: np.ndarray


@dataclass(frozen=True, eq=False)
class Level:
    """One level of the loop as it passes from SOLVE and ESTIMATE to MARK and REFINE.

    ``number`` counts from 0; ``sol`` and ``est``: its Solution and Estimate (``est`` None until estimated);
    ``tol``: the eta_h it must reach (:func:`target`); ``seconds``: the time of its phases;
    ``marking``: the refinement that makes the next level (None where the loop stops); ``stopped``: why the loop
    stops here (``"tol"``, ``"max_levels"``, ``"max_seconds"``, ``"max_ndof"``, ``"memory"``; None: it goes on).
    """

    number: int
    sol: Solution
    est: Estimate | None
    tol: float | None
    seconds: Seconds
    marking: Marking | None = None
    stopped: str | None = None


@contextlib.contextmanager
def frozen_older_objects():
    """The objects alive on entry moved out of the garbage collector's view until exit (``gc.freeze``): the full
    collection of every level (``AdaptiveLoop.refine``) then scans only what the loop made
    (:ref:`decisions-levels`)."""
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def out_of_time(records, sol, seconds, start, max_seconds):
    """Whether the next level would end after ``max_seconds`` from ``start``: the time so far plus this
    level's ``seconds`` (by phase, a mapping) times its growth in DOFs over the last level of ``records`` (2 after
    the first)."""
    if max_seconds is None:
        return False
    growth = sol.ndof / records[-1]["ndof"] if records else 2.0
    return time.perf_counter() - start + sum(seconds.values()) * max(growth, 1.0) > max_seconds


class AdaptiveLoop:
    """The state the levels of :func:`ngdgfric.adapt` hand on: the mesh and its :class:`HPState`, the previous
    solution on the refined mesh (a warm start) and the eta_h the next level starts from.  ``mesh`` is refined in
    place; ``settings``: a :class:`LoopSettings`."""

    def __init__(self, problem, mesh, settings):
        self.problem, self.mesh, self.settings = problem, mesh, settings
        self.state, self.previous, self.predicted, self.sol = HPState.uniform(mesh, settings.order), None, None, None
        self.expected = None  # the eta_h the last marking expected of this level, (1 - theta)^(1/2) eta_h
        self.singular = None  # the points the next hp refinement grades towards (set by solve)
        self.frictional = False  # whether a friction law acts somewhere (set by solve; _refine)
        # u survives refinement in an autoupdating GridFunction; it must be one space for the whole loop, created on a
        # mesh never refined before (a space created on an already refined mesh is prolongated wrongly by NGSolve
        # 6.2.2608: by 30 % of u on adapt's hp meshes, whose first mesh had its corner layers; decisions-levels);
        # on a mesh with a history u is interpolated from the solution's own mesh instead (exact, a point search)
        self.carrier_order = settings.options.max_order if settings.options.hp else settings.order
        self.carrier = ngs.GridFunction(ngs.L2(mesh, order=self.carrier_order, autoupdate=True) ** 2, autoupdate=True) \
            if mesh.levels == 1 else None

    def orders(self, state):
        """The degrees of the method's V_h on a mesh of ``state``: its p_T for hp, ``order`` for h."""
        return state.orders if self.settings.options.hp else self.settings.order

    def solve(self, number):
        """SOLVE and ESTIMATE level ``number`` (inexactly unless it is the last): its :class:`Level`."""
        settings, start = self.settings, time.perf_counter()
        inexact = {} if settings.gamma_lin is None or self.predicted is None else dict(energy_tol=settings.gamma_lin
                                                                                        * self.predicted)
        sol = solve(self.problem, self.mesh, order=self.orders(self.state), initial=self.previous, **inexact,
                    **settings.solve_options)
        tol = target(settings.tolerances, sol)
        level = Level(number, sol, None, tol, Seconds(solve=time.perf_counter() - start))
        level = self.settle(level, number == settings.options.max_levels - 1)
        self.sol, self.predicted = level.sol, level.est.eta_h
        self.frictional = bool(np.any(np.asarray(level.sol.contact.traces.c_tau) > 0))
        # the points the next refinement grades towards (hp_refine): corners and ends of the contact and stick zones
        graded = settings.options.hp and settings.options.layers
        self.singular = np.vstack([self.problem.geometry.corners, transitions(level.sol)]) if graded else None
        return level

    def decide(self, level, records):
        """MARK: ``level`` with why the loop stops there (eta_h <= tol, the last level, the time limit:
        ``out_of_time``, the size of the refined mesh: :meth:`too_large`) or with Doerfler's marking of it; a level
        the loop stops at for a budget is solved to the full tolerance (:meth:`settle`).  ``records``: the rows of
        the levels before (:func:`record`)."""
        options, est = self.settings.options, level.est
        if est.eta_h <= level.tol:
            return replace(level, stopped="tol")
        if level.number == options.max_levels - 1:
            return replace(level, stopped="max_levels")
        if out_of_time(records, level.sol, asdict(level.seconds), self.settings.start, options.max_seconds):
            return self.settle(replace(level, stopped="max_seconds"), True)
        reduction = 1.0 if not self.expected else min(max(est.eta_h / self.expected, 0.25), 1.5)
        theta = landing_theta(options.theta, est.eta_h, level.tol, est.kind, reduction)
        self.expected = (1.0 - theta) ** 0.5 * est.eta_h  # 0 for theta = 1: no correction next level
        marked, mark_seconds = timed(dorfler_mark, est.eta_T_squared, theta)
        marking = Marking(est.eta_T_squared, marked)
        stopped, size_seconds = timed(self.too_large, marking)
        level = replace(level, seconds=level.seconds.plus(mark_refine=mark_seconds + size_seconds))
        if stopped is None:
            return replace(level, marking=marking)
        return self.settle(replace(level, stopped=stopped), True)

    def settle(self, level, returned):
        """``settle`` with this loop's estimator, solver tolerance and gamma_lin."""
        settings = self.settings
        return settle(level, settings.estimator, settings.solve_options["solver_tol"], settings.gamma_lin, returned)

    def too_large(self, marking):
        """``too_large`` for this mesh and state, counting the DOFs of the method's V_h (the conforming
        baseline's are about half the DG count on the same mesh and orders)."""
        method = get_method(self.settings.solve_options["method"])
        count = None if not method.conforming else lambda mesh, state: space(
            self.problem, mesh, self.orders(state), method).ndof
        return too_large(self.mesh, self.state, self.settings.options, self._refine, marking, count)

    def refine(self, marking):
        """REFINE: carry the solution over, then refine the mesh in place by ``marking`` (h or hp) and update the
        state.  The caller holds no Level of this mesh any more (its solution must go before the mesh changes)."""
        if self.carrier is None:
            self.previous = WarmStart(u=discontinuous(self.sol)[0], mesh=self.sol.mesh,
                                      multiplier=multiplier_snapshot(self.sol))
        else:
            copy_orders(*discontinuous(self.sol), self.carrier, np.full(self.mesh.ne, self.carrier_order))
            self.previous = WarmStart(u=self.carrier, mesh=self.mesh, multiplier=multiplier_snapshot(self.sol))
        self.sol = None  # compressed spaces on Gamma_C must be gone before the mesh changes;
        gc.collect()  # reference cycles may keep them alive (seen in dask workers); adapt froze the older objects
        self.state = self._refine(self.mesh, self.state, marking)

    def _refine(self, mesh, state, marking):
        """Refine ``mesh`` in place by ``marking`` (h: one bisection; hp: :func:`hp_refine`, then, where friction acts
        somewhere, the elements along which a contact law acts brought to one degree, ``HPState.shared``: without
        friction the forces are unique whatever the degrees, and a degree raised at the ends of the contact zone cost
        accuracy there: Hertz's half-width came out 0.6 % asymmetric); returns the new HPState."""
        options = self.settings.options
        if options.hp:
            refined = hp_refine(mesh, state, marking.indicators, marking.marked, options.max_order,
                                singular=self.singular, layers=options.layers)
            return refined.shared(law_elements(self.problem, mesh)) if self.frictional else refined
        refine(mesh, marking.marked)
        return HPState.uniform(mesh, self.settings.order)


def record(level, state):
    """The CSV row of ``level`` (keys ``FIELDS``, and ``target``: its target eta_h); ``state``: the
    HPState of its mesh, which must not be refined yet.  ``changed_points``: the contact points whose state (no
    contact, stick, slip) the solve changed from its start (the warm start; zero on the first level)."""
    sol, est, seconds, mesh = level.sol, level.est, level.seconds, level.sol.mesh
    return dict(level=level.number, ndof=sol.ndof, elements=mesh.ne, eta_h=est.eta_h,
                **{k: math.sqrt(v) for k, v in est.terms_squared.items()}, eta_lin=sol.info.get("linearization", 0.0),
                iterations=sol.iterations, changed_points=sol.info.get("changed_points"), solve_seconds=seconds.solve,
                assemble_seconds=sol.timings["assemble"],
                estimate_seconds=seconds.estimate,
                mark_refine_seconds=seconds.mark_refine, h_min=float(element_diameters(mesh).min()),
                min_angle=minimum_angle(mesh), p_min=int(state.orders.min()), p_max=int(state.orders.max()),
                target=level.tol)


def target(tolerances, sol):
    """The eta_h a level must reach for ``tolerances`` (tol, rtol), at least one of them a number (``AdaptOptions``
    sees to it; the other None): the larger of tol and rtol |||u_h|||_h (:func:`ngdgfric.energy_norm`); 0 for
    ``rtol=0`` alone, a target only an exact solution reaches."""
    tol, rtol = tolerances
    return max(value for value in (tol, None if rtol is None else rtol * energy_norm(sol)) if value is not None)


def settle(level, estimator, solver_tol, gamma_lin, returned):
    """``level`` estimated, and an inexact solve made good enough (Ern & Vohralik's adaptive inexact loop): if
    eta_lin > gamma_lin eta_h, solved on to eta_lin <= gamma_lin eta_h and re-estimated (then, if still short, to
    the full tolerance ``solver_tol``); solved to the full tolerance at once where it is returned (``returned``, or
    eta_h <= ``level.tol``).  ``estimator``: callable(sol) -> Estimate.  Returns the level with its solution,
    estimate and seconds (solve, estimate) brought up to date."""
    if level.est is None:
        est, seconds = timed(estimator, level.sol)
        level = replace(level, est=est, seconds=level.seconds.plus(estimate=seconds))
    for partial in (True, False):
        sol, est = level.sol, level.est
        if sol.state is None:
            break
        full = not partial or returned or est.eta_h <= level.tol
        if not full and sol.info["linearization"] <= gamma_lin * est.eta_h:
            break
        sol, solve_seconds = timed(finish, sol, solver_tol=solver_tol,
                                   energy_tol=None if full else gamma_lin * est.eta_h)
        est, estimate_seconds = timed(estimator, sol)
        level = replace(level, sol=sol, est=est, seconds=level.seconds.plus(solve=solve_seconds,
                                                                            estimate=estimate_seconds))
    return level


def timed(function, *args, **kwargs):
    """(function(*args, **kwargs), the seconds it took)."""
    start = time.perf_counter()
    result = function(*args, **kwargs)
    return result, time.perf_counter() - start


def too_large(mesh, state, options, refine_mesh, marking, count=None):
    """"max_ndof" if the refined mesh would have more than ``options.max_ndof`` DOFs, "memory" if its solve
    would need more than ``options.max_bytes`` (the memory model of :func:`ngdgfric.checks.check_size`),
    else None; ``options``: an :class:`ngdgfric.AdaptOptions` (hp or h refinement, the budgets).

    One pass of bisection with closure gives an element at most 4 children (hp_refine makes two
    passes) and raising p_T to p_T + 1 at most doubles its n_T = (p_T + 1)(p_T + 2) DOFs (so at most
    quadruples its memory n_T (1000 + 270 n_T)); near the limits the refinement is done on a copy
    of the mesh (Netgen's copy keeps the bisection data, so the copy refines exactly as the mesh would).
    ``refine_mesh``: callable(mesh, state, marking) -> the HPState of ``mesh`` refined in place by ``marking``.
    ``count``: callable(mesh, state) -> the DOFs of the method's V_h there (None: the DG count ``state.ndof``,
    which bounds the conforming one from above, so the first test holds for both).
    """
    max_ndof, max_bytes = options.max_ndof, options.max_bytes
    growth, memory_growth = (32, 64) if options.hp else (4, 4)
    if state.ndof * growth <= max_ndof and estimated_bytes(state.orders) * memory_growth <= max_bytes:
        return None
    copy = ngs.Mesh(mesh.ngmesh.Copy())
    refined = refine_mesh(copy, state, marking)
    if (refined.ndof if count is None else count(copy, refined)) > max_ndof:
        return "max_ndof"
    return "memory" if estimated_bytes(refined.orders) > max_bytes else None
