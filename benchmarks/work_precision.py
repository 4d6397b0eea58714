"""Accuracy against run time: every method x order x strategy x solver, against the reference solutions.

For each example: the true error |||u_ref - u_h|||_h (results/reference_<example>.npz) against wall
time and against DOFs for the five methods, P1-P3, uniform / h-adaptive / hp-adaptive refinement
(:func:`ngdgfric.studies.strategy_run`) and Newton / Uzawa; the Pareto front (no other run is both
faster and more accurate) marked.  What each tolerance on the paper's eta_h (``variant="paper"``) costs
per strategy.
Cases run through dask.distributed with a cache (:mod:`ngdgfric.studies.runner`).  Writes
results/work_precision_<example>.png / _dofs.png / .csv and results/work_precision.md.

    python benchmarks/work_precision.py [--quick] [--scheduler ADDRESS] [--workers N]
"""

import sys
from pathlib import Path

import matplotlib
import numpy as np

from ngdgfric.dg.methods import DG_METHODS
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.studies.cases import precision_case
from ngdgfric.studies.runner import run_cases

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
from common import RESULTS, command_line, run_script, save_figure, say, script_parser, write_csv  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = {"uniform": "s", "h": "o", "hp": "D"}
LINES = {"newton": "-", "uzawa": "--"}
TOLERANCES = (100.0, 10.0, 1.0)


def parse(argv=None):
    parser = script_parser(__doc__, "SIPG P1 with small budgets (smoke test)", example="many")
    parser.add_argument("--newton-ndof", type=int, default=30_000, help="DOF budget per Newton run")
    parser.add_argument("--uzawa-ndof", type=int, default=5_000, help="DOF budget per Uzawa run")
    parser.add_argument("--scheduler", default=None)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--cache", type=Path, default=Path(".cache/work_precision"))
    return parser.parse_args(argv)


def case_list(example, args):
    reference = str((RESULTS / f"reference_{example.replace('.', '_')}.npz").resolve())
    methods, orders = (["sipg"], [1]) if args.quick else (sorted(DG_METHODS), [1, 2, 3])
    budget = dict(newton=1500, uzawa=800) if args.quick else dict(newton=args.newton_ndof, uzawa=args.uzawa_ndof)
    out = []
    for method in methods:
        for solver in ("newton", "uzawa"):
            runs = [(s, p) for s in ("uniform", "h") for p in orders] + [("hp", 2)]
            out += [dict(example=example, method=method, order=p, strategy=s, solver=solver, max_ndof=budget[solver],
                         reference=reference) for s, p in runs]
    return out


def name(run):
    strategy = {"uniform": "uniform", "h": "h-adaptive", "hp": "hp-adaptive"}[run["strategy"]]
    order = "" if run["strategy"] == "hp" else f" P{run['order']}"
    return f"{run['method']} {strategy}{order} {run['solver']}"


def pareto(points):
    """Indices of the points (seconds, error) not dominated by another (faster and more accurate)."""
    order = np.lexsort((points[:, 1], points[:, 0]))
    front, best = [], np.inf
    for i in order:
        if points[i, 1] < best:
            front.append(i)
            best = points[i, 1]
    return front


def plot(example, runs, out):
    colours = dict(zip(sorted(DG_METHODS), plt.rcParams["axes.prop_cycle"].by_key()["color"], strict=False))
    for key, suffix, xlabel in (("seconds", "", "wall time (s)"), ("ndof", "_dofs", "degrees of freedom")):
        fig, ax = plt.subplots(figsize=(9, 6.5))
        points = []
        for run in runs:
            records = run["records"]
            if not records:
                continue
            x = [r[key] for r in records]
            y = [r["error"] for r in records]
            points += list(zip(x, y, strict=True))
            ax.loglog(x, y, color=colours[run["method"]], marker=MARKERS[run["strategy"]], markersize=3,
                      linestyle=LINES[run["solver"]], alpha={1: 0.45, 2: 0.7, 3: 1.0}[run["order"]], linewidth=1)
        points = np.array(points)
        front = points[pareto(points)]
        ax.loglog(front[:, 0], front[:, 1], "k-", linewidth=2.5, alpha=0.35, label="Pareto front")
        handles = [plt.Line2D([], [], color=c, label=m) for m, c in colours.items()]
        handles += [plt.Line2D([], [], color="gray", marker=mk, linestyle="", label=s) for s, mk in MARKERS.items()]
        handles += [plt.Line2D([], [], color="gray", linestyle=ls, label=s) for s, ls in LINES.items()]
        handles += [plt.Line2D([], [], color="k", linewidth=2.5, alpha=0.35, label="Pareto front")]
        ax.legend(handles=handles, fontsize=8, ncol=2, title="colour: method, marker: strategy, line: solver; "
                  "faint -> solid: P1 -> P3", title_fontsize=7)
        ax.set(xlabel=xlabel, ylabel="true error $|||u_{ref} - u_h|||_h$", title=f"Example {example}")
        ax.grid(True, which="both", alpha=0.3)
        save_figure(fig, out / f"work_precision_{example.replace('.', '_')}{suffix}.png", dpi=100)


def cheapest(runs, key, target, value="seconds"):
    """(run name, cost) of the run reaching ``key`` <= target at the smallest ``value``."""
    best = None
    for run in runs:
        for r in run["records"]:
            if r[key] <= target:
                if best is None or r[value] < best[1]:
                    best = (name(run), r[value], r["ndof"], r["seconds"])
                break
    return best


def summary(example, runs):
    errors = sorted({e for run in runs for e in [r["error"] for r in run["records"]]})
    targets = [t for t in (1.0, 0.3, 0.1, 0.03, 0.01, 1e-3) if errors and t >= errors[0]]
    rows = []
    for target in targets:
        fast, small = cheapest(runs, "error", target), cheapest(runs, "error", target, "ndof")
        rows.append([f"{target:g}", fast[0], f"{fast[1]:.2f}", fast[2], small[0], small[2], f"{small[3]:.2f}"])
    lines = [f"## Example {example}", "",
             f"![error vs time](work_precision_{example.replace('.', '_')}.png)"
             f" ![error vs DOFs](work_precision_{example.replace('.', '_')}_dofs.png)", "",
             "Cheapest run to reach each true error (first level at or below it):", "",
             markdown_table(["error <=", "fastest run", "s", "its DOFs", "fewest DOFs", "DOFs", "its s"], rows), ""]
    tol_rows = []
    for strategy in ("uniform", "h", "hp"):
        for tol in TOLERANCES:
            mine = [run for run in runs if run["strategy"] == strategy and run["solver"] == "newton"]
            best = cheapest(mine, "eta_h", tol)
            tol_rows.append([strategy, f"{tol:g}"] + (["-", "-", "-"] if best is None else
                                                      [best[0], best[2], f"{best[3]:.2f}"]))
    lines += ["What `adapt(tol=..., variant=\"paper\")` (or a uniform mesh fine enough) costs for eta_h <= tol "
              "(the paper's estimator), Newton, cheapest method "
              "and order per strategy:", "",
              markdown_table(["strategy", "eta_h tol", "run", "DOFs", "s"], tol_rows), ""]
    return lines, rows


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    lines = ["# Accuracy against run time", "",
             "True error |||u_ref - u_h|||_h against the hp reference solutions (results/reference.md).  Uniform: "
             "the cold solve on that mesh alone; adaptive: cumulative solve + estimate + mark + refine.  "
             f"DOF budgets: Newton {args.newton_ndof}, Uzawa {args.uzawa_ndof} (Uzawa's iteration counts make "
             "larger runs impractical).  Timings on a shared 2-core machine, two cases at a time.", ""]
    for example in args.example:
        cases = case_list(example, args)
        say(f"Example {example}: {len(cases)} runs")
        runs = run_cases(precision_case, cases, cache=args.cache, scheduler=args.scheduler, workers=args.workers,
                         progress=say)
        write_csv(args.out / f"work_precision_{example.replace('.', '_')}.csv",
                  [dict(run=name(run), **r) for run in runs for r in run["records"]],
                  ["run", "level", "ndof", "eta_h", "error", "seconds", "iterations", "p_max"])
        failed = [name(run) + ": " + run["status"] for run in runs if run["status"] != "converged"]
        plot(example, runs, args.out)
        section, _ = summary(example, runs)
        lines += section + ([f"Failed runs: {'; '.join(failed)}", ""] if failed else [])
    lines += [f"Regenerate: `{command_line()}`", ""]
    write_text(args.out / "work_precision.md", "\n".join(lines))
    say("\n".join(lines))


if __name__ == "__main__":
    run_script(main)
