"""Accuracy against run time: each method's Pareto front of (seconds, true error) on Examples 6.1 and 6.2.

What is measured.  For each example and each method of ``ngdgfric.METHODS`` (the five DG methods of Section 3 and
the conforming ``cg``), with Newton's solver (the default), one run at a time in this one process:

* uniform meshes h = 2^-1, 2^-2, ... in degree p = 1-4, h halved while the method's V_h stays within the DOF budget;
  seconds = the cold solve on that mesh alone (a user who knows h solves once);
* h-adaptive: ``adapt(problem, method=m, hp=False, order=p)`` for p = 1-3, its other defaults;
* hp-adaptive: ``adapt(problem, method=m)`` with its defaults (hp from p = 4 up to 8, theta = 0.8);

the adaptive runs stop at the DOF budget or at eta_h <= 1e-4 (the smallest target; eta_h, the default estimator in
energy units, is above the true error), and their seconds are the cumulative solve + estimate + mark + refine up to
the level (:func:`ngdgfric.studies.strategy_run`).  Beside them: the conforming baseline of benchmarks/conforming.py
(its own H1 code, p = 3 and 4, up to twice the budget: of fixed degree, it needs more DOFs for 1e-4) and what
``ndf.adapt(problem, tol=t)`` with every default delivers for t = 1e-1 ... 1e-4 (the seconds of the whole loop, the
true error of its answer).  True error:
|||u_ref - u_h|||_h (``ndf.energy_error``) against the hp references results/reference_6_1.npz and
reference_6_2.npz, evaluated outside the timing.  Seconds are wall seconds; a run that took under ``CHEAP``
seconds is repeated up to ``--repeat`` times and each level keeps its fastest.  A run whose solver fails is
recorded as failed, not fatal.

Writes results/work_precision.png (one panel per example: per method the Pareto front over its strategies and
orders, the raw points faint; the baseline dashed, adapt's default as stars), work_precision_dofs.png (the same
against DOFs), work_precision.csv (every point) and work_precision.md (the cheapest run per target error).

    python benchmarks/work_precision.py [--quick] [--example 6.1 ...] [--budget DOFS] [--repeat N]
"""

import functools
import inspect
import os
import shlex
import sys
import time
from pathlib import Path

import matplotlib
import numpy as np

import ngdgfric as ndf
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.studies import strategy_run

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
import conforming  # noqa: E402  (benchmarks/conforming.py, the baseline, beside this file)
from common import RESULTS, run_script, save_figure, say, script_parser, write_csv  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# ----------------------------------------------------------------------------------------- PARAMETERS
TARGETS = (1e-1, 1e-2, 1e-3, 1e-4)   # true errors of the table; the stored references resolve 1e-4
ADAPT_ORDER = inspect.signature(ndf.adapt).parameters["order"].default  # hp runs start where adapt does
RUNS = (("uniform", (1, 2, 3, 4)), ("h", (1, 2, 3)), ("hp", (ADAPT_ORDER,)))
BASELINE_ORDERS = (3, 4)             # conforming.py: p = 2 is never the fastest (benchmarks/README.md)
BUDGET = 62_000                      # DOFs: hp reaches 1e-4 within it on both examples (6.1: 55,962-58,968 DOFs but
                                     # NIPG, whose eta_h stalls), uniform P4 has h = 1/16; 22 min at 70,000, loaded
BASELINE_BUDGET = 2                  # x BUDGET: with its fixed degree the baseline needs 75,000-80,000 DOFs for 1e-4
CHEAP = 2.0                          # runs faster than this many wall seconds are repeated (--repeat)
QUICK = dict(budget=6000, methods=("sipg", "cg"), tols=(1e-1,))
FIELDS = ["example", "method", "strategy", "p", "tol", "level", "ndof", "seconds", "error", "eta_h", "p_max"]
BASELINE, DEFAULT = "baseline", "adapt default"
STRATEGY_NAMES = {"uniform": "uniform", "h": "h-adaptive", "hp": "hp-adaptive"}


def parse(argv):
    parser = script_parser(__doc__, "the first --example only, SIPG and cg, a DOF budget of "
                                    f"{QUICK['budget']}, adapt's default at tol = 1e-1 (for the tests)", example="many")
    parser.add_argument("--budget", type=int, default=None, help=f"DOFs per run (default {BUDGET})")
    parser.add_argument("--repeat", type=int, default=3, help=f"runs under {CHEAP} s: the fastest of this many")
    args = parser.parse_args(argv)
    if args.budget is None:
        args.budget = QUICK["budget"] if args.quick else BUDGET
    return args


# ----------------------------------------------------------------------------------------- RUNS
def fastest(repeat, measure):
    """(records, failure) of ``measure()`` (a list of records with ``seconds``, or a SolverError); when the first
    call took under CHEAP wall seconds, up to ``repeat`` calls, each level at its fastest (levels of the same DOFs)."""
    start = time.perf_counter()
    try:
        records = measure()
    except ndf.SolverError as error:
        return [], str(error).splitlines()[0][:160]
    if time.perf_counter() - start < CHEAP:
        for _ in range(repeat - 1):
            again = measure()
            if [r["ndof"] for r in again] != [r["ndof"] for r in records]:
                say("  a repeat took other levels: the first run is kept")
                break
            for record, other in zip(records, again, strict=True):
                record["seconds"] = min(record["seconds"], other["seconds"])
    return records, None


def method_run(problem, reference, method, strategy, order, budget):
    """The records of one strategy of ``method`` in degree ``order`` (module docstring), eta_h of the default
    estimator."""
    adaptive = {} if strategy == "uniform" else dict(tol=min(TARGETS))
    if strategy == "hp":
        adaptive["max_order"] = None  # adapt's default
    records = strategy_run(problem, strategy, method=method, order=order, reference=reference, max_ndof=budget,
                           progress=None, **adaptive)
    return [dict(level=r["level"], ndof=r["ndof"], seconds=r["seconds"], error=r["error"], eta_h=r["eta_h"],
                 p_max=r.get("p_max", order)) for r in records]


def baseline_run(problem, reference, order, budget):
    """The levels of benchmarks/conforming.py in degree ``order`` up to BASELINE_BUDGET x ``budget`` DOFs (its rule:
    it stops when a level has more than 1 / 1.1 of it) or to the smallest target."""
    try:
        _, history = conforming.time_to_targets(problem, order, TARGETS, reference,
                                                max_ndof=BASELINE_BUDGET * budget)
    except (ValueError, NotImplementedError, RuntimeError) as error:  # its own solver's failures
        raise ndf.SolverError(f"conforming.py: {error}") from error
    return [dict(level=level, ndof=ndof, seconds=seconds, error=error, eta_h=eta_h, p_max=order)
            for level, ndof, seconds, error, eta_h, _ in history]


def default_run(problem, reference, tol):
    """``ndf.adapt(problem, tol=tol)`` with every default: one record, its answer (seconds: the whole loop)."""
    run = ndf.adapt(problem, tol=tol, progress=None)
    seconds = sum(r["solve_seconds"] + r["estimate_seconds"] + r["mark_refine_seconds"] for r in run.levels)
    return [dict(level=len(run.levels) - 1, ndof=run.solution.ndof, seconds=seconds, eta_h=run.estimate.eta_h,
                 error=ndf.energy_error(run.solution, reference), p_max=run.levels[-1]["p_max"], chose=run.method)]


def cases(methods, tols):
    """(method, strategy, p or tol, label) of every run of one example, cheapest kinds first."""
    out = [(m, s, p, f"{m} {STRATEGY_NAMES[s]} p{p}") for m in methods for s, orders in RUNS for p in orders]
    out += [(BASELINE, "conforming.py", p, f"conforming.py p{p}") for p in BASELINE_ORDERS]
    return out + [(DEFAULT, "hp", tol, f"adapt(problem, tol={tol:g})") for tol in tols]


def study(example, args):
    """The runs of one example: dicts of method, strategy, p, tol, label, records, failure."""
    problem = ndf.example(example)
    reference = ndf.load_reference(RESULTS / f"reference_{example.replace('.', '_')}.npz", problem)
    methods, tols = (QUICK["methods"], QUICK["tols"]) if args.quick else (tuple(ndf.METHODS), TARGETS)
    runs = []
    for method, strategy, value, label in cases(methods, tols):
        if method == DEFAULT:
            measure = functools.partial(default_run, problem, reference, value)
        elif method == BASELINE:
            measure = functools.partial(baseline_run, problem, reference, value, args.budget)
        else:
            measure = functools.partial(method_run, problem, reference, method, strategy, value, args.budget)
        records, failure = fastest(args.repeat, measure)
        tol = value if method == DEFAULT else None
        runs.append(dict(method=method, strategy=strategy, p=None if tol else value, tol=tol, label=label,
                         records=records, failure=failure))
        last = records[-1] if records else None
        levels = len(records) if method != DEFAULT or not records else last["level"] + 1  # the default: its answer
        say(f"{example} {label}: " + (f"failed: {failure}" if failure else
                                      f"{levels} levels, {last['ndof']} DOFs, error {last['error']:.3e}, "
                                      f"{last['seconds']:.2f} s"))
    return runs


def points(runs):
    """The CSV rows of ``runs`` (one per level); adapt's default: strategy "hp (<the method it chose>)"."""
    rows = []
    for run in runs:
        for record in run["records"]:
            record = dict(record)
            chose = record.pop("chose", None)
            rows.append(dict(method=run["method"], strategy=run["strategy"] if chose is None else f"hp ({chose})",
                             p=run["p"], tol=run["tol"], **record))
    return rows


# ----------------------------------------------------------------------------------------- FRONTS
def pareto(xy):
    """Indices of the rows (x, error) of ``xy`` that no other row beats in both (x at most, error below), by
    increasing x and so decreasing error."""
    order = np.lexsort((xy[:, 1], xy[:, 0]))
    front, best = [], np.inf
    for i in order:
        if xy[i, 1] < best:
            front.append(int(i))
            best = xy[i, 1]
    return front


def front(rows, key="seconds"):
    """The rows of one method's Pareto front of (``key``, error), by increasing ``key``."""
    if not rows:
        return []
    return [rows[i] for i in pareto(np.array([[r[key], r["error"]] for r in rows], dtype=float))]


def groups(rows):
    """{name: rows}: the methods of ngdgfric.METHODS that ran, then the baseline and adapt's default."""
    names = [m for m in ndf.METHODS if any(r["method"] == m for r in rows)] + [BASELINE, DEFAULT]
    return {name: [r for r in rows if r["method"] == name] for name in names}


# ----------------------------------------------------------------------------------------- PLOT
def plot(study_rows, path, key="seconds"):
    """One panel per example: per method its front (line) and raw points (faint dots); the baseline's front
    dashed black, adapt's default as black stars."""
    colours = dict(zip(ndf.METHODS, plt.rcParams["axes.prop_cycle"].by_key()["color"], strict=False))
    fig, axes = plt.subplots(1, len(study_rows), figsize=(5.6 * len(study_rows), 4.8), squeeze=False,
                             sharey=True)
    for ax, (example, rows) in zip(axes[0], study_rows.items(), strict=True):
        for name, mine in groups(rows).items():
            if not mine:
                continue
            best = front(mine, key)
            x, y = [r[key] for r in best], [r["error"] for r in best]
            if name == DEFAULT:
                ax.loglog([r[key] for r in mine], [r["error"] for r in mine], "k*", markersize=11,
                          label="adapt(problem, tol) defaults")
            elif name == BASELINE:
                ax.loglog(x, y, "k--", linewidth=1.6, label="conforming.py (p = 3, 4)")
            else:
                ax.loglog([r[key] for r in mine], [r["error"] for r in mine], ".", color=colours[name],
                          alpha=0.25, markersize=4)
                ax.loglog(x, y, "-", color=colours[name], linewidth=1.8, label=name)
        for target in TARGETS:
            ax.axhline(target, color="0.75", linewidth=0.6, zorder=0)
        ax.set(title=f"Example {example}", xlabel="wall seconds (cumulative for adaptive runs)"
               if key == "seconds" else "degrees of freedom")
        ax.grid(True, which="major", alpha=0.3)
    axes[0][0].set_ylabel(r"true error $|||u_{ref} - u_h|||_h$")
    axes[0][0].legend(fontsize=8, loc="lower left")
    fig.suptitle("Lines: each method's Pareto front over its uniform (p = 1-4), h-adaptive (p = 1-3)\n"
                 "and hp-adaptive runs; dots: every level of every run", fontsize=9)
    save_figure(fig, path)


# ----------------------------------------------------------------------------------------- TABLE
def cheapest(rows, target):
    """The row reaching error <= target in the least seconds (None if none does)."""
    reached = [r for r in rows if r["error"] <= target]
    return min(reached, key=lambda r: r["seconds"]) if reached else None


def run_name(row):
    if row["method"] == DEFAULT:
        return f"tol = {row['tol']:g}, {row['strategy']}"
    if row["method"] == BASELINE:
        return f"$p = {row['p']}$"
    return f"{STRATEGY_NAMES[row['strategy']]}, $p = {row['p']}$"


def summary(rows):
    """Markdown rows: per target, per method (and baseline, adapt's default) its cheapest run and the ratio of
    its seconds to the baseline's."""
    table = []
    for target in TARGETS:
        found = {name: cheapest(mine, target) for name, mine in groups(rows).items()}
        base = found[BASELINE]
        for name, row in found.items():
            if row is None:
                errors = [r["error"] for r in groups(rows)[name]]
                table.append([f"{target:g}", name, "not reached" + (f" (best {min(errors):.1e})" if errors else ""),
                              "-", "-", "-"])
                continue
            ratio = "-" if base is None else f"{row['seconds'] / base['seconds']:.2f}"
            table.append([f"{target:g}", name, run_name(row), f"{row['seconds']:.2f}", row["ndof"], ratio])
    return table


SETTING = """\
What is measured: for each example and each method of `ngdgfric.METHODS` (the five DG methods of Section 3 and the
conforming `cg`), with Newton's solver (the default), one run at a time in one process:

- uniform meshes $h = 2^{-1}, 2^{-2}, \\dots$ in degree $p = 1, \\dots, 4$, $h$ halved while the method's space
  $V_h$ stays within the DOF budget; seconds: the cold solve on that mesh alone (a user who knows $h$ solves once);
- h-adaptive: `adapt(problem, method=m, hp=False, order=p)` for $p = 1, 2, 3$, its other defaults;
- hp-adaptive: `adapt(problem, method=m)` with its defaults (hp from $p = 4$ up to 8, $\\theta = 0.8$).

The adaptive runs stop at the DOF budget or at $\\eta_h \\le 10^{-4}$ (the smallest target; $\\eta_h$, the default
estimator in energy units, is above the true error), and their seconds are the cumulative solve, estimate, mark and
refine up to the level (`ngdgfric.studies.strategy_run`).  Beside them: the conforming baseline
`benchmarks/conforming.py` (its own $H^1$ code, $p = 3$ and 4, up to twice the budget: of fixed degree, it needs
more DOFs for $10^{-4}$), and what `ndf.adapt(problem, tol=t)` with every default delivers for
$t = 10^{-1}, \\dots, 10^{-4}$ (the seconds of the whole loop, the true error of its answer).  The true error
$|\\!|\\!| u_\\mathrm{ref} - u_h |\\!|\\!|_h$ (`ndf.energy_error`) is measured against the hp references of
[the reference solutions](reference.md), outside the timing.  Seconds are wall seconds; a run that took under
`CHEAP` seconds is repeated up to `--repeat` times and each level keeps its fastest.  A run whose solver fails is
recorded as failed, not fatal."""
"""What the page measured, how (Markdown)."""


def headline(study_rows):
    """The page's opening: what is compared and, computed from the cheapest runs, what it shows (Markdown)."""
    dg, cg, strategies = [], [], set()
    for rows in study_rows.values():
        for target in TARGETS:
            found = {name: cheapest(mine, target) for name, mine in groups(rows).items()}
            base = found[BASELINE]
            for name, row in found.items():
                if row is None or name in (BASELINE, DEFAULT):
                    continue
                strategies.add(STRATEGY_NAMES[row["strategy"]])
                if base is not None:
                    (cg if name == "cg" else dg).append(row["seconds"] / base["seconds"])
    text = ("The seconds each method needs to reach a true error of $10^{-1}, \\dots, 10^{-4}$ on Examples "
            f"{' and '.join(study_rows)}, over uniform, h-adaptive and hp-adaptive runs of every degree, against a "
            "plain conforming code (the baseline).")
    if len(strategies) == 1:
        text += f"  Every method's cheapest run to every target is its {strategies.pop()} run."
    if dg:
        text += (f"  The DG methods need {min(dg):.2f} to {max(dg):.2f} times the baseline's seconds"
                 + (f", the conforming `cg` of ngdgfric {min(cg):.2f} to {max(cg):.2f} times." if cg else "."))
    return text


def report(study_rows, failures, args, argv, load):
    lines = ["# Accuracy against run time", "", headline(study_rows), "", SETTING, "",
             f"DOF budget {args.budget} ({BASELINE_BUDGET} times that for the baseline), best of {args.repeat} for "
             f"runs under {CHEAP:g} s.  The whole run: "
             f"{load['wall'] / 60:.1f} min of wall time and {load['cpu'] / 60:.1f} min of CPU time (this process) "
             f"on {os.cpu_count()} cores, load average {load['start']:.1f} at the start and {load['end']:.1f} at the "
             "end (other work on the machine slows every run alike).", "",
             "![error against seconds](work_precision.png)", "", "![error against DOFs](work_precision_dofs.png)", ""]
    for example, rows in study_rows.items():
        lines += [f"## Example {example}", "",
                  "The cheapest run of each method to each true error (its first level at or below it; "
                  "seconds as in the chart), and its seconds over the baseline's:", "",
                  markdown_table(["true error $\\le$", "method", "cheapest run", "seconds", "DOFs",
                                  "seconds / baseline's"], summary(rows)), ""]
    lines += [f"Failed runs: {'; '.join(failures) if failures else 'none'}.", "",
              f"Regenerate: `{shlex.join(['python', 'benchmarks/work_precision.py', *argv])}`", ""]
    write_text(args.out / "work_precision.md", "\n".join(lines))
    return lines


# ----------------------------------------------------------------------------------------- MAIN
def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    load = dict(start=os.getloadavg()[0], wall=time.perf_counter(), cpu=time.process_time())
    study_rows, failures, every = {}, [], []
    for example in args.example[:1] if args.quick else args.example:
        runs = study(example, args)
        failures += [f"Example {example}, {run['label']}: {run['failure']}" for run in runs if run["failure"]]
        study_rows[example] = points(runs)
        every += [dict(example=example, **row) for row in study_rows[example]]
        write_csv(args.out / "work_precision.csv", every, FIELDS)
    plot(study_rows, args.out / "work_precision.png")
    plot(study_rows, args.out / "work_precision_dofs.png", key="ndof")
    load.update(end=os.getloadavg()[0], wall=time.perf_counter() - load["wall"], cpu=time.process_time() - load["cpu"])
    lines = report(study_rows, failures, args, argv, load)
    say("\n".join(lines))
    return {example: {name: front(mine) for name, mine in groups(rows).items()}
            for example, rows in study_rows.items()}


if __name__ == "__main__":
    run_script(main)
