"""Command line: ``ngdgfric solve|uniform|adaptive PROBLEM [options]`` (also ``python -m ngdgfric``).

PROBLEM is ``6.1`` or ``6.2`` (the examples of Section 6) or a TOML problem file
(:mod:`ngdgfric.problem_file`).  ``solve`` solves (3.1) once and writes a CSV summary, a VTK file
(displacement, von Mises stress) and a PNG of the deformed mesh; ``uniform`` runs the study of
Tables 6.1/6.2 (|||u_h - u_{h/2}|||_h on h = 2^-1, 2^-2, ...) and writes CSV and Markdown;
``adaptive`` runs the SOLVE-ESTIMATE-MARK-REFINE loop of Section 6 and writes CSV and a PNG of
eta_h against the number of DOFs.  ``solve`` and ``adaptive`` (for its final solution) also print the forces on
the body (:mod:`ngdgfric.forces`: contact resultants and contact/stick/slip zones per contact side, reactions per
Dirichlet and symmetry side, the equilibrium residual) and write them as ``*_forces.csv`` with a PNG of the zones
along each contact side, ``*_contact.png``.  Bad input ends with one line ``ngdgfric: error: ...`` on
stderr and exit code 2 before anything is computed where it can be known then (arguments, problem
file and data, mesh size, output folder, outputs of an earlier run without ``--overwrite``); a
solver failure with exit code 1.  Every file is written atomically, each as soon as it is
finished, so an interrupted run keeps what it completed.

This module parses the arguments and dispatches to the library; the files and plots are made by
:mod:`ngdgfric.output` (shared with the notebooks).
"""

import argparse
import importlib.metadata
import inspect
import itertools
import math
import os
import sys
import time
import warnings
from pathlib import Path

from .adaptivity import adapt
from .checks import DataError, check_size
from .dg.methods import METHODS
from .errors import SolverError
from .estimator import KINDS, estimate
from .examples import EXAMPLES, SCENES, example
from .files import check_writable, write_csv, write_text
from .forces import force_balance
from .meshes import estimated_elements, netgen_mesh, uniform_mesh
from .output import (
    rate_text,
    uniform_markdown,
    write_adaptive_png,
    write_contact_png,
    write_deformed_png,
    write_vtk,
)
from .problem_file import in_file, load_problem
from .reference import energy_norm
from .solution import SOLVERS, solve
from .studies import uniform_study

__all__ = ["main", "run", "build_parser", "load"]

DEFAULT_H = 0.125
MAX_NDOF_HELP = "refuse meshes with more DOFs (default: refuse above an estimated 8 GB of memory)"


NOT_REACHED = 4  # the exit code of an adaptive run that stopped before --tol
STOPS = {"max_levels": "--levels reached", "max_ndof": "the next mesh would exceed --max-ndof",
         "memory": "the next mesh would exceed the memory budget", "max_seconds": "--max-seconds reached"}


class UsageError(Exception):
    """Bad command-line arguments (reported in one line instead of argparse's usage + message)."""


class NotReached(Exception):
    """An adaptive run stopped before its --tol (its outputs are written)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def _number(kind, low=0.0, high=None, what="positive"):
    """argparse type: a finite ``kind`` number x with low < x (<= high)."""
    def convert(text):
        try:
            value = float(text) if kind is float else _integer(text)
        except (ValueError, OverflowError):
            raise argparse.ArgumentTypeError(f"not {'a number' if kind is float else 'an integer'}: {text!r}") from None
        if not (value > low and (high is None or value <= high) and math.isfinite(value)):
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


DEFAULTS = {"solve": _defaults(solve), "adapt": _defaults(adapt)}
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
                       help=f"uniform mesh of squares of side h cut in two (rectangles only; default: {default})")
    group.add_argument("--maxh", type=_number(float), default=None, help="Netgen mesh with mesh size maxh")


def _solve_parser(commands):
    sub = commands.add_parser("solve", help="solve once; write CSV, VTK and a PNG of the deformed mesh",
                              description="Solve (3.1) once; print DOFs, iterations, |||u_h|||_h, eta_h, time and the "
                                          "forces on the body; write a CSV summary, a VTK file (displacement, von "
                                          "Mises stress), a PNG of the deformed mesh with the contact zones, the "
                                          "forces as CSV and a PNG of the zones along each contact side.")
    _common_options(sub)
    _mesh_options(sub, f"h = {DEFAULT_H}, or Netgen maxh = {DEFAULT_H} for other polygons")
    sub.add_argument("--max-ndof", type=_number(int), default=None, help=MAX_NDOF_HELP)
    sub.add_argument("--scale", type=_number(float), default=None,
                     help="displacement magnification in the PNG (default: largest displacement = 10%% of the "
                          "domain size)")


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
    _mesh_options(sub, "h = 1/2, or Netgen maxh = 1/2 for other polygons")
    theta, levels, max_ndof = (default("adapt", name) for name in ("theta", "max_levels", "max_ndof"))
    sub.add_argument("--theta", type=_number(float, high=1.0, what="in (0, 1]"), default=theta,
                     help=f"Doerfler parameter (default: {theta})")
    sub.add_argument("--levels", type=_number(int), default=levels,
                     help=f"maximal number of solves (default: {levels})")
    sub.add_argument("--max-ndof", type=_number(int), default=max_ndof,
                     help=f"stop before a solve with more DOFs (default: {max_ndof:.0e})")
    sub.add_argument("--max-seconds", type=_number(float), default=default("adapt", "max_seconds"),
                     help="stop before a level that would end after this many seconds (default: no limit)")
    sub.add_argument("--tol", type=_number(float), default=default("adapt", "tol"),
                     help="stop when eta_h <= TOL (an estimate of the energy error |||u - u_h|||_h); a run that "
                          f"stops before exits with code {NOT_REACHED}")
    sub.add_argument("--rtol", type=_number(float), default=default("adapt", "rtol"),
                     help="stop when eta_h <= RTOL |||u_h|||_h (a relative tolerance: 1e-3 for 0.1 %% of the energy "
                          "norm; with --tol, whichever is reached first); exit code as for --tol")
    weights = default("adapt", "weights")
    sub.add_argument("--weights", choices=["energy", "paper"], default=weights,
                     help=f"estimator (default: {weights}): 'energy' (in the units of the energy norm) or 'paper' "
                          "(Section 4 as printed)")
    kind = default("adapt", "estimator")
    sub.add_argument("--estimator", choices=list(KINDS), default=kind,
                     help=f"estimator that marks and stops (default: {kind}): 'residual' (Section 4) or "
                          "'equilibrated' (a guaranteed upper bound of the energy error, ngdgfric.equilibration; "
                          "--weights does not apply to it)")
    hp = default("adapt", "hp")
    sub.add_argument("--hp", action=argparse.BooleanOptionalAction, default=hp,
                     help=f"hp refinement (ngdgfric.hp.hp_refine), or h refinement only "
                          f"(default: {'--hp' if hp else '--no-hp'})")
    max_order = default("adapt", "max_order")
    sub.add_argument("--max-order", type=_number(int), default=max_order,
                     help=f"largest degree with --hp (default: {max_order})")
    layers = default("adapt", "layers")
    sub.add_argument("--layers", type=_number(int, low=-1, what="an integer >= 0"), default=layers,
                     help=f"extra geometric layers towards corners and ends of the contact and stick zones in each "
                          f"hp step (default: {layers})")


def _version():
    try:
        return importlib.metadata.version("ngdgfric")
    except importlib.metadata.PackageNotFoundError:
        return "(not installed)"


def load(spec):
    """(problem, tag) for PROBLEM: an example or scene name or the path of a TOML problem file."""
    if spec in EXAMPLES or spec in SCENES:
        return example(spec), spec.replace(".", "_")
    path = Path(spec)
    if not path.is_file():
        raise FileNotFoundError(f"no problem file {spec!r} (PROBLEM is 6.1, 6.2, a shipped scene "
                                f"({', '.join(SCENES)}) or a TOML file)")
    return load_problem(path), path.stem


def _mesh(problem, h, maxh, default, order, max_ndof):
    """(mesh, description) from --h / --maxh; the size is checked before meshing (``max_ndof``)."""
    rectangle = problem.geometry.is_rectangle
    if maxh is None and h is None:
        if default is None:
            return None, "h = 1/2" if rectangle else "Netgen maxh = 1/2"
        h, maxh = (default, None) if rectangle else (None, default)
    try:
        check_size(order, max_ndof, elements=estimated_elements(problem, h=h, maxh=maxh))
    except ValueError as exc:
        raise ValueError(f"{'--maxh' if maxh is not None else '--h'} {maxh or h:g}: {exc}") from None
    if maxh is not None:
        return netgen_mesh(problem, maxh, max_elements=None), f"Netgen maxh = {maxh:g}"
    return uniform_mesh(problem, h, max_elements=None), f"uniform h = {h:g}"


def say(message):
    print(message, flush=True)


def _uzawa_progress():
    """Every tenth progress line of Uzawa (one per 1000 iterations, the command line's rate), indented."""
    calls = itertools.count(1)

    def show(message):
        if next(calls) % 10 == 0:
            say(f"  {message}")

    return show


def cmd_solve(args, problem, tag):
    mesh, described = _mesh(problem, args.h, args.maxh, DEFAULT_H, args.order, args.max_ndof)
    say(f"{problem.name}: {described}, {mesh.ne} elements; {args.method} P{args.order}, {args.solver}")
    start = time.perf_counter()
    sol = solve(problem, mesh, method=args.method, order=args.order, eta=args.eta, solver=args.solver,
                solver_tol=args.solver_tol, max_ndof=args.max_ndof,
                progress=_uzawa_progress() if args.solver == "uzawa" else None)
    solved = time.perf_counter()
    est = estimate(sol)
    estimated = time.perf_counter()
    record = dict(problem=problem.name, mesh=described, elements=mesh.ne, method=sol.method, order=sol.order,
                  penalty=sol.eta, solver=sol.solver, ndof=sol.ndof, iterations=sol.iterations,
                  energy_norm=energy_norm(sol), eta_h=est.eta_h,
                  **{k: math.sqrt(v) for k, v in est.terms_squared.items()},
                  solve_seconds=solved - start, estimate_seconds=estimated - solved)
    say(f"  DOFs             {record['ndof']}")
    say(f"  iterations       {record['iterations']}")
    say(f"  |||u_h|||_h      {record['energy_norm']:.10e}")
    say(f"  eta_h            {record['eta_h']:.10e}")
    say(f"  time             {record['solve_seconds']:.2f} s solve, {record['estimate_seconds']:.2f} s estimate")
    csv_path, vtu_path, png_path, forces_path, contact_path = outputs(args, tag)
    write_csv(csv_path, [record])
    write_vtk(vtu_path, sol)
    balance = report_forces(sol)
    write_deformed_png(png_path, sol, args.scale, balance.contact)
    write_forces(forces_path, contact_path, sol, balance)
    say(f"wrote {csv_path}, {vtu_path}, {png_path}, {forces_path}, {contact_path}")
    return [record]


def report_forces(sol, heading="forces on the body"):
    """Print the forces on the body of ``sol`` (:func:`ngdgfric.forces.force_balance`) under ``heading``;
    returns them."""
    balance = force_balance(sol)
    say(f"{heading} as (x, y); contact: normal = integral of the pressure, tangential = friction along t:")
    for line in balance.summary():
        say(f"  {line}")
    return balance


def write_forces(csv_path, png_path, sol, balance):
    """The forces CSV (:meth:`ngdgfric.forces.ForceBalance.rows`) and the contact zones PNG of ``sol``."""
    write_csv(csv_path, balance.rows())
    write_contact_png(png_path, sol, balance.contact)


def outputs(args, tag):
    """The files a command writes (checked before computing: see :func:`run`)."""
    if args.command == "solve":
        stem = args.out / f"{tag}_{args.method}_p{args.order}"
        return [Path(f"{stem}{suffix}") for suffix in (".csv", ".vtu", ".png", "_forces.csv", "_contact.png")]
    if args.command == "uniform":
        return [args.out / f"{tag}_uniform.{suffix}" for suffix in ("csv", "md")]
    stem = args.out / f"{tag}_adaptive_{args.method or 'auto'}_p{args.order}{'_hp' if args.hp else ''}"
    return [Path(f"{stem}{suffix}") for suffix in (".csv", ".png", "_forces.csv", "_contact.png")]


def cmd_uniform(args, problem, tag):
    levels = tuple(range(1, args.levels + 1))
    try:  # before any output (uniform_study checks it again)
        check_size(args.order, args.max_ndof, elements=estimated_elements(problem, h=2.0**-levels[-1]))
    except ValueError as exc:
        raise ValueError(f"--levels {args.levels}: {exc}") from None
    csv_path, md_path = outputs(args, tag)
    rows = []
    for method in args.method:
        say(f"{problem.name}: {method} P{args.order}, {args.solver}, uniform h = 2^-1 ... 2^-{levels[-1]}")
        study, solutions = uniform_study(problem, method, args.order, levels, solver=args.solver, eta=args.eta,
                                         progress=say, solver_tol=args.solver_tol, max_ndof=args.max_ndof)
        for row, sol in zip(study, solutions, strict=False):
            row = dict(method=method, order=args.order, **row, eta_h=estimate(sol).eta_h)
            say(f"  h = 2^-{row['k']}: |||u_h - u_h/2|||_h = {row['energy']:.4e}, rate {rate_text(row['rate'])}, "
                f"eta_h = {row['eta_h']:.4e}")
            rows.append(row)
        write_csv(csv_path, rows)  # each finished study at once: an interrupted run keeps it
        write_text(md_path, uniform_markdown(f"{problem.name}: uniform meshes, P{args.order}, {args.solver}", rows))
        say(f"wrote {csv_path}, {md_path}")
    return rows


def cmd_adaptive(args, problem, tag):
    mesh, described = _mesh(problem, args.h, args.maxh, None, args.order, args.max_ndof)
    kind = "hp" if args.hp else "h"
    say(f"{problem.name}: P{args.order}, {kind}-adaptive from {described}, theta = {args.theta:g}")
    csv_path, png_path, forces_path, contact_path = outputs(args, tag)
    adaptation = adapt(problem, mesh, method=args.method, order=args.order, theta=args.theta,
                       max_levels=args.levels, max_ndof=args.max_ndof, tol=args.tol, rtol=args.rtol, solver=args.solver,
                       eta=args.eta,
                       solver_tol=args.solver_tol, max_seconds=args.max_seconds,
                       csv_path=csv_path, progress=say, hp=args.hp, max_order=args.max_order, weights=args.weights,
                       layers=args.layers, estimator=args.estimator)
    records = adaptation.levels
    slope = (records, args.order) if not args.hp and len(records) > 1 else None
    write_adaptive_png(png_path, f"{problem.name}: theta = {args.theta:g}", f"{adaptation.method} {kind}-adaptive",
                       records, adaptation.solution.mesh, slope)
    balance = report_forces(adaptation.solution, f"final solution ({records[-1]['ndof']} DOFs): forces on the body")
    write_forces(forces_path, contact_path, adaptation.solution, balance)
    say(f"wrote {csv_path}, {png_path}, {forces_path}, {contact_path}")
    if (args.tol is not None or args.rtol is not None) and adaptation.stopped != "tol":
        asked = " or ".join(f"--{name} {value:g}" for name, value in (("tol", args.tol), ("rtol", args.rtol))
                            if value is not None)
        raise NotReached(f"stopped before {asked} ({STOPS[adaptation.stopped]}): eta_h = "
                         f"{records[-1]['eta_h']:.4e} (target {records[-1]['target']:.4e}) after {len(records)} "
                         f"levels, {records[-1]['ndof']} DOFs")
    return records


COMMANDS = {"solve": cmd_solve, "uniform": cmd_uniform, "adaptive": cmd_adaptive}


def run(argv=None):
    """Run a command; returns its records (raises on bad input, see :func:`main`)."""
    args = build_parser().parse_args(argv)
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
    with warnings.catch_warnings():
        warnings.showwarning = lambda message, *_, **__: print(f"ngdgfric: warning: {message}", file=sys.stderr)
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
    stopped before its ``--tol`` (levels, DOFs, memory or time; its files are written); 130: interrupted.
    """
    try:
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
    except KeyboardInterrupt:
        return _fail("interrupted", 130)
    except Exception as exc:  # a bug: one line, not a traceback, unless asked for
        if os.environ.get("NGDGFRIC_TRACEBACK"):
            raise
        return _fail(f"internal error: {type(exc).__name__}: {exc} (NGDGFRIC_TRACEBACK=1 shows the traceback; "
                     f"please report it)", 3)
    return 0


def _fail(message, code):
    text = " ".join(str(message).split())
    print(f"ngdgfric: error: {text}", file=sys.stderr)
    return code
