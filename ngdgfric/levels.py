r"""One level of the adaptive loop of Section 6 (SOLVE -> ESTIMATE -> MARK -> REFINE), for :func:`ngdgfric.adapt`.

``AdaptiveLoop`` holds what the levels hand on (the mesh, its ``HPState``, the previous solution as a warm start,
the :math:`\eta_h` the next level starts from) and does one step each: ``AdaptiveLoop.solve`` (solve and
estimate, inexactly where ``gamma_lin`` allows: ``settle``), ``AdaptiveLoop.decide`` (stop, or Doerfler marking,
:mod:`ngdgfric.marking`, and the size of the next mesh: ``too_large``, ``out_of_time``) and
``AdaptiveLoop.refine`` (h or hp).  ``record`` is a level's row of the CSV (``FIELDS``).
"""

import contextlib
import gc
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .checks import estimated_bytes
from .contact import transitions
from .dg.discretization import space
from .dg.methods import get_method
from .hp import HPState, hp_refine
from .marking import dorfler_mark, landing_theta
from .meshes import element_diameters, minimum_angle, refine
from .reference import energy_norm
from .solution import finish, solve
from .transfer import WarmStart, copy_orders, discontinuous, multiplier_snapshot

__all__ = ["AdaptiveLoop", "LoopSettings", "FIELDS", "record", "target", "out_of_time", "settle", "too_large",
           "frozen_older_objects"]

FIELDS = ["level", "ndof", "elements", "eta_h", "eta1", "eta2", "eta3", "eta4", "eta5", "eta6", "eta_lin",
          "iterations", "solve_seconds", "assemble_seconds", "estimate_seconds", "mark_refine_seconds", "h_min",
          "min_angle", "p_min", "p_max"]


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

    options: object
    order: int
    estimator: Callable
    gamma_lin: float | None
    solve_options: Mapping
    start: float

    @property
    def tolerances(self):
        """(tol, rtol): the targets of :func:`target`."""
        return self.options.tol, self.options.rtol


@contextlib.contextmanager
def frozen_older_objects():
    """The objects alive on entry moved out of the garbage collector's view until exit (``gc.freeze``): the full
    collection of every level (``AdaptiveLoop.refine``) then scans only what the loop made
    (:doc:`/decisions_adaptivity`)."""
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()

def out_of_time(records, sol, seconds, start, max_seconds):
    """Whether the next level would end after ``max_seconds`` from ``start``: the time so far plus this
    level's ``seconds`` times its growth in DOFs over the last level (2 after the first)."""
    if max_seconds is None:
        return False
    growth = sol.ndof / records[-1]["ndof"] if records else 2.0
    return time.perf_counter() - start + sum(seconds.values()) * max(growth, 1.0) > max_seconds


class AdaptiveLoop:
    """The state the levels of :func:`ngdgfric.adapt` hand on: the mesh and its :class:`HPState`, the previous
    solution on the refined mesh (a warm start) and the eta_h the next level starts from.  ``mesh`` is refined in
    place; ``settings``: a :class:`LoopSettings`."""

    def __init__(self, problem, mesh, settings):
        self.problem, self.mesh, self.settings, self.tol = problem, mesh, settings, None
        self.state, self.previous, self.predicted, self.sol = HPState.uniform(mesh, settings.order), None, None, None
        self.expected = None  # the eta_h the last marking expected of this level, (1 - theta)^(1/2) eta_h
        self.singular = None  # the points the next hp refinement grades towards (set by solve)
        # u survives refinement in an autoupdating GridFunction; it must be one space for the whole
        # loop (a space created on an already refined mesh is prolongated wrongly by NGSolve 6.2.2608)
        self.carrier_order = settings.options.max_order if settings.options.hp else settings.order
        self.carrier = ngs.GridFunction(ngs.L2(mesh, order=self.carrier_order, autoupdate=True) ** 2, autoupdate=True)

    def orders(self, state):
        """The degrees of the method's V_h on a mesh of ``state``: its p_T for hp, ``order`` for h."""
        return state.orders if self.settings.options.hp else self.settings.order

    def solve(self, last):
        """Solve and estimate this level (inexactly unless ``last``); returns (sol, est, seconds)."""
        settings, start = self.settings, time.perf_counter()
        inexact = {} if settings.gamma_lin is None or self.predicted is None else dict(energy_tol=settings.gamma_lin
                                                                                        * self.predicted)
        sol = solve(self.problem, self.mesh, order=self.orders(self.state), initial=self.previous, **inexact,
                    **settings.solve_options)
        self.tol = target(settings.tolerances, sol)
        seconds = dict(solve=time.perf_counter() - start, estimate=0.0, mark_refine=0.0)
        sol, est = self.settle(sol, None, last, seconds)
        self.sol, self.predicted = sol, est.eta_h
        # the points the next refinement grades towards (hp_refine): corners and ends of the contact and stick zones
        graded = settings.options.hp and settings.options.layers
        self.singular = np.vstack([self.problem.geometry.corners, transitions(sol)]) if graded else None
        return sol, est, seconds

    def decide(self, level, sol, est, seconds, records):
        """(sol, est, why the loop stops or None, the refinement to make): eta_h <= tol, the last level, the
        time limit (``out_of_time``), else Doerfler marking and the size of the refined mesh
        (:meth:`too_large`); a level the loop stops at is solved to the full tolerance (:meth:`settle`)."""
        options, refinement = self.settings.options, None
        if self.tol is not None and est.eta_h <= self.tol:
            stopped = "tol"
        elif level == options.max_levels - 1:
            stopped = "max_levels"
        elif out_of_time(records, sol, seconds, self.settings.start, options.max_seconds):
            stopped = "max_seconds"
        else:
            reduction = 1.0 if not self.expected else min(max(est.eta_h / self.expected, 0.25), 1.5)
            theta = landing_theta(options.theta, est.eta_h, self.tol, est.kind, reduction)
            self.expected = (1.0 - theta) ** 0.5 * est.eta_h  # 0 for theta = 1: no correction next level
            marked = timed(seconds, "mark_refine", dorfler_mark, est.eta_T_squared, theta)
            refinement = dict(indicators=est.eta_T_squared, marked=marked)
            stopped = timed(seconds, "mark_refine", self.too_large, refinement)
        if stopped not in (None, "tol", "max_levels"):
            sol, est = self.settle(sol, est, True, seconds)
        return sol, est, stopped, refinement

    def settle(self, sol, est, returned, seconds):
        """``settle`` with this loop's estimator, tolerances and gamma_lin."""
        settings = self.settings
        return settle(sol, est, settings.estimator, (self.tol, settings.solve_options["solver_tol"]),
                      settings.gamma_lin, returned, seconds)

    def too_large(self, refinement):
        """``too_large`` for this mesh and state, counting the DOFs of the method's V_h (the conforming
        baseline's are about half the DG count on the same mesh and orders)."""
        method = get_method(self.settings.solve_options["method"])
        count = None if not method.conforming else lambda mesh, state: space(
            self.problem, mesh, self.orders(state), method).ndof
        return too_large(self.mesh, self.state, self.settings.options, self._refine, refinement, count)

    def refine(self, refinement):
        """Carry the solution over, then refine the mesh in place (h or hp) and update the state."""
        copy_orders(*discontinuous(self.sol), self.carrier, np.full(self.mesh.ne, self.carrier_order))
        self.previous = WarmStart(u=self.carrier, mesh=self.mesh, multiplier=multiplier_snapshot(self.sol))
        self.sol = None  # compressed spaces on Gamma_C must be gone before the mesh changes;
        gc.collect()  # reference cycles may keep them alive (seen in dask workers); adapt froze the older objects
        self.state = self._refine(self.mesh, self.state, **refinement)

    def _refine(self, mesh, state, indicators, marked):
        """Refine ``mesh`` in place (h: one bisection; hp: :func:`hp_refine`); returns the new HPState."""
        options = self.settings.options
        if options.hp:
            return hp_refine(mesh, state, indicators, marked, options.max_order, singular=self.singular,
                             layers=options.layers)
        refine(mesh, marked)
        return HPState.uniform(mesh, self.settings.order)


def record(level, sol, est, state, seconds, tol):
    """The CSV row of a level (keys ``FIELDS``; ``tol``: the level's target eta_h, :func:`target`)."""
    mesh = sol.mesh
    return dict(level=level, ndof=sol.ndof, elements=mesh.ne, eta_h=est.eta_h,
                **{k: math.sqrt(v) for k, v in est.terms_squared.items()}, eta_lin=sol.info.get("linearization", 0.0),
                iterations=sol.iterations, solve_seconds=seconds["solve"], assemble_seconds=sol.timings["assemble"],
                estimate_seconds=seconds["estimate"],
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


def settle(sol, est, estimator, tolerances, gamma_lin, returned, seconds):
    """The estimate of a level, and an inexact solve made good enough (Ern & Vohralik's adaptive
    inexact loop): if eta_lin > gamma_lin eta_h, solved on to eta_lin <= gamma_lin eta_h and
    re-estimated (then, if still short, to the full tolerance); solved to the full tolerance at once
    where it is returned (``returned``, or eta_h <= tol; ``tolerances``: (tol, solver_tol)).  ``estimator``:
    callable(sol) -> Estimate.  ``est``: the
    estimate of ``sol`` if known;
    ``seconds``: its "solve" and "estimate" entries are increased.  Returns (sol, est)."""
    tol, solver_tol = tolerances
    if est is None:
        est = timed(seconds, "estimate", estimator, sol)
    for partial in (True, False):
        if sol.state is None:
            break
        full = not partial or returned or (tol is not None and est.eta_h <= tol)
        if not full and sol.info["linearization"] <= gamma_lin * est.eta_h:
            break
        sol = timed(seconds, "solve", finish, sol, solver_tol=solver_tol,
                     energy_tol=None if full else gamma_lin * est.eta_h)
        est = timed(seconds, "estimate", estimator, sol)
    return sol, est


def timed(seconds, key, function, *args, **kwargs):
    """function(*args, **kwargs), its seconds added to ``seconds[key]``."""
    start = time.perf_counter()
    result = function(*args, **kwargs)
    seconds[key] += time.perf_counter() - start
    return result


def too_large(mesh, state, options, refine_mesh, refinement, count=None):
    """"max_ndof" if the refined mesh would have more than ``options.max_ndof`` DOFs, "memory" if its solve
    would need more than ``options.max_bytes`` (the memory model of :func:`ngdgfric.checks.check_size`),
    else None; ``options``: an :class:`ngdgfric.AdaptOptions` (hp or h refinement, the budgets).

    One pass of bisection with closure gives an element at most 4 children (hp_refine makes two
    passes) and raising p_T to p_T + 1 at most doubles its n_T = (p_T + 1)(p_T + 2) DOFs (so at most
    quadruples its memory n_T (1000 + 270 n_T)); near the limits the refinement is done on a copy
    of the mesh (Netgen's copy keeps the bisection data, so the copy refines exactly as the mesh would).
    ``count``: callable(mesh, state) -> the DOFs of the method's V_h there (None: the DG count ``state.ndof``,
    which bounds the conforming one from above, so the first test holds for both).
    """
    max_ndof, max_bytes = options.max_ndof, options.max_bytes
    growth, memory_growth = (32, 64) if options.hp else (4, 4)
    if state.ndof * growth <= max_ndof and estimated_bytes(state.orders) * memory_growth <= max_bytes:
        return None
    copy = ngs.Mesh(mesh.ngmesh.Copy())
    refined = refine_mesh(copy, state, **refinement)
    if (refined.ndof if count is None else count(copy, refined)) > max_ndof:
        return "max_ndof"
    return "memory" if estimated_bytes(refined.orders) > max_bytes else None
