"""Many contact points: the contact solve against the linear solve on a long contact side, M = 2,500 ... 10,000.

The scene: a strip 8 x 1/16 (``long_strip``) pressed down and sheared by its top (u_D = (0.002,
-0.001), E = 2500, nu = 0.2) onto a compliant foundation along its long side (c_n = 1e4, m_n = 1, g_a = 0, Tresca
friction c_tau = 25: stick in the middle, slip towards the ends), conforming P4 (adapt's default discretisation;
p = 4 contact points per edge) on grid meshes with 8 / h = M / 4 cells along Gamma_C.  Per M:

* contact, cold: ``ndf.solve`` with the default solver from zero (from FULL_SPACE_POINTS points the full-space
  semismooth Newton, :mod:`ngdgfric.solvers.fullspace`);
* contact, warm: from the solution at M / 2 on the mesh that one uniform refinement in place turns into this one,
  u prolongated by NGSolve and the multiplier as Gauss values (as adapt starts a level: :class:`ndf.WarmStart`);
* linear: the same matrix without the contact terms, A, assembled, analysed, factorised and solved by the same
  PARDISO (:class:`ngdgfric.solvers.pardiso.Factorization`); end to end (assembly included) as the contact solves;
* condensed: the Delassus solver (``formulation="condensed"``) up to ``--condensed-max`` points, for the cross-over;

best of ``--repeat`` runs in one process, with PARDISO's peak memory of the factorisation (its iparm[14..16]) and
the Delassus operator's 32 M^2 bytes.  Writes results/long_contact_side.md and .csv.  Run through the solver
benchmark:

    python benchmarks/bench_solvers.py --long-side [--quick] [--points 2500 5000 10000] [--repeat 2]

``--report-only`` measures nothing: it rewrites long_contact_side.md from the long_contact_side.csv in --out
(after a change of the report's text; the timings stay those of the run that wrote the CSV):

    python benchmarks/bench_solvers.py --long-side --report-only
"""

import dataclasses
import sys
import time
from pathlib import Path

import ngsolve as ngs
import numpy as np

import ngdgfric as ndf
from ngdgfric.files import write_text
from ngdgfric.meshes import grid_mesh
from ngdgfric.output import markdown_table
from ngdgfric.solvers.condensation import _csr
from ngdgfric.solvers.fullspace import FULL_SPACE_POINTS
from ngdgfric.solvers.pardiso import Factorization
from ngdgfric.transfer import interpolate, multiplier_snapshot

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
from common import best, command_line, read_csv, say, write_csv  # noqa: E402

METHOD, ORDER = "cg", 4  # contact points per edge: ORDER (conforming)
MAX_NDOF = 4_000_000  # M = 10,000: 1.6 million DOFs (the default memory model, made for DG, refuses them)
FIELDS = ["points", "ndof", "cold", "cold_its", "cold_factorizations", "warm", "warm_its", "warm_factorizations",
          "linear", "linear_solver_only", "cold_ratio", "warm_ratio", "assembly", "contact_bytes", "linear_bytes",
          "delassus_bytes", "condensed", "condensed_its", "difference", "formulation"]


def long_strip(length=8.0, height=1 / 16):
    """The scene of the module docstring."""
    base = ndf.example_6_2()
    geometry = ndf.Polygon(((0, 0), (length, 0), (length, height), (0, height)),
                           ("contact", "traction", "dirichlet", "traction"))
    return dataclasses.replace(base, name="long strip", geometry=geometry, g=(0.0, 0.0), u_D=(0.002, -0.001),
                               c_n=1e4, c_tau=25.0)


def mesh_for(problem, points):
    """The grid mesh with points / ORDER cells along the contact side."""
    return grid_mesh(problem, 8.0 / (points / ORDER))


def linear_solve(problem, mesh):
    """(seconds of the factorisation and solve alone, PARDISO's bytes): A assembled, analysed, factorised, solved."""
    disc = ndf.Discretization(problem, mesh, method=METHOD, order=ORDER, max_ndof=MAX_NDOF)
    start = time.perf_counter()
    indptr, cols, values = _csr(disc.A)
    rows = np.repeat(np.arange(disc.A.height), np.diff(indptr))
    upper = cols >= rows
    upper_indptr = np.concatenate([[0], np.cumsum(np.bincount(rows[upper], minlength=disc.A.height))])
    factorization = Factorization(upper_indptr, cols[upper], values[upper])
    factorization.factor(values[upper])
    factorization.solve(disc.F.FV().NumPy())
    seconds, memory = time.perf_counter() - start, factorization.memory_bytes
    factorization.release()
    return seconds, memory


def refined_with_warm_start(problem, points):
    """(the mesh of ``points`` contact points made by refining that of points / 2 in place, the warm start from the
    solution there), as :class:`ngdgfric.levels.AdaptiveLoop` hands a level on."""
    mesh = mesh_for(problem, points // 2)
    coarse = ndf.solve(problem, mesh, method=METHOD, order=ORDER, max_ndof=MAX_NDOF)
    carrier = ngs.GridFunction(ngs.L2(mesh, order=ORDER, autoupdate=True) ** 2, autoupdate=True)
    interpolate(carrier, coarse.u)
    multiplier = multiplier_snapshot(coarse)
    del coarse
    mesh.Refine()
    return mesh, ndf.WarmStart(u=carrier, mesh=mesh, multiplier=multiplier)


def measure(problem, points, repeat, condensed_max):
    """One row (module docstring); returns (row, the cold solution)."""
    mesh, previous = refined_with_warm_start(problem, points)
    cold_seconds, cold = best(repeat, lambda: ndf.solve(problem, mesh, method=METHOD, order=ORDER, max_ndof=MAX_NDOF))
    linear_seconds, (solver_only, linear_bytes) = best(repeat, lambda: linear_solve(problem, mesh))
    row = dict(points=cold.info["contact_points"], ndof=cold.ndof, cold=cold_seconds, cold_its=cold.iterations,
               cold_factorizations=cold.info.get("factorizations", 1), linear=linear_seconds,
               linear_solver_only=solver_only, cold_ratio=cold_seconds / linear_seconds,
               assembly=cold.timings["setup"], contact_bytes=cold.info.get("factor_bytes", float("nan")),
               linear_bytes=linear_bytes, delassus_bytes=32.0 * cold.info["contact_points"] ** 2,
               formulation=cold.info["linear_solver"])
    warm_seconds, warm = best(repeat, lambda: ndf.solve(problem, mesh, method=METHOD, order=ORDER,
                                                        initial=previous, max_ndof=MAX_NDOF))
    row.update(warm=warm_seconds, warm_its=warm.iterations, warm_factorizations=warm.info.get("factorizations", 1),
               warm_ratio=warm_seconds / linear_seconds)
    if points <= condensed_max:
        condensed_seconds, condensed = best(repeat, lambda: ndf.solve(problem, mesh, method=METHOD, order=ORDER,
                                                                      formulation="condensed"))
        row.update(condensed=condensed_seconds, condensed_its=condensed.iterations,
                   difference=ndf.energy_norm(condensed, cold.u) / ndf.energy_norm(condensed))
    return row, cold


def add_arguments(parser):
    """The options of this case in the solver benchmark's parser."""
    parser.add_argument("--points", type=int, nargs="+", default=[1000, 2500, 5000, 10000],
                        help="--long-side: the numbers of contact points M")
    parser.add_argument("--condensed-max", type=int, default=5000,
                        help="--long-side: run the condensed solver up to this many points (its W needs 32 M^2 bytes)")
    parser.add_argument("--report-only", action="store_true",
                        help="--long-side: measure nothing; rewrite long_contact_side.md from the "
                             "long_contact_side.csv in --out")


def run(args):
    """The rows of the long-side case for the parsed ``args`` of benchmarks/bench_solvers.py, written to
    ``args.out`` (with ``--report-only``: the rows of the CSV there, its Markdown rewritten from them)."""
    if getattr(args, "report_only", False):
        return rewrite_report(args.out)
    points = [500, 1000] if args.quick else args.points
    repeat = 1 if args.quick else args.repeat
    problem, rows = long_strip(), []
    args.out.mkdir(parents=True, exist_ok=True)
    for m in points:
        row, _ = measure(problem, m, repeat, args.condensed_max)
        rows.append(row)
        say(f"M = {row['points']}: {row['ndof']} DOFs, contact {row['cold']:.2f} s ({row['cold_its']} its, "
            f"{row['cold_factorizations']} factorisations), warm {row['warm']:.2f} s, linear {row['linear']:.2f} s: "
            f"{row['cold_ratio']:.2f} / {row['warm_ratio']:.2f}; condensed {row.get('condensed', float('nan')):.2f} s")
        write_csv(args.out / "long_contact_side.csv", rows, FIELDS)
        write_text(args.out / "long_contact_side.md", report(rows))
    return rows


def rewrite_report(out):
    """long_contact_side.md in ``out`` rewritten from the long_contact_side.csv there, nothing measured; its
    'Regenerate' line names the measuring command (this one without --report-only)."""
    rows = read_csv(out / "long_contact_side.csv")
    command = " ".join(word for word in command_line().split(" ") if word != "--report-only")
    write_text(out / "long_contact_side.md", report(rows, command))
    say(f"{out / 'long_contact_side.md'} rewritten from {len(rows)} rows of {out / 'long_contact_side.csv'}")
    return rows


def _f(row, key, spec=".2f"):
    value = row.get(key)
    return "-" if value is None or value != value else format(value, spec)


SETTING = """\
The scene: a strip $8 \\times 1/16$ (`long_strip`) pressed down and sheared by its top ($u_D = (0.002, -0.001)$,
$E = 2500$, $\\nu = 0.2$) onto a compliant foundation along its long side ($c_n = 10^4$, $m_n = 1$, $g_a = 0$, Tresca
friction $c_\\tau = 25$: stick in the middle, slip towards the ends), conforming $P_4$ (adapt's default
discretisation; $p = 4$ contact points per edge) on grid meshes with $8 / h = M / 4$ cells along $\\Gamma_C$.  Per
$M$: the contact solve from zero (cold) and from the solution at $M / 2$ prolongated as `adapt` starts a level
(warm); the linear solve of the same matrix without the contact terms by the same PARDISO, end to end as the contact
solves; and the Delassus solver (`formulation=\"condensed\"`) up to `--condensed-max` points, for the cross-over.
Best of `--repeat` runs in one process, with PARDISO's peak memory of the factorisation and the Delassus operator's
$32 M^2$ bytes."""
"""The setting of the page (Markdown)."""


def report(rows, command=None):
    """The Markdown of ``rows``; ``command``: the one to name as regenerating it (default: this process's)."""
    ratios = [r["cold_ratio"] for r in rows]
    lines = ["# Many contact points: contact solve against linear solve on a long contact side", "",
             f"The contact solve on one long contact side with $M$ = {min(r['points'] for r in rows)} to "
             f"{max(r['points'] for r in rows)} contact points against the linear solve of the same matrix: it takes "
             f"{min(ratios):.2f} to {max(ratios):.2f} times the linear solve's seconds from zero, and its "
             "factorisation needs about the memory of the linear one, while the dense Delassus "
             "operator's grows like $M^2$.", "",
             SETTING, "",
             f"The default formulation switches to the full space from `FULL_SPACE_POINTS` = {FULL_SPACE_POINTS} "
             "contact points.  Times in seconds, end to end (assembly included); ratios: contact / linear; memory "
             "in MB.", "",
             "## Contact against linear", ""]
    lines += [markdown_table(
        ["$M$", "DOFs", "solver", "contact s (iterations, factorisations)", "warm s (iterations, factorisations)",
         "linear s", "of it factorisation and solve", "cold / linear", "warm / linear"],
        [[r["points"], r["ndof"], r["formulation"], f"{r['cold']:.2f} ({r['cold_its']}, {r['cold_factorizations']})",
          f"{_f(r, 'warm')} ({r.get('warm_its', '-')}, {r.get('warm_factorizations', '-')})", f"{r['linear']:.2f}",
          f"{r['linear_solver_only']:.2f}", f"{r['cold_ratio']:.2f}", _f(r, "warm_ratio")] for r in rows]), "",
        "## The condensed formulation and the memory", "",
        markdown_table(
        ["$M$", "condensed s (iterations)", "condensed against the default (energy, relative)",
         "PARDISO MB, contact / linear", "$W$ would need MB"],
        [[r["points"], f"{_f(r, 'condensed')} ({r.get('condensed_its', '-')})", _f(r, "difference", ".1e"),
          f"{_f({'v': r['contact_bytes'] / 1e6}, 'v', '.0f')} / {r['linear_bytes'] / 1e6:.0f}",
          f"{r['delassus_bytes'] / 1e6:.0f}"] for r in rows]), "",
        f"Regenerate: `{command or command_line()}` (run alone: timings on a busy machine are meaningless).", ""]
    return "\n".join(lines)
