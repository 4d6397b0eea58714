"""The commands of the command line (:mod:`ngdgfric.cli`): ``solve``, ``uniform`` and ``adaptive``.

Each ``cmd_*`` takes the parsed arguments, the problem and its tag (``load``), runs the library
(:func:`ngdgfric.solve`, ``ngdgfric.studies.uniform_study``, :func:`ngdgfric.adapt`), prints what it did and
writes its files (``outputs``, made by :mod:`ngdgfric.output`), each as soon as it is finished.  The progress
lines of the library come through the logger ``"ngdgfric"``, which ``ngdgfric.cli.run`` prints
(:mod:`ngdgfric.progress`).
"""

import itertools
import math
import time
from pathlib import Path

from .adaptivity import DEFAULT_RTOL, adapt
from .checks import check_size
from .estimator import estimate
from .examples import EXAMPLES, SCENES, example
from .files import write_csv, write_text
from .forces import force_balance
from .meshes import estimated_elements, grid_mesh, netgen_mesh, uniform_mesh
from .output import (
    rate_text,
    uniform_markdown,
    write_adaptive_png,
    write_contact_png,
    write_deformed_png,
    write_vtk,
)
from .problem_file import load_problem
from .reference import energy_norm
from .solution import solve
from .studies import uniform_study
from .studies.uniform import finest_elements

__all__ = ["COMMANDS", "cmd_solve", "cmd_uniform", "cmd_adaptive", "load", "outputs", "report_forces", "write_forces",
           "say", "NotReached", "NOT_REACHED", "DEFAULT_H"]

DEFAULT_H = 0.125
NOT_REACHED = 4  # the exit code of an adaptive run that stopped before --tol
STOPS = {"max_levels": "--levels reached", "max_ndof": "the next mesh would exceed --max-ndof",
         "memory": "the next mesh would exceed the memory budget", "max_seconds": "--max-seconds reached"}


class NotReached(Exception):
    """An adaptive run stopped before its --tol (its outputs are written)."""


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
    """(mesh, description) from --h / --maxh; the size is checked before meshing (``max_ndof``).  Without either:
    ``default`` None is adapt's first mesh (:func:`ngdgfric.adaptivity.initial_mesh`), a number the mesh size
    on domains of unit size, smaller ones scaled with their diameter (cells of sides at most it on a rectangle,
    :func:`~ngdgfric.meshes.grid_mesh`; Netgen's maxh otherwise)."""
    grid = False
    if maxh is None and h is None:
        if default is None:
            return None, "adapt's first mesh"
        size = default * min(1.0, problem.geometry.diameter())
        grid = problem.geometry.is_rectangle
        h, maxh = (size, None) if grid else (None, size)
    given = f"the default mesh (cells of sides at most {h:g})" if grid else \
        f"{'--maxh' if maxh is not None else '--h'} {maxh or h:g}"
    try:
        check_size(order, max_ndof, elements=estimated_elements(problem, h=h, maxh=maxh))
    except ValueError as exc:
        raise ValueError(f"{given}: {exc}") from None
    if grid:
        return grid_mesh(problem, h, max_elements=None), f"cells of sides at most {h:g}"
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
    record = dict(problem=problem.name, mesh=described, elements=mesh.ne, method=sol.method, order=sol.max_order,
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
    write_deformed_png(png_path, sol, args.scale, balance.sides())
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
    write_contact_png(png_path, sol, balance.sides())


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
        check_size(args.order, args.max_ndof, elements=finest_elements(problem, levels))
    except ValueError as exc:
        raise ValueError(f"--levels {args.levels}: {exc}") from None
    csv_path, md_path = outputs(args, tag)
    rows = []
    for method in args.method:
        say(f"{problem.name}: {method} P{args.order}, {args.solver}, uniform h = 2^-1 ... 2^-{levels[-1]}")
        study, solutions = uniform_study(problem, method, args.order, levels, solver=args.solver, eta=args.eta,
                                         solver_tol=args.solver_tol, max_ndof=args.max_ndof)
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
                       eta=args.eta, solver_tol=args.solver_tol, max_seconds=args.max_seconds, csv_path=csv_path,
                       hp=args.hp, max_order=args.max_order, variant=args.variant, layers=args.layers,
                       estimator=args.estimator)
    records = adaptation.levels
    slope = (records, args.order) if not args.hp and len(records) > 1 else None
    write_adaptive_png(png_path, f"{problem.name}: theta = {args.theta:g}", f"{adaptation.method} {kind}-adaptive",
                       records, adaptation.solution.mesh, slope)
    balance = report_forces(adaptation.solution, f"final solution ({records[-1]['ndof']} DOFs): forces on the body")
    write_forces(forces_path, contact_path, adaptation.solution, balance)
    say(f"wrote {csv_path}, {png_path}, {forces_path}, {contact_path}")
    if adaptation.stopped != "tol":
        reached = (f"({STOPS[adaptation.stopped]}): eta_h = {records[-1]['eta_h']:.4e} (target "
                   f"{records[-1]['target']:.4e}) after {len(records)} levels, {records[-1]['ndof']} DOFs")
        if args.tol is None and args.rtol is None:  # the default accuracy: said, not an error
            say(f"stopped before the default accuracy rtol = {DEFAULT_RTOL:g} {reached}; give --tol or --rtol to make "
                f"this an error (exit code {NOT_REACHED})")
        else:
            asked = " or ".join(f"--{name} {value:g}" for name, value in (("tol", args.tol), ("rtol", args.rtol))
                                if value is not None)
            raise NotReached(f"stopped before {asked} {reached}")
    return records


COMMANDS = {"solve": cmd_solve, "uniform": cmd_uniform, "adaptive": cmd_adaptive}
