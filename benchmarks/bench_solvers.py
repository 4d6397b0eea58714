"""Solver benchmark: a contact solve against the linear solve of the same problem, end to end.

Issue 12, item 7.  For Examples 6.1 and 6.2, SIPG, NIPG and Bassi et al. (a lifting method),
p = 1 and 2, uniform meshes h = 2^-2 ... 2^-7, and the final hp meshes of results/hp.md:

* contact: ``ndf.solve(problem, mesh, method, order)`` with the default solver, from zero (cold)
  and from the previous level's solution (warm, transfer included);
* linear: ``ndf.solve`` of the same problem without contact (c_tau = 0, g_a = 1e6): the headline
  ratio contact / linear is the one the issue defines;
* floor: assembly + one factorisation and back-substitution of A with NGSolve's fastest direct
  solver (sparsecholesky, umfpack for NIPG): a linear elasticity solve without any contact code;

everything end to end (assembly included), best of ``--repeat`` runs in one process.  Also the
parts of a contact solve (assembly, condensation onto the contact points, Newton at the points,
recovery of u) and Newton's iterations.  Writes results/solver_benchmark.md, .csv and .png.

With ``--long-side`` instead: many contact points, M = 1,000 ... 10,000 on a long contact side
(benchmarks/long_contact_side.py, results/long_contact_side.md).  With ``--levels-count``: Newton's iterations and the
contact solve against the linear solve level by level in adaptive runs (benchmarks/newton_levels.py,
results/newton_levels.md).

    python benchmarks/bench_solvers.py [--quick] [--repeat 2] [--budget SECONDS]
    python benchmarks/bench_solvers.py --long-side [--quick] [--points 2500 5000 10000] [--repeat 2]
    python benchmarks/bench_solvers.py --levels-count [--quick] [--scenes 6.1 rubber_pad ...] [--repeat 2]
"""

import re
import sys
import time
from pathlib import Path

import matplotlib
import ngsolve as ngs
import numpy as np

import ngdgfric as ndf
from ngdgfric.examples import EXAMPLES
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.sparse import direct_inverse
from ngdgfric.studies import max_rel_diff
from ngdgfric.threads import threads
from ngdgfric.transfer import WarmStart, multiplier_snapshot

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
import long_contact_side  # noqa: E402  (benchmarks/long_contact_side.py, beside this file)
import newton_levels  # noqa: E402  (benchmarks/newton_levels.py, beside this file)
from common import best, command_line, contact_free, run_script, save_figure, say, script_parser, write_csv  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SERIES = [(example, method, order) for example in ("6.1", "6.2") for method in ("sipg", "nipg", "bassi")
          for order in (1, 2)]
HP_EXAMPLES = ("6.1", "6.2")
HP_MAX_NDOF = 30_000  # the DOF budget of the hp runs of results/hp.md (scripts/hp.py --hp-max-ndof)
GOAL = 1.5  # contact / linear at every level with >= 1e4 DOFs


def parse(argv=None):
    parser = script_parser(__doc__, "two small series, no hp meshes (smoke test)")
    parser.add_argument("--levels", type=int, nargs="+", default=[2, 3, 4, 5, 6, 7], help="h = 2^-k")
    parser.add_argument("--repeat", type=int, default=2, help="runs per measurement (best is kept)")
    parser.add_argument("--budget", type=float, default=240.0, help="seconds per series before coarser levels stop")
    parser.add_argument("--long-side", action="store_true", help="the long contact side case alone (module docstring)")
    parser.add_argument("--levels-count", action="store_true",
                        help="Newton's iterations level by level in adaptive runs (benchmarks/newton_levels.py)")
    parser.add_argument("--scenes", nargs="+", choices=newton_levels.ALL_SCENES, help="with --levels-count: the scenes "
                        "(default: all)")
    long_contact_side.add_arguments(parser)
    return parser.parse_args(argv)


def floor_solve(problem, mesh, method, order):
    """Assembly + one factorisation and back-substitution with NGSolve's fastest direct solver."""
    disc = ndf.Discretization(problem, mesh, method=method, order=order)
    x = disc.F.CreateVector()
    with threads(disc.V.ndof):
        x.data = direct_inverse(disc.A, disc.symmetric) * disc.F
    return disc


def measure(problem, mesh, method, order, repeat, initial=None):
    """One row: cold, warm (if ``initial``), linear and floor, end to end."""
    cold_seconds, cold = best(repeat, lambda: ndf.solve(problem, mesh, method=method, order=order))
    free = contact_free(problem)
    linear_seconds, linear = best(repeat, lambda: ndf.solve(free, mesh, method=method, order=order))
    floor_seconds, _ = best(repeat, lambda: floor_solve(problem, mesh, method, order))
    parts = cold.info["timings"]
    row = dict(ndof=cold.ndof, contact_points=cold.info["contact_points"], linear_solver=cold.info["linear_solver"],
               cold=cold_seconds, linear=linear_seconds, floor=floor_seconds, ratio=cold_seconds / linear_seconds,
               floor_ratio=cold_seconds / floor_seconds, cold_its=cold.iterations,
               assemble=cold.timings["setup"], condense=parts["condense"], newton=parts["newton"],
               recover=parts["recover"], linear_its=linear.iterations)
    if initial is not None:
        warm_seconds, warm = best(repeat, lambda: ndf.solve(problem, mesh, method=method, order=order,
                                                            initial=initial))
        row.update(warm=warm_seconds, warm_ratio=warm_seconds / linear_seconds, warm_its=warm.iterations,
                   warm_difference=max_rel_diff(warm, cold))
    return row, cold


def run_series(example, method, order, levels, repeat, budget):
    problem = EXAMPLES[example]()
    rows, previous, spent = [], None, 0.0
    for k in levels:
        if spent > budget:
            say(f"  stop before h = 2^-{k}: time budget used")
            break
        start = time.perf_counter()
        mesh = ndf.uniform_mesh(problem, 2.0**-k)
        row, previous = measure(problem, mesh, method, order, repeat, initial=previous)
        row.update(example=example, method=method, order=order, mesh=f"h = 2^-{k}")
        rows.append(row)
        spent += time.perf_counter() - start
        report_row(row)
    return rows


def hp_row(example, repeat):
    """The final mesh of an hp-adaptive run (SIPG, p from 2 up to 8, theta = 0.3, the paper's estimator,
    HP_MAX_NDOF), with the previous level's solution kept for the warm start."""
    problem = EXAMPLES[example]()
    mesh = ndf.uniform_mesh(problem, 0.5)
    kept = {}

    def keep(level, sol, est):  # carry the last two levels' u through the refinements
        carrier = ngs.GridFunction(ngs.L2(mesh, order=8, autoupdate=True) ** 2, autoupdate=True)
        carrier.Set(sol.u)
        kept["previous"] = kept.get("current")
        kept["current"] = WarmStart(u=carrier, mesh=mesh, multiplier=multiplier_snapshot(sol))
        kept["orders"] = sol.discretization.orders.copy()

    run = ndf.adapt(problem, mesh, method="sipg", order=2, hp=True, max_order=8, max_levels=60,
                    max_ndof=HP_MAX_NDOF, rtol=0, variant="paper", theta=0.3, progress=None, keep=keep)
    row, _ = measure(problem, mesh, "sipg", kept["orders"], repeat, initial=kept["previous"])
    row.update(example=example, method="sipg", order=f"hp {kept['orders'].min()}-{kept['orders'].max()}",
               mesh=f"final hp mesh ({len(run.levels)} levels)")
    report_row(row)
    return row


def report_row(row):
    say(f"  {row['example']} {row['method']} P{row['order']} {row['mesh']}: {row['ndof']} dofs | contact "
        f"{row['cold']:.2f} s ({row['cold_its']} its) | linear {row['linear']:.2f} s | floor {row['floor']:.2f} s | "
        f"contact/linear {row['ratio']:.2f}, /floor {row['floor_ratio']:.2f} | warm "
        f"{row.get('warm', float('nan')):.2f} s ({row.get('warm_its', '-')} its, "
        f"{row.get('warm_ratio', float('nan')):.2f})")


def main(argv=None):
    args = parse(argv)
    if args.long_side:
        return long_contact_side.run(args)
    if args.levels_count:
        return newton_levels.run(args)
    series = [("6.1", "sipg", 1), ("6.2", "nipg", 1)] if args.quick else SERIES
    levels = [2, 3] if args.quick else args.levels
    rows = []
    for example, method, order in series:
        say(f"Example {example}, {method} P{order}")
        rows += run_series(example, method, order, levels, 1 if args.quick else args.repeat, args.budget)
    if not args.quick:
        for example in HP_EXAMPLES:
            say(f"Example {example}, final hp mesh")
            rows.append(hp_row(example, args.repeat))
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(args.out / "solver_benchmark.csv", rows,
              fields=["example", "method", "order", "mesh", "ndof", "contact_points", "linear_solver", "cold",
                      "cold_its", "warm", "warm_its", "warm_difference", "linear", "linear_its", "floor", "ratio",
                      "warm_ratio", "floor_ratio", "assemble", "condense", "newton", "recover"])
    plot(rows, args.out / "solver_benchmark.png")
    write_text(args.out / "solver_benchmark.md", report(rows))
    return rows


def plot(rows, path):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    uniform = [r for r in rows if r["mesh"].startswith("h")]
    for key in sorted({(r["example"], r["method"], r["order"]) for r in uniform}):
        subset = [r for r in uniform if (r["example"], r["method"], r["order"]) == key]
        label = f"{key[0]} {key[1]} P{key[2]}"
        axes[0].loglog([r["ndof"] for r in subset], [r["ratio"] for r in subset], "o-", label=label)
        axes[1].loglog([r["ndof"] for r in subset], [r["cold"] for r in subset], "o-", label=label)
    for r in rows:
        if not r["mesh"].startswith("h"):
            axes[0].loglog(r["ndof"], r["ratio"], "k*", markersize=12)
    axes[0].axhline(GOAL, color="gray", linestyle="--")
    axes[0].set_ylim(0.5, 4)
    axes[0].set(xlabel="DOFs", ylabel="contact solve / linear solve (end to end)",
                title="cost of contact (stars: final hp meshes)")
    axes[1].set(xlabel="DOFs", ylabel="seconds", title="contact solve, end to end")
    axes[0].legend(fontsize=7, ncol=2)
    save_figure(fig, path)


def mesh_text(label):
    """A mesh's label as the page shows it: ``h = 2^-k`` typeset."""
    return re.sub(r"h = 2\^-(\d+)", r"$h = 2^{-\1}$", label)


def report(rows):
    large = [r for r in rows if r["ndof"] >= 1e4]
    warm = [r for r in large if "warm" in r]
    worst = max(large, key=lambda r: r["ratio"]) if large else None
    worst_warm = max(warm, key=lambda r: r["warm_ratio"]) if warm else None
    lines = ["# Solver benchmark: contact solve against linear solve, end to end", "",
             "The contact solve (`ndf.solve` with the default solver) against a linear solve of the same system, end "
             "to end, on uniform and hp meshes of the paper's examples"
             + (f": on {len(large)} meshes of at least $10^4$ DOFs the contact solve takes at most "
                f"{worst['ratio']:.2f} times the seconds of the linear one." if large else "."), "",
             "![ratio against DOFs](solver_benchmark.png)", "",
             "Every time is end to end (problem to solution: assembly, contact solver, recovery), best of the "
             "runs in one process, 2 cores.  'contact' is `ndf.solve` with the default solver from zero, 'warm' "
             "from the previous level's solution (transfer included), 'linear' is `ndf.solve` of the same problem "
             "without contact ($c_\\tau = 0$, $g_a = 10^6$), 'floor' is assembly and one factorisation and solve of "
             "$A$ with NGSolve's fastest direct solver.  Ratios: contact / linear (the measure of the goal) and "
             "contact / floor.  The contact solve's parts: assembly, condensation onto the contact points (one PARDISO "
             "partial factorisation with the Schur complement, or NGSolve back-substitutions without mkl), "
             "Newton at the points, recovery of u.", "",
             "## Summary (computed)", ""]
    if large:
        lines += [f"- Levels with at least $10^4$ DOFs: {len(large)}; contact / linear at most {worst['ratio']:.2f} "
                  f"({worst['example']} {worst['method']} $P_{worst['order']}$, {mesh_text(worst['mesh'])}, "
                  f"{worst['ndof']} DOFs); "
                  f"{sum(r['ratio'] <= GOAL for r in large)} of {len(large)} within the goal {GOAL}.",
                  f"- Warm starts: contact / linear at most {worst_warm['warm_ratio']:.2f} "
                  f"({worst_warm['example']} {worst_warm['method']} $P_{worst_warm['order']}$, "
                  f"{mesh_text(worst_warm['mesh'])}); "
                  f"{sum(r['warm_ratio'] <= GOAL for r in warm)} of {len(warm)} within the goal; warm and cold "
                  f"solutions differ by at most {max(r['warm_difference'] for r in warm):.1e} (relative)."
                  if warm else "- No warm starts measured.",
                  f"- Against the floor (a plain linear solve without contact code): contact / floor between "
                  f"{min(r['floor_ratio'] for r in large):.2f} and {max(r['floor_ratio'] for r in large):.2f}.",
                  f"- Newton iterations at the points from zero: median {np.median([r['cold_its'] for r in large]):g}, "
                  f"at most {max(r['cold_its'] for r in large)}; from the previous level: at most "
                  f"{max((r['warm_its'] for r in warm), default=0)}.  Each costs a dense solve with one row per "
                  "penetrating or sticking point: Newton's share of the contact solve is at most "
                  f"{max(r['newton'] / r['cold'] for r in large):.1%}.", ""]
    case = ["example", "method", "$p$", "mesh"]

    def cells(r):
        return [r["example"], r["method"], r["order"], mesh_text(r["mesh"])]

    lines += ["## The ratios", "", markdown_table(
        case + ["DOFs", "contact points", "contact / linear", "warm / linear", "contact / floor"],
        [cells(r) + [r["ndof"], r["contact_points"], f"{r['ratio']:.2f}",
                     f"{r['warm_ratio']:.2f}" if "warm" in r else "-", f"{r['floor_ratio']:.2f}"] for r in rows]), "",
        "## The seconds (and Newton iterations)", "", markdown_table(
        case + ["contact (iterations)", "warm (iterations)", "linear", "floor"],
        [cells(r) + [f"{r['cold']:.3f} ({r['cold_its']})",
                     f"{r['warm']:.3f} ({r.get('warm_its', '-')})" if "warm" in r else "-",
                     f"{r['linear']:.3f}", f"{r['floor']:.3f}"] for r in rows]), "",
        "## Where the contact solve's seconds go", "", markdown_table(
        case + ["assembly", "condensation", "Newton", "recovery"],
        [cells(r) + [f"{r['assemble']:.3f}", f"{r['condense']:.3f}", f"{r['newton']:.3f}", f"{r['recover']:.3f}"]
         for r in rows]), "",
        f"Regenerate: `{command_line()}` (run alone: timings on a busy machine are meaningless).", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    run_script(main)
