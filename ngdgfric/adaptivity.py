r"""SOLVE, ESTIMATE, MARK, REFINE (Section 6): the adaptive loop :func:`ngdgfric.adapt` and its settings.

Doerfler marking (:func:`ngdgfric.dorfler_mark`), then bisection of the marked elements or the hp decision of
:func:`ngdgfric.hp_refine`; one level at a time by ``AdaptiveLoop`` (:mod:`ngdgfric.levels`).

The defaults of :func:`ngdgfric.adapt`: the conforming baseline where :math:`\nu` is moderate
(``choose_method``), hp from :math:`p = 4` up to ``MAX_ORDER``, :math:`\theta = 0.8` and ``LAYERS`` geometric layers:
a marked element that the hp decision bisects and that contains a singular point (a corner of the domain, an end of
the contact or the stick zone) is bisected twice more towards it in the same step, so that the grading towards the
singular points does not pace the levels.  The paper's loop (``method="sipg", hp=False, order=1, theta=0.3,
variant="paper"``) is unchanged by them: layers act in hp refinement only.  The inexact solves of ``gamma_lin``
(Ern and Vohralik, SISC 35, 2013) are not the default.  The time to an accuracy these defaults reach:
:doc:`/results/time_to_accuracy`; the runs that chose them: :ref:`decisions-adaptivity`.
"""

import dataclasses
import functools
import time
from dataclasses import dataclass
from numbers import Integral, Real
from pathlib import Path
from types import MappingProxyType

import numpy as np

from .checks import MEMORY_BUDGET, callback, nonnegative_number, optional, positive_integer, positive_number
from .dg.discretization import MAX_DEGREE, check_order, space
from .dg.material import largest
from .dg.methods import get_method
from .equilibration import PAIRS_REASON
from .estimator import KINDS, VARIANTS, deprecated_weights, estimate
from .files import check_writable, write_csv
from .hp import containing
from .levels import FIELDS, AdaptiveLoop, LoopSettings, frozen_older_objects, record, timed
from .marking import dorfler_mark
from .meshes import grid_mesh, minimum_angle, netgen_mesh, refine, snapshot
from .progress import log, reporter
from .threads import limited_blas

__all__ = ["dorfler_mark", "adapt", "AdaptOptions", "Adaptation", "minimum_angle", "choose_method", "initial_mesh",
           "level_line", "FIELDS", "MAX_ORDER", "LAYERS", "INITIAL_LAYERS", "DEFAULT_RTOL"]

DEFAULT_RTOL = 1e-3
"""The accuracy :func:`adapt` stops at when given neither ``tol`` nor ``rtol``: :math:`\\eta_h \\le 10^{-3}
|\\!|\\!| u_h |\\!|\\!|_h`, 0.1 % of the energy norm (without a target the loop would run on to its budgets)."""

MAX_ORDER = 8
"""The largest degree of hp-adaptivity unless :func:`adapt` is given ``max_order``: no lower cap reaches the same
accuracy faster on the paper's examples (the measurements: :ref:`decisions-adaptivity`)."""
LAYERS = 1
"""The geometric layers per hp step unless :func:`adapt` is given ``layers`` (what a layer is: module docstring;
why one: :ref:`decisions-adaptivity`)."""
INITIAL_LAYERS = 2
"""Geometric layers towards the corners of the domain in ``initial_mesh`` for hp-adaptivity."""


@dataclass
class Adaptation:
    """The result of :func:`adapt`: its levels, the last solution and estimate, and why it stopped.

    Parameters
    ----------
    levels : list of dict
        One record per solved level, with the keys of ``ngdgfric.adaptivity.FIELDS`` (level, DOFs, degrees,
        :math:`\\eta_h`, iterations and the contact points whose state changed from the warm start, times; the
        columns of ``adapt``'s CSV) and ``target``: the :math:`\\eta_h` the
        level had to reach, the larger of ``tol`` and ``rtol`` :math:`|\\!|\\!| u_h |\\!|\\!|_h` (0 for ``rtol=0``
        alone: no accuracy target).
    solution : Solution
        The :class:`ngdgfric.Solution` of the last level; its mesh is the final mesh, not refined after the solve.
    estimate : Estimate
        Its :class:`ngdgfric.Estimate`.
    stopped : str
        Why the loop ended: ``"tol"`` (the target reached), ``"max_levels"``, ``"max_ndof"``, ``"memory"`` or
        ``"max_seconds"``.
    method : str, optional
        The method used.  Default ``"sipg"``.
    method_reason : str, optional
        Why: ``"given"``, or the reason of the automatic choice when :func:`adapt` was given no method.
    """

    levels: list
    solution: object
    estimate: object
    stopped: str
    method: str = "sipg"
    method_reason: str = "given"


def choose_method(problem, mesh, order):
    """(method, reason): the discretisation :func:`adapt` uses when none is given, by where each method locks
    (``ngdgfric.dg.methods.LOCKING``, :doc:`/results/locking`; the data :class:`~ngdgfric.Discretization` warns with,
    so that adapt never warns about its own choice).  The conforming baseline ``cg`` (about half the DOFs of a DG
    method on the same mesh and orders, no skeleton terms, and the same contact solver, estimator and hp loop:
    :doc:`/results/time_to_accuracy`) where it locks at no degree: below nu = 0.49, from where its error grows more than
    twice at p = 1-3.  At p = 4 its displacement does not lock (x1.84 at nu = 0.49999), but its stresses are worse: the
    estimator's effectivity (which sees them) rises from 2.0 at nu = 0.3 to 4.9 at nu = 0.49 and 6.6 at 0.4999 (Bassi
    et al.: 2.1-2.5), so adapt would stop far below tol (:ref:`decisions-adaptivity`).  From nu = 0.49 the
    first of Bassi et al. (symmetric, error growth at most x1.08 up to nu = 0.49999) and Brezzi et al. (as robust at
    1.3-1.5 times Bassi's assembly cost) that does not lock at ``order``."""
    nu = largest(problem.on(mesh).nu, mesh)
    cg = get_method("cg")
    if not cg.locks(nu):
        return "cg", (f"nu = {nu:.6g} is moderate: the conforming baseline, half the DOFs of a DG method on the same "
                      f"mesh, is the cheapest adequate discretisation")
    name = next((name for name in ("bassi", "brezzi") if not get_method(name).locks(nu, order)), "brezzi")
    return name, (f"nu reaches {nu:.6g}: conforming elements lock from nu = {min(e.nu for e in cg.locking if e):g} "
                  f"(the results page 'locking'); the DG method {name!r} does not")


@dataclass(frozen=True)
class AdaptOptions:
    r"""The refinement and stopping settings of :func:`adapt`, checked when made.

    :func:`adapt` takes them as this object (``settings=``) or as keywords of the same names; the two forms give
    the same run.  The loop stops at the first of: the estimate at or below ``tol`` or ``rtol`` times the energy
    norm (given neither, ``rtol`` is ``DEFAULT_RTOL`` = 1e-3), ``max_levels`` solved levels, a next mesh above
    ``max_ndof`` DOFs or ``max_bytes`` of memory, a next level that would end after ``max_seconds``.

    Parameters
    ----------
    theta : float, optional
        Doerfler's bulk parameter :math:`\theta \in (0, 1]`: the marked elements carry at least the fraction
        :math:`\theta` of :math:`\eta_h^2`.  Default ``0.8``; the paper uses ``0.3``.
    hp : bool, optional
        ``True`` (default): hp-refinement (:func:`ngdgfric.hp_refine`: a marked element is bisected or its degree
        raised); ``False``: bisection only, the degree stays ``order``.
    max_order : int or None, optional
        The largest degree of hp-refinement, at least ``order`` and at most 30.  Default ``None``: 8 (measured:
        lower caps are no faster to the same accuracy).  Refused with ``hp=False``.
    layers : int or None, optional
        Geometric layers per hp step: a bisected element containing a singular point (a corner, an end of the
        contact or stick zone) is bisected twice more towards it, ``layers`` times.  Default ``None``: 1.
        Refused with ``hp=False``.
    tol : float or None, optional
        Stop when :math:`\eta_h \le` ``tol``.  Default ``None``: no absolute target.
    rtol : float or None, optional
        Stop when :math:`\eta_h \le` ``rtol`` :math:`|\!|\!| u_h |\!|\!|_h` (the energy norm,
        :func:`ngdgfric.energy_norm`).  Default ``None``: ``DEFAULT_RTOL`` = 1e-3 if ``tol`` is ``None`` too, else no
        relative target.  ``rtol=0`` (or ``tol=0``): no accuracy target, the budgets alone end the run.
    max_levels : int, optional
        Solve at most this many levels.  Default ``100``.
    max_ndof : int, optional
        Stop before a mesh with more DOFs (a first mesh with more is refused by :func:`adapt` before it is
        solved).  Default ``10**6``.
    max_bytes : float, optional
        Stop before a mesh whose solve is estimated to need more memory, in bytes.  Default ``8e9``.
    max_seconds : float or None, optional
        Stop before a level that would end after this many seconds from the start (the last level's time
        times its growth in DOFs; the first level always runs).  Default ``None``: no limit.

    Raises
    ------
    ValueError
        A value out of its range, named with the value; ``max_order`` or ``layers`` given with ``hp=False``.

    See Also
    --------
    ngdgfric.adapt : The adaptive loop that reads these settings.

    Examples
    --------
    >>> settings = ndf.AdaptOptions(tol=1e-2, theta=0.5, max_levels=20)
    >>> settings.tol, settings.rtol, settings.hp
    (0.01, None, True)
    >>> ndf.AdaptOptions().rtol
    0.001
    >>> ndf.AdaptOptions(theta=0)
    Traceback (most recent call last):
    ...
    ValueError: theta must be in (0, 1], got 0
    """

    theta: float = 0.8
    hp: bool = True
    max_order: int | None = None
    layers: int | None = None
    tol: float | None = None
    rtol: float | None = None
    max_levels: int = 100
    max_ndof: int = 10**6
    max_bytes: float = MEMORY_BUDGET
    max_seconds: float | None = None

    def __post_init__(self):
        def fraction(value, name):
            if not (isinstance(value, Real) and not isinstance(value, bool) and 0 < value <= 1):
                raise ValueError(f"{name} must be in (0, 1], got {value!r}")

        def hp_order(value, name):
            if not (isinstance(value, Integral) and not isinstance(value, bool) and 1 <= value <= MAX_DEGREE):
                raise ValueError(f"{name} must be an integer in 1..{MAX_DEGREE} (MAX_DEGREE, the largest degree "
                                 f"NGSolve assembles) or None, got {value!r}")

        def layer_count(value, name):
            if not (isinstance(value, Integral) and not isinstance(value, bool) and value >= 0):
                raise ValueError(f"{name} must be an integer >= 0, got {value!r}")

        def flag(value, name):
            if not isinstance(value, (bool, np.bool_)):
                raise ValueError(f"{name} must be True or False, got {value!r}")

        checks = dict(theta=(fraction, float), hp=(flag, bool), max_order=(optional(hp_order), int),
                      layers=(optional(layer_count), int), tol=(optional(nonnegative_number), float),
                      rtol=(optional(nonnegative_number), float), max_levels=(positive_integer, int),
                      max_ndof=(positive_integer, int), max_bytes=(positive_number, float),
                      max_seconds=(optional(positive_number), float))
        for name, (check, kind) in checks.items():
            value = getattr(self, name)
            check(value, name)
            if value is not None:  # numpy's numbers as Python's: in the records, the CSV and repr
                object.__setattr__(self, name, kind(value))
        for name in ("max_order", "layers"):
            if getattr(self, name) is not None and not self.hp:
                raise ValueError(f"{name}={getattr(self, name)!r} acts in hp refinement only; hp=False would ignore it")
        if self.tol is None and self.rtol is None:
            object.__setattr__(self, "rtol", DEFAULT_RTOL)


SETTINGS = tuple(field.name for field in dataclasses.fields(AdaptOptions))
"""The keywords of :func:`adapt` that are the fields of :class:`AdaptOptions`."""


def _settings_once(function):
    """``function`` (:func:`adapt`) refusing its settings given both as ``settings=`` and as keywords."""
    @functools.wraps(function)
    def checked(*args, **keywords):
        settings = args[4] if len(args) > 4 else keywords.get("settings")
        given = sorted(name for name in SETTINGS if name in keywords)
        if settings is not None and given:
            raise ValueError(f"{', '.join(given)} given as keywords together with settings={settings!r}: give the "
                             f"settings either as an AdaptOptions or as keywords")
        return function(*args, **keywords)
    return checked


@_settings_once
@limited_blas
def adapt(problem, mesh=None, method=None, order=4, settings=None, *, tol=None, rtol=None, theta=0.8, hp=True,
          max_order=None, layers=None, max_levels=100, max_ndof=10**6, max_bytes=MEMORY_BUDGET, max_seconds=None,
          estimator="residual", variant=None, solver="newton", eta=None, solver_tol=None, gamma_lin=None,
          csv_path=None, progress=log, keep=None, weights=None, **options):
    r"""Solve adaptively to a tolerance: SOLVE, ESTIMATE, MARK, REFINE (Section 6), level after level.

    Every level solves the contact problem (:func:`ngdgfric.solve`, from the previous level's solution),
    estimates the error (:func:`ngdgfric.estimate`), marks elements by Doerfler's criterion
    (:func:`ngdgfric.dorfler_mark`) and refines them: bisection, or with ``hp`` the hp decision of
    :func:`ngdgfric.hp_refine`.  It stops at the first of ``tol``, ``rtol`` (by default
    :math:`\eta_h \le 10^{-3} |\!|\!| u_h |\!|\!|_h`), ``max_levels``, ``max_ndof``, ``max_bytes``, ``max_seconds``;
    the refinement of a level that would pass a budget is tried on a copy of the mesh, so the returned solution's
    mesh is never refined after its solve.

    Parameters
    ----------
    problem : ContactProblem
        The scene (:class:`ngdgfric.ContactProblem`).
    mesh : ngsolve.Mesh or None, optional
        The first mesh, refined in place.  Default ``None``: cells of sides at most
        :math:`\min(1/2, \text{diameter}/2)` on a rectangle (Netgen elsewhere), graded by two geometric layers
        towards the domain's corners for hp.
    method : str or None, optional
        One of ``"sipg"``, ``"nipg"``, ``"bassi"``, ``"brezzi"``, ``"ldg"`` (:data:`ngdgfric.DG_METHODS`) or
        ``"cg"`` (the conforming baseline).  Default ``None``: chosen by where each method locks -- ``"cg"`` for
        :math:`\nu < 0.49`, else the first of ``"bassi"``, ``"brezzi"`` that does not lock at ``order``; the
        choice and its reason are reported (``Adaptation.method``, ``Adaptation.method_reason``).
    order : int, optional
        The polynomial degree :math:`1 \le p \le 30` of the first level (of every level with ``hp=False``).
        Default ``4``.
    settings : AdaptOptions or None, optional
        The settings ``tol`` ... ``max_seconds`` below as one object (:class:`AdaptOptions`, the same names and
        defaults); refused together with any of those keywords.  Default ``None``: the keywords.
    tol : float or None, optional
        Stop when :math:`\eta_h \le` ``tol`` (an estimate of :math:`|\!|\!| u - u_h |\!|\!|_h`).  Default ``None``:
        no absolute target.
    rtol : float or None, optional
        Stop when :math:`\eta_h \le` ``rtol`` :math:`|\!|\!| u_h |\!|\!|_h` (with ``tol``, whichever is reached
        first).  Default ``None``: ``DEFAULT_RTOL`` = 1e-3 (0.1 % of the energy norm) if ``tol`` is ``None`` too, and
        ``adapt`` says so in its first progress line; else no relative target.  ``rtol=0``: no accuracy target, the
        budgets below alone end the run.
    theta : float, optional
        Doerfler's bulk parameter :math:`\theta \in (0, 1]`.  Default ``0.8``; the paper uses ``0.3``.
    hp : bool, optional
        ``True`` (default): hp-refinement (:func:`ngdgfric.hp_refine`); ``False``: bisection only, degree ``order``.
    max_order : int or None, optional
        The largest degree of hp-refinement.  Default ``None``: ``MAX_ORDER`` = 8.  Refused with ``hp=False``.
    layers : int or None, optional
        Geometric layers per hp step towards corners and the ends of the contact and stick zones.  Default
        ``None``: ``LAYERS`` = 1.  Refused with ``hp=False``.
    max_levels : int, optional
        Solve at most this many levels.  Default ``100``.
    max_ndof : int, optional
        Stop before a mesh with more DOFs.  Default ``10**6``.
    max_bytes : float, optional
        Stop before a mesh whose solve is estimated to need more memory, in bytes.  Default ``8e9``
        (``MEMORY_BUDGET``).
    max_seconds : float or None, optional
        Stop before a level that would end after this many seconds from the start.  Default ``None``: no limit.
    estimator : str, optional
        ``"residual"`` (default; :func:`ngdgfric.estimate`, the estimator of Section 4) or
        ``"equilibrated"`` (the guaranteed bound of :func:`ngdgfric.equilibrate`).  Marking uses its indicators.
    variant : str or None, optional
        The residual estimator's variant: ``None`` or ``"energy"`` (:math:`\eta_h` estimates
        :math:`|\!|\!| u - u_h |\!|\!|_h`, so that ``rtol=1e-3`` asks for 0.1 % of it) or ``"paper"`` (Section 4
        as printed).  Refused with ``estimator="equilibrated"``, which has no variants.
    solver : str, optional
        The contact solver of every level: ``"newton"`` (default), ``"uzawa"`` or ``"fixed_point"``
        (:func:`ngdgfric.solve`).
    eta : float or None, optional
        The penalty parameter of the DG methods.  Default ``None``: the method's own default
        (:data:`ngdgfric.METHODS`): ``sipg`` :math:`30\mu`, ``nipg`` :math:`30\mu`, ``bassi`` :math:`6`,
        ``brezzi`` :math:`1`, ``ldg`` :math:`30\mu`, ``cg`` :math:`30\mu` (:math:`\mu` times a number for the
        edge penalties, a pure number for the lifting penalties of Bassi et al. and Brezzi et al.); sipg and cg raise
        theirs to 1.5 times the coercivity threshold where :math:`30\mu` is not above it (:func:`ngdgfric.solve`).
    solver_tol : float or None, optional
        The solver's tolerance (:func:`ngdgfric.solve`).  Default ``None``: the solver's default.
    gamma_lin : float or None, optional
        With ``solver="newton"`` only: solve every level but the returned one inexactly, until the
        linearisation estimate :math:`\eta_{lin} \le \gamma_{lin}\,\eta_h` (Ern and Vohralik, SISC 35, 2013).
        Default ``None``: exact solves (inexact ones steered the hp decisions into refining Gamma_C, measured).
    csv_path : str or pathlib.Path or None, optional
        A CSV of the finished levels (one row each: DOFs, degrees, :math:`\eta_h`, iterations, times),
        rewritten atomically after every level, so that an interrupted run keeps them.  Default ``None``.
    progress : callable or None, optional
        ``progress(line)`` receives one line per level.  Default ``log``: the lines go to the logger
        ``"ngdgfric"`` at level INFO (silent unless logging is configured); ``None``: no lines.
    keep : callable or None, optional
        ``keep(level, solution, estimate)`` is called at every level, e.g. to save a picture.  Default ``None``.
    weights : str or None, optional
        The old name of ``variant`` (DeprecationWarning).
    **options
        The solver's options for :func:`ngdgfric.solve` (e.g. ``maxit``; :class:`ngdgfric.NewtonOptions`).

    Returns
    -------
    Adaptation
        The levels (one record each), the last level's solution and estimate, why the loop stopped and the
        method used (:class:`ngdgfric.Adaptation`).

    Raises
    ------
    ValueError
        An argument out of its range or one that the chosen solver, estimator or refinement would ignore,
        named with its value; all are checked before the first solve.

    See Also
    --------
    ngdgfric.AdaptOptions : The settings, with their defaults.
    ngdgfric.solve : One solve on a given mesh.

    Notes
    -----
    The paper's loop is ``adapt(problem, method="sipg", order=1, hp=False, theta=0.3, variant="paper")``.
    The defaults (hp from :math:`p = 4`, :math:`\theta = 0.8`, one geometric layer, the method chosen by
    where it locks) are those measured fastest to an accuracy on both of the paper's examples.

    Examples
    --------
    >>> problem = ndf.example_6_2()
    >>> run = ndf.adapt(problem, tol=1e-2, progress=None)
    >>> run.stopped, run.method
    ('tol', 'cg')
    >>> print(run.estimate.eta_h <= 1e-2)
    True

    The same settings grouped:

    >>> settings = ndf.AdaptOptions(tol=1e-2)
    >>> ndf.adapt(problem, settings=settings, progress=None).levels[-1]["ndof"] == run.levels[-1]["ndof"]
    True
    """
    variant = deprecated_weights(variant, weights, "adapt")
    if settings is None:
        settings = AdaptOptions(theta=theta, hp=hp, max_order=max_order, layers=layers, tol=tol, rtol=rtol,
                                max_levels=max_levels, max_ndof=max_ndof, max_bytes=max_bytes, max_seconds=max_seconds)
    elif not isinstance(settings, AdaptOptions):
        raise ValueError(f"settings must be an AdaptOptions or None, got {settings!r}")
    _check_arguments(order, settings, gamma_lin)
    _check_applicable(solver, estimator, variant, gamma_lin)
    if estimator == "equilibrated" and problem.pairs:
        raise ValueError(f"adapt(estimator='equilibrated') is refused: {PAIRS_REASON}")
    callback(keep, "keep")
    start, say = time.perf_counter(), reporter(progress)
    settings = _with_hp_defaults(settings)
    mesh = initial_mesh(problem, INITIAL_LAYERS if settings.layers else 0) if mesh is None else mesh
    if csv_path is not None:
        csv_path = Path(csv_path)
        check_writable(csv_path.parent)
    method, reason = choose_method(problem, mesh, order) if method is None else (get_method(method).name, "given")
    _check_first_level(problem, mesh, order, get_method(method), settings)
    say(f"method {method}: {reason}")
    if tol is None and rtol is None and settings.tol is None and settings.rtol == DEFAULT_RTOL:
        say(f"target: eta_h <= rtol |||u_h|||_h with rtol = {DEFAULT_RTOL:g}, the default (neither tol nor rtol was "
            f"given; rtol=0 runs on to the budgets)")
    solve_options = MappingProxyType(dict(method=method, eta=eta, solver=solver, solver_tol=solver_tol,
                                          max_bytes=settings.max_bytes, **options))
    loop = AdaptiveLoop(problem, mesh, LoopSettings(
        options=settings, order=order, estimator=functools.partial(estimate, variant=variant, kind=estimator),
        gamma_lin=gamma_lin, solve_options=solve_options, start=start))
    records, last = _levels(loop, keep, csv_path, functools.partial(_say_level, say, solver))
    return Adaptation(records, last.sol, last.est, last.stopped, method, reason)


def _with_hp_defaults(settings):
    """``settings`` with ``max_order`` and ``layers`` given for hp (``MAX_ORDER``, ``LAYERS`` where None); h
    settings as they are (both None)."""
    if not settings.hp:
        return settings
    return dataclasses.replace(settings, max_order=MAX_ORDER if settings.max_order is None else settings.max_order,
                               layers=LAYERS if settings.layers is None else settings.layers)


def _levels(loop, keep, csv_path, show):
    """Run the levels of ``loop`` until it stops; returns (the records, the last ``Level``, which says why).
    Every finished level is written to ``csv_path`` (``write_levels``) and shown (``show(record)``)."""
    records = []
    with frozen_older_objects():
        for number in range(loop.settings.options.max_levels):
            level = loop.decide(loop.solve(number), records)
            records.append(record(level, loop.state))
            if keep is not None:
                keep(number, level.sol, level.est)
            if level.stopped is None:
                marking, level = level.marking, None  # the solution gone before the mesh changes (loop.refine)
                records[-1]["mark_refine_seconds"] += timed(loop.refine, marking)[1]
            write_levels(csv_path, records)
            show(records[-1])
            if level is not None:  # the loop stopped at this level
                return records, level
    raise AssertionError("the last level always stops")  # pragma: no cover


def initial_mesh(problem, layers=0):
    """The first mesh of :func:`adapt`: on a rectangle cells of sides at most min(1/2, half its longest side)
    (``grid_mesh``: uniform h = 1/2 on the paper's examples), else Netgen with maxh = min(1/2,
    a quarter of the domain's diameter, its longest extent); then ``layers`` geometric layers towards the domain's
    corners (the elements containing one bisected twice, ``layers`` times), where the solution is singular whatever
    the data: hp-adaptive runs start with ``INITIAL_LAYERS`` (why: :ref:`decisions-adaptivity`).  With layers the
    mesh returned is a copy without the refinement history (``snapshot``), on which the loop's warm starts are exact
    (:ref:`decisions-levels`)."""
    size = problem.geometry.diameter()
    if problem.geometry.is_rectangle:
        mesh = grid_mesh(problem, min(0.5, size / 2))
    else:
        mesh = netgen_mesh(problem, min(0.5, size / 4))
    for _ in range(layers):
        refine(mesh, containing(mesh, problem.geometry.corners), bisections=2)
    return snapshot(mesh) if layers else mesh  # a mesh without a history: the loop's warm starts are exact on it


def _check_arguments(order, settings, gamma_lin):
    """ValueError naming the first argument of :func:`adapt` out of its range (the settings checked themselves)."""
    if np.ndim(order) != 0:
        raise ValueError(f"order must be an integer in 1..{MAX_DEGREE} (the degree of the first level), got {order!r}")
    check_order(order)
    largest = MAX_ORDER if settings.max_order is None else settings.max_order
    if settings.hp and largest < order:
        raise ValueError(f"max_order must be an integer >= order = {order}, got {settings.max_order!r}"
                         f"{f' (the default {MAX_ORDER})' if settings.max_order is None else ''}")
    if gamma_lin is not None and not (isinstance(gamma_lin, Real) and not isinstance(gamma_lin, bool)
                                      and 0 < gamma_lin < 1):
        raise ValueError(f"gamma_lin must be a number in (0, 1) or None, got {gamma_lin!r}")


def _check_first_level(problem, mesh, order, method, settings):
    """ValueError before the first solve if the first level alone has more than ``max_ndof`` DOFs (those of ``method``
    on ``mesh`` at degree ``order``; its ``max_bytes`` are checked by the first solve before assembly)."""
    ndof = space(problem, mesh, order, method).ndof
    if ndof > settings.max_ndof:
        raise ValueError(f"max_ndof = {settings.max_ndof} is below the first level's {ndof} DOFs ({method.name}, "
                         f"degree {order}, {mesh.ne} elements): give max_ndof >= {ndof}, a lower order or a coarser "
                         f"first mesh")


def _check_applicable(solver, estimator, variant, gamma_lin):
    """ValueError for an option of :func:`adapt` that the chosen solver or estimator would ignore."""
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


def write_levels(csv_path, records):
    """The CSV of the levels so far (columns ``FIELDS``), written atomically; nothing for ``csv_path`` None."""
    if csv_path is not None:
        write_csv(csv_path, records, FIELDS)


def level_line(level_record, solver):
    """The progress line of a level: DOFs, orders, eta_h, iterations (and the contact points whose state changed from
    the warm start), times."""
    r = level_record
    orders = f"p {r['p_min']}..{r['p_max']}, " if r["p_max"] > r["p_min"] else ""
    changed = f" ({r['changed_points']} points changed state)" if r.get("changed_points") is not None else ""
    return (f"level {r['level']:3d}: {r['ndof']:7d} dofs, {orders}eta_h = {r['eta_h']:.4e}, {solver} "
            f"{r['iterations']} iterations{changed}, {r['solve_seconds']:.2f} s solve "
            f"({r['assemble_seconds']:.2f} s of it assembly), "
            f"{r['estimate_seconds'] + r['mark_refine_seconds']:.2f} s estimate+refine")


def _say_level(say, solver, level_record):
    say(level_line(level_record, solver))
