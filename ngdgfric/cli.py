r"""Command line: ``ngdgfric solve|uniform|adaptive PROBLEM [options]`` (also ``python -m ngdgfric``).

PROBLEM is ``6.1`` or ``6.2`` (the examples of Section 6) or a TOML problem file
(:mod:`ngdgfric.problem_file`).  ``solve`` solves (3.1) once and writes a CSV summary, a VTK file
(displacement, von Mises stress) and a PNG of the deformed mesh; ``uniform`` runs the study of
Tables 6.1/6.2 (:math:`\|u_h - u_{h/2}\|_h` on :math:`h = 2^{-1}, 2^{-2}, \dots`) and writes CSV and Markdown;
``adaptive`` runs the SOLVE-ESTIMATE-MARK-REFINE loop of Section 6 and writes CSV and a PNG of
:math:`\eta_h` against the number of DOFs.  ``solve`` and ``adaptive`` (for its final solution) also print the
forces on the body (:mod:`ngdgfric.forces`: contact resultants and contact/stick/slip zones per contact side,
reactions per Dirichlet and symmetry side, the equilibrium residual) and write them as ``*_forces.csv`` with a PNG
of the zones along each contact side, ``*_contact.png``.  Bad input ends with one line ``ngdgfric: error: ...`` on
stderr and exit code 2 before anything is computed where it can be known then (arguments, problem
file and data, mesh size, output folder, outputs of an earlier run without ``--overwrite``); a
solver failure with exit code 1.  Every file is written atomically, each as soon as it is
finished, so an interrupted run (Ctrl-C, exit code 130, or SIGTERM, 143) keeps what it completed.

This module parses the arguments and dispatches to the commands (:mod:`ngdgfric.commands`), printing the
library's progress lines (the logger ``"ngdgfric"``, :mod:`ngdgfric.progress`) on stdout; the files and plots are
made by :mod:`ngdgfric.output` (shared with the notebooks).  ``--weights`` is the deprecated old name of
``--variant`` (a warning on stderr).
"""

import argparse
import contextlib
import importlib.metadata
import inspect
import math
import os
import signal
import sys
import threading
import warnings
from pathlib import Path

from .adaptivity import DEFAULT_RTOL, INITIAL_LAYERS, LAYERS, MAX_ORDER, AdaptOptions, adapt
from .checks import MEMORY_BUDGET, DataError
from .commands import COMMANDS, DEFAULT_H, NOT_REACHED, NotReached, load, outputs
from .dg.methods import METHODS
from .errors import SolverError
from .estimator import KINDS, VARIANTS
from .examples import EXAMPLES, SCENES
from .files import check_writable
from .problem_file import in_file
from .progress import printed
from .solution import SOLVERS, solve

__all__ = ["main", "run", "build_parser", "load"]

MAX_NDOF_HELP = f"refuse meshes with more DOFs (default: above an estimated {MEMORY_BUDGET / 1e9:g} GB of memory)"


class UsageError(Exception):
    """Bad command-line arguments (reported in one line instead of argparse's usage + message)."""



class Terminated(KeyboardInterrupt):
    """SIGTERM while :func:`main` runs.  A KeyboardInterrupt, so the run stops as on Ctrl-C (temporary files
    removed, a meshing child killed, finished files kept); :func:`main` returns 128 + 15."""


RESEND = 0.5
"""Seconds between the SIGTERMs the process sends itself after the first, until :func:`main` has stopped."""


@contextlib.contextmanager
def _sigterm_interrupts():
    """Inside the block SIGTERM raises :class:`Terminated`; the previous handler is restored after it.

    Only in the main thread (the only one where Python sets handlers) and over a handler known to Python (``None``,
    one set outside Python, could not be put back).  The handler's exception can be lost where it is raised:
    pybind11 clears it while NGSolve converts arguments (``CF((a, b))`` tries its next overload) or turns it into
    another error ("Unable to cast ... tuple"), and Python drops it in a ``__del__``.  So from the first SIGTERM on,
    a thread started with the block sends the main thread one every ``RESEND`` seconds until the block is left, any
    other error then leaves the block as :class:`Terminated`, and one dropped in a ``__del__`` is not printed.  The
    handler raises nothing while a KeyboardInterrupt is handled, so the cleanups of the first (temporary files, a
    meshing child) run to their end, and takes no lock (it can run inside any code, threading's included).
    """
    previous = signal.getsignal(signal.SIGTERM)
    if previous is None or threading.current_thread() is not threading.main_thread():
        yield
        return
    received, left, main_thread, unraisable = False, threading.Event(), threading.get_ident(), sys.unraisablehook

    def terminate(signum, frame):
        nonlocal received
        if left.is_set() or isinstance(sys.exc_info()[1], KeyboardInterrupt):
            return
        received = True
        raise Terminated

    def resend():
        while not left.wait(RESEND):
            if received:  # to the main thread: it wakes from a sleep or a wait
                signal.pthread_kill(main_thread, signal.SIGTERM)

    def unprinted(info):
        if not isinstance(info.exc_value, Terminated):
            unraisable(info)

    resender = threading.Thread(target=resend, name="ngdgfric-sigterm", daemon=True)
    resender.start()
    signal.signal(signal.SIGTERM, terminate)
    sys.unraisablehook = unprinted
    try:
        yield
    except Exception as exc:
        if received:
            raise Terminated from exc
        raise
    finally:
        left.set()
        resender.join()
        sys.unraisablehook = unraisable
        signal.signal(signal.SIGTERM, previous)  # runs a SIGTERM still pending through terminate first


class _Deprecated(argparse.Action):
    """An old option name: stores its value under the new one and notes the old name in ``deprecated``, which
    :func:`run` reports as a warning."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        namespace.deprecated = [*getattr(namespace, "deprecated", []), (option_string, self.dest)]


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def _number(kind, low=0.0, high=None, what="positive", closed=False):
    """argparse type: a finite ``kind`` number x with low < x (<= high); low <= x if ``closed``."""
    def convert(text):
        try:
            value = float(text) if kind is float else _integer(text)
        except (ValueError, OverflowError):
            raise argparse.ArgumentTypeError(f"not {'a number' if kind is float else 'an integer'}: {text!r}") from None
        if not ((value >= low if closed else value > low) and (high is None or value <= high) and math.isfinite(value)):
            raise argparse.ArgumentTypeError(f"must be {what}, got {text}")
        return value
    return convert


def _integer(text):
    value = float(text)  # accepts 1e5
    if value != int(value):
        raise ValueError(text)
    return int(value)


def build_parser():
    """The argparse parser of the three subcommands."""
    parser = _Parser(prog="ngdgfric", description="DG methods for 2D frictional contact with normal compliance "
                                                  "(Porwal & Tanvi): solve, uniform and adaptive studies.",
                     epilog="Run 'ngdgfric COMMAND --help' for the options of a command.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in (_solve_parser, _uniform_parser, _adaptive_parser):
        add(commands)
    return parser


def _defaults(function):
    return {name: parameter.default for name, parameter in inspect.signature(function).parameters.items()}


DEFAULTS = {"solve": _defaults(solve), "adapt": {**_defaults(adapt), **_defaults(AdaptOptions)}}
"""The keyword defaults of :func:`ngdgfric.solve` and :func:`ngdgfric.adapt`: the command line's own defaults."""


def default(library, name):
    """The default of keyword ``name`` of the library's function ``library`` ("solve" or "adapt")."""
    return DEFAULTS[library][name]


def _common_options(sub, several_methods=False, library="solve"):
    """PROBLEM, --method, --order, --solver, --eta, --solver-tol, --out, --overwrite; defaults those of the
    library's function ``library`` (:func:`ngdgfric.solve`, or :func:`ngdgfric.adapt` for ``adaptive``)."""
    sub.add_argument("problem", metavar="PROBLEM", help=f"6.1, 6.2 (Section 6), a shipped scene ({', '.join(SCENES)}) "
                                                      "or a TOML problem file")
    method = default(library, "method")
    if several_methods:
        sub.add_argument("--method", nargs="+", choices=sorted(METHODS), default=[method],
                         help=f"DG methods of Section 3 or cg, the conforming baseline (default: {method})")
    else:
        shown = method or "chosen for the problem: cg, or bassi for nearly incompressible material"
        sub.add_argument("--method", choices=sorted(METHODS), default=method,
                         help=f"DG method of Section 3 or cg, the conforming baseline (default: {shown})")
    order = default(library, "order")
    sub.add_argument("--order", type=_number(int), default=order,
                     help=f"polynomial degree p >= 1 (default: {order}{', the lowest with hp' * (library == 'adapt')})")
    sub.add_argument("--solver", choices=sorted(SOLVERS), default=default(library, "solver"),
                     help=f"nonlinear solver (default: {default(library, 'solver')}, the problem condensed onto "
                          "Gamma_C and solved by semismooth Newton there; uzawa: the paper's method)")
    sub.add_argument("--eta", type=_number(float), default=None,
                     help="penalty parameter (default: 30 mu for the edge penalties, Section 6)")
    sub.add_argument("--solver-tol", type=_number(float), default=None,
                     help="tolerance of the nonlinear solver (default: 1e-13 on the KKT residual for "
                          "newton, 1e-8 on the relative change for uzawa as in Section 6)")
    sub.add_argument("--out", type=Path, default=Path("out"), help="output folder (default: out/)")
    sub.add_argument("--overwrite", action="store_true",
                     help="replace the output files of an earlier run (default: refuse to)")


def _mesh_options(sub, default):
    group = sub.add_mutually_exclusive_group()
    group.add_argument("--h", type=_number(float), default=None,
                       help=f"uniform mesh of squares of side h cut in two (rectangles only, h dividing their sides; "
                            f"default: {default})")
    group.add_argument("--maxh", type=_number(float), default=None, help="Netgen mesh with mesh size maxh")


def _solve_parser(commands):
    sub = commands.add_parser("solve", help="solve once; write CSV, VTK and a PNG of the deformed mesh",
                              description="Solve (3.1) once; print DOFs, iterations, |||u_h|||_h, eta_h, time and the "
                                          "forces on the body; write a CSV summary, a VTK file (displacement, von "
                                          "Mises stress), a PNG of the deformed mesh with the contact zones, the "
                                          "forces as CSV and a PNG of the zones along each contact side.")
    _common_options(sub)
    _mesh_options(sub, f"cells of sides at most {DEFAULT_H} on a rectangle, Netgen maxh = {DEFAULT_H} on other "
                       f"domains; {DEFAULT_H} x the diameter on domains smaller than 1")
    sub.add_argument("--max-ndof", type=_number(int), default=None, help=MAX_NDOF_HELP)
    sub.add_argument("--scale", type=_number(float), default=None,
                     help="displacement magnification in the PNG (default: the largest 1, 2 or 5 x 10^k that draws "
                          "the largest displacement as at most 10%% of the domain size)")


def _uniform_parser(commands):
    sub = commands.add_parser("uniform", help="uniform refinement study (Tables 6.1, 6.2); write CSV and Markdown",
                              description="Solve on uniform meshes h = 2^-1 ... 2^-LEVELS (rectangles only) and "
                                          "report |||u_h - u_{h/2}|||_h, its observed rate and eta_h (Section 6).")
    _common_options(sub, several_methods=True)
    sub.add_argument("--max-ndof", type=_number(int), default=None, help=MAX_NDOF_HELP)
    sub.add_argument("--levels", type=_number(int, low=1, what="at least 2"), default=5,
                     help="number of meshes, h = 2^-1 ... 2^-LEVELS (default: 5)")


def _adaptive_parser(commands):
    sub = commands.add_parser("adaptive", help="adaptive loop of Section 6; write CSV and a PNG of eta_h vs DOFs",
                              description="SOLVE -> ESTIMATE -> MARK (Doerfler) -> REFINE (newest vertex "
                                          "bisection, or h/p with --hp), one progress line per level.")
    _common_options(sub, library="adapt")
    _mesh_options(sub, f"adapt's first mesh: cells of sides at most min(1/2, diameter / 2) on a rectangle, Netgen "
                       f"maxh = min(1/2, diameter / 4) on other domains, then {INITIAL_LAYERS} geometric layers "
                       f"towards the corners with --hp")
    theta, levels, max_ndof = (default("adapt", name) for name in ("theta", "max_levels", "max_ndof"))
    sub.add_argument("--theta", type=_number(float, high=1.0, what="in (0, 1]"), default=theta,
                     help=f"Doerfler parameter (default: {theta})")
    sub.add_argument("--levels", type=_number(int), default=levels,
                     help=f"maximal number of solves (default: {levels})")
    sub.add_argument("--max-ndof", type=_number(int), default=max_ndof,
                     help=f"stop before a solve with more DOFs (default: {max_ndof:.0e})")
    sub.add_argument("--max-seconds", type=_number(float), default=default("adapt", "max_seconds"),
                     help="stop before a level that would end after this many seconds (default: no limit)")
    sub.add_argument("--tol", type=_number(float, what=">= 0", closed=True), default=default("adapt", "tol"),
                     help="stop when eta_h <= TOL (an estimate of the energy error |||u - u_h|||_h); a run that "
                          f"stops before exits with code {NOT_REACHED}")
    sub.add_argument("--rtol", type=_number(float, what=">= 0", closed=True), default=default("adapt", "rtol"),
                     help="stop when eta_h <= RTOL |||u_h|||_h (a relative tolerance: 1e-3 for 0.1 %% of the energy "
                          "norm; with --tol, whichever is reached first); exit code as for --tol when given (default: "
                          f"{DEFAULT_RTOL:g} when --tol is not given either, and a stop before it is said, not an "
                          "error; 0: no target, the budgets end the run)")
    sub.add_argument("--variant", choices=list(VARIANTS), default=default("adapt", "variant"),
                     help=f"variant of the residual estimator (default: {VARIANTS[0]}): 'energy' (in the units of "
                          "the energy norm) or 'paper' (Section 4 as printed); not with --estimator equilibrated")
    sub.add_argument("--weights", choices=list(VARIANTS), dest="variant", action=_Deprecated, default=argparse.SUPPRESS,
                     help="deprecated alias of --variant (removed in the next release)")
    kind = default("adapt", "estimator")
    sub.add_argument("--estimator", choices=list(KINDS), default=kind,
                     help=f"estimator that marks and stops (default: {kind}): 'residual' (Section 4) or "
                          "'equilibrated' (a guaranteed upper bound of the energy error, ngdgfric.equilibration)")
    hp = default("adapt", "hp")
    sub.add_argument("--hp", action=argparse.BooleanOptionalAction, default=hp,
                     help=f"hp refinement (ngdgfric.hp.hp_refine), or h refinement only "
                          f"(default: {'--hp' if hp else '--no-hp'})")
    max_order = default("adapt", "max_order")
    sub.add_argument("--max-order", type=_number(int), default=max_order,
                     help=f"largest degree with --hp (default: {MAX_ORDER})")
    layers = default("adapt", "layers")
    sub.add_argument("--layers", type=_number(int, low=-1, what="an integer >= 0"), default=layers,
                     help=f"extra geometric layers towards corners and ends of the contact and stick zones in each "
                          f"hp step (default: {LAYERS})")


def _version():
    try:
        return importlib.metadata.version("ngdgfric")
    except importlib.metadata.PackageNotFoundError:
        return "(not installed)"


def run(argv=None):
    """Run a command; returns its records (raises on bad input, see :func:`main`)."""
    args = build_parser().parse_args(argv)
    for old, new in getattr(args, "deprecated", []):
        _warn(f"{old} is deprecated and will be removed in the next release: use --{new}")
    problem, tag = load(args.problem)
    if getattr(args, "h", None) is not None and not problem.geometry.is_rectangle:
        raise ValueError("--h needs a rectangle geometry; use --maxh for a general polygon")
    check_writable(args.out)
    for path in outputs(args, tag):
        if path.is_dir():
            raise ValueError(f"cannot write {path}: it is a folder")
        if path.exists() and not args.overwrite:
            raise ValueError(f"{path} exists (an earlier run's output); pass --overwrite to replace it, or choose "
                             f"another --out")
    with warnings.catch_warnings(), printed():  # the library's progress lines (logger "ngdgfric") on stdout
        warnings.showwarning = lambda message, *_, **__: _warn(message)
        try:
            return COMMANDS[args.command](args, problem, tag)
        except DataError as exc:  # found on the mesh: name the key of the problem file
            if args.problem in EXAMPLES or args.problem in SCENES:
                raise
            raise ValueError(in_file(args.problem, exc)) from exc


def main(argv=None):
    """Entry point of ``ngdgfric`` and ``python -m ngdgfric``; returns the exit code.

    0: success; 2: bad input (arguments, problem file, problem data, sizes, output files), or not
    enough memory, reported in one line ``ngdgfric: error: ...`` on stderr; 1: the nonlinear solver
    failed; 3: an internal error (one line; the traceback with NGDGFRIC_TRACEBACK=1); 4: ``adaptive``
    stopped before its ``--tol`` (levels, DOFs, memory or time; its files are written); 130: interrupted
    (Ctrl-C); 143: terminated by SIGTERM, handled like Ctrl-C while ``main`` runs (the previous handler is
    restored when it returns).  Both keep the files finished before.
    """
    try:
        with _sigterm_interrupts():
            run(argv)
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else 0
    except (UsageError, ValueError, OSError) as exc:  # tomllib.TOMLDecodeError is a ValueError
        return _fail(exc, 2)
    except MemoryError:
        return _fail("not enough memory: use a coarser mesh, a lower --order or --max-ndof", 2)
    except SolverError as exc:
        return _fail(exc, 1)
    except NotReached as exc:
        return _fail(exc, NOT_REACHED)
    except Terminated:
        return _fail("terminated (SIGTERM)", 128 + signal.SIGTERM)
    except KeyboardInterrupt:
        return _fail("interrupted", 130)
    except Exception as exc:  # a bug: one line, not a traceback, unless asked for
        if os.environ.get("NGDGFRIC_TRACEBACK"):
            raise
        return _fail(f"internal error: {type(exc).__name__}: {exc} (NGDGFRIC_TRACEBACK=1 shows the traceback; "
                     f"please report it)", 3)
    return 0


def _warn(message):
    print(f"ngdgfric: warning: {message}", file=sys.stderr)


def _fail(message, code):
    text = " ".join(str(message).split())
    print(f"ngdgfric: error: {text}", file=sys.stderr)
    return code
