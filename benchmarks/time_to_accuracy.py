"""Time to an answer: ``ndf.adapt`` against the conforming baseline of benchmarks/conforming.py, side by side.

Cases: Examples 6.1 and 6.2 (true errors against the stored hp references, results/reference.md; absolute targets
1e-1 ... 1e-4) and the scenes of results/scenes.md that have an hp reference and that the baseline can solve
(straight contact sides, m_t = 0: l-shape, hertz, wedge; targets relative to |||u_ref|||: 1e-1 ... 1e-3, the
references of ``python scripts/scenes.py``, cached in results/.cache/scenes).  Runs per case, one process,
alternating, best of ``--repeat`` (2):

* ``adapt``: ``ndf.adapt(problem)`` with its defaults (the method it chooses), its tolerance far below the
  targets, the true error of every level measured outside the timing;
* the conforming baseline (benchmarks/conforming.py: H^1 of fixed degree p = 3 and 4, exact friction by
  semismooth Newton, ZZ estimator, Doerfler theta = 0.5, ``mesh.Refine``), the best p per target;
* every DG method's own ``adapt(problem, method=m)`` (one run each), the best method per target.

Time to a target = the cumulative seconds (solve + estimate + mark + refine of the levels before, solve +
estimate of the level itself) to the first level whose true error is at or below it, DOFs and levels of that
level.  Then the stopping runs, what ``adapt(problem, tol=t)`` with its defaults delivers against t (the method
it chooses, cg here; hp from p = 4 up to 8, Doerfler theta = 0.8, geometric layers, the estimator in energy units)
for t = 1e-1, 1e-2, 1e-3, 5e-4 and 1e-5 on both examples, with the residual estimator and with the guaranteed
bound (``estimator="equilibrated"``): levels, DOFs, the loop's seconds, one linear solve of its final mesh
(``ndf.solve`` of the problem without contact, same method and orders, best of 3), their ratio, eta_h, the true
error |||u - u_h|||_h of the answer, error / t and eta_h / error.  Timings on a shared 2-core machine.

Writes results/time_to_accuracy.csv, time_to_accuracy_stops.csv, .md and .png.

    python benchmarks/time_to_accuracy.py [--quick] [--case 6.2 ...] [--repeat 2]   # about 20 minutes
    python benchmarks/time_to_accuracy.py --stops-only    # the stopping runs alone (a few minutes), targets kept
"""

import itertools
import math
import sys
import time
from pathlib import Path

import ngdgfric as ndf
from ngdgfric.output import markdown_table
from ngdgfric.studies.scenes import SCENES

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
import conforming  # noqa: E402  (benchmarks/conforming.py, the baseline, beside this file)
from common import (  # noqa: E402
    RESULTS,
    best,
    contact_free,
    fmt,
    read_csv,
    results_path,
    run_script,
    save_figure,
    say,
    script_parser,
    write_csv,
)

EXAMPLE_TARGETS = (1e-1, 1e-2, 1e-3, 1e-4)
SCENE_TARGETS = (1e-1, 1e-2, 1e-3)  # relative to |||u_ref|||
SCENE_CASES = {"l-shape": "l_shape", "hertz": "hertz", "wedge": "wedge"}
BASELINE_ORDERS = (3, 4)  # p = 2 is never the fastest (benchmarks/README.md: 5-7 times slower to 1e-2)
STOP_TOLERANCES = (1e-1, 1e-2, 1e-3, 5e-4, 1e-5)
RESOLVED = 1e-4  # tolerances at or above it are resolved by the stored references (estimated error 3e-5)
MAX_NDOF = 400_000
DG_SECONDS = 300  # a DG method's own adapt run stops here (TimeLimitError): NIPG on the wedge ran 9.5 min unfinished
FIELDS = ["case", "run", "target", "relative", "seconds", "ndof", "levels", "error"]
TEXT_COLUMNS = ("case", "run", "method", "stopped", "estimator")  # read back as text whatever they hold ("6.1")
ESTIMATORS = ("residual", "equilibrated")
STOP_FIELDS = ["case", "estimator", "tol", "method", "levels", "ndof", "p_max", "stopped", "loop_seconds",
               "linear_seconds", "ratio", "eta_h", "error", "error_over_tol", "effectivity", "last_growth",
               "mean_growth"]


def parse(argv=None):
    parser = script_parser(__doc__, "Example 6.2, targets 1e-1 and 1e-2, one repeat, SIPG only among the DG "
                                    "methods (for the tests)")
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--case", nargs="+", default=None, help="6.1, 6.2, l-shape, hertz, wedge (default: all)")
    parser.add_argument("--report", action="store_true", help="only rewrite the Markdown and the plot from the CSVs")
    parser.add_argument("--dg", nargs="*", choices=ndf.DG_METHODS, default=list(ndf.DG_METHODS),
                        help="the DG methods whose own adapt runs are timed (default: all five)")
    parser.add_argument("--append", action="store_true", help="add the rows to those of the CSVs in --out")
    parser.add_argument("--dg-only", action="store_true",
                        help="only the DG methods' own adapt runs (--dg), added to the rows of the CSVs in --out")
    parser.add_argument("--stops-only", action="store_true",
                        help="only the stopping runs adapt(problem, tol); the target rows are read from "
                             "time_to_accuracy.csv in --out")
    return parser.parse_args(argv)


def case(name):
    """(problem, reference, targets, scale): the absolute targets and |||u_ref||| (1 for the examples)."""
    if name in ndf.examples.EXAMPLES:
        problem = ndf.example(name)
        reference = ndf.load_reference(results_path(f"reference_{name.replace('.', '_')}.npz"), problem)
        return problem, reference, EXAMPLE_TARGETS, 1.0
    scene = SCENES[SCENE_CASES[name]]()
    path = RESULTS / ".cache" / "scenes" / f"{name}.npz"
    if not path.exists():
        raise FileNotFoundError(f"{path}: run python scripts/scenes.py first (it computes the hp references)")
    reference = ndf.load_reference(path, scene.problem)
    scale = ndf.energy_norm(reference)
    return scene.problem, reference, tuple(t * scale for t in SCENE_TARGETS), scale


def reached(history, targets):
    """{target: (seconds, ndof, levels, error) of the first level at or below it} from (seconds, ndof, error) per
    level."""
    out = {}
    for k, (seconds, ndof, error) in enumerate(history):
        for target in targets:
            if target not in out and error <= target:
                out[target] = (seconds, ndof, k + 1, error)
    return out


def adapt_history(problem, reference, targets, **options):
    """(seconds, ndof, true error) per level of ``ndf.adapt(problem, **options)`` with a tolerance of a fifth of the
    smallest target (eta_h is about three times the error: the run goes just past the smallest target)."""
    errors = []

    def keep(level, sol, est):
        errors.append((sol.ndof, ndf.energy_error(sol, reference)))

    try:
        run = ndf.adapt(problem, tol=min(targets) / 5, max_ndof=MAX_NDOF, progress=None, keep=keep, **options)
    except ndf.SolverError as error:
        say(f"  failed: {str(error)[:100]}")
        return []
    return _cumulative(run.levels, errors)


def _cumulative(levels, errors):
    """Seconds to each level's solution: the levels before in full, this level's solve and estimate."""
    history, total = [], 0.0
    for record, (ndof, error) in zip(levels, errors, strict=False):
        here = record["solve_seconds"] + record["estimate_seconds"]
        history.append((total + here, ndof, error))
        total += here + record["mark_refine_seconds"]
    return history


def baseline_history(problem, reference, targets, order, mesh):
    """The baseline's (seconds, ndof, true error) per level from ``mesh`` (a copy: the baseline refines it)."""
    try:
        _, history = conforming.time_to_targets(problem, order, targets, reference, max_ndof=MAX_NDOF,
                                                mesh=ndf.meshes.snapshot(mesh))
    except (ValueError, NotImplementedError, RuntimeError) as error:
        say(f"  baseline failed: {str(error)[:100]}")
        return []
    return [(seconds, ndof, error) for _, ndof, seconds, error, _, _ in history]


def first_mesh(name, problem):
    """The baseline's first mesh: uniform h = 1/4 on the examples (its default), the scene's own first mesh."""
    if name in ndf.examples.EXAMPLES:
        return ndf.uniform_mesh(problem, conforming.H0)
    return SCENES[SCENE_CASES[name]]().mesh(0)


def measure(name, repeat, quick, dg_methods, dg_only=False):
    """The rows of one case: adapt, the baseline per p, each DG method; best of ``repeat`` for the first two.
    ``dg_only``: the DG methods' rows alone."""
    problem, reference, targets, scale = case(name)
    if quick:
        targets = targets[:2]
    runs, mesh = {}, first_mesh(name, problem)

    def keep_best(label, history):
        for target, result in reached(history, targets).items():
            if (label, target) not in runs or result[0] < runs[label, target][0]:
                runs[label, target] = result

    for _ in range(0 if dg_only else repeat):  # alternating: adapt, then the baseline at every p
        keep_best("adapt", _traced(name, "adapt", adapt_history(problem, reference, targets)))
        for order in BASELINE_ORDERS[:1] if quick else BASELINE_ORDERS:
            keep_best(f"baseline P{order}", _traced(name, f"baseline P{order}",
                                                    baseline_history(problem, reference, targets, order, mesh)))
    for method in ("sipg",) if quick else dg_methods:
        keep_best(method, _traced(name, method, adapt_history(problem, reference, targets, method=method,
                                                              max_seconds=DG_SECONDS)))
    return [dict(case=name, run=label, target=target, relative=target / scale, seconds=r[0], ndof=r[1],
                 levels=r[2], error=r[3]) for (label, target), r in sorted(runs.items(), key=lambda kv: kv[0][1])]


def _traced(name, label, history):
    if history:
        say(f"{name} {label}: {len(history)} levels, {history[-1][1]} DOFs, {history[-1][0]:.2f} s, error "
            f"{history[-1][2]:.3e}")
    return history


def stopping(name, tol, estimator):
    """``adapt(problem, tol=tol, estimator=estimator)`` with its defaults: one row."""
    problem, reference, _, _ = case(name)
    start = time.perf_counter()
    try:
        run = ndf.adapt(problem, tol=tol, max_ndof=MAX_NDOF, progress=None, estimator=estimator)
    except ndf.SolverError as error:
        return dict(case=name, estimator=estimator, tol=tol, stopped=f"failed: {str(error)[:100]}",
                    loop_seconds=time.perf_counter() - start)
    levels, sol = run.levels, run.solution
    loop = sum(r["solve_seconds"] + r["estimate_seconds"] + r["mark_refine_seconds"] for r in levels)
    linear, _ = best(3, lambda: ndf.solve(contact_free(problem), sol.mesh, method=run.method,
                                          order=sol.discretization.orders))
    growth = [b["ndof"] / a["ndof"] for a, b in zip(levels, levels[1:], strict=False)]
    error = ndf.energy_error(sol, reference)
    return dict(case=name, estimator=estimator, tol=tol, method=run.method, levels=len(levels), ndof=sol.ndof,
                p_max=levels[-1]["p_max"],
                stopped=run.stopped, loop_seconds=loop, linear_seconds=linear, ratio=loop / linear,
                eta_h=run.estimate.eta_h, error=error, error_over_tol=error / tol,
                effectivity=run.estimate.eta_h / error,
                last_growth=growth[-1] if growth else math.nan,
                mean_growth=math.exp(sum(map(math.log, growth)) / len(growth)) if growth else math.nan)


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    names = args.case or (["6.2"] if args.quick else ["6.1", "6.2", *SCENE_CASES])
    csv_path, stops_path = args.out / "time_to_accuracy.csv", args.out / "time_to_accuracy_stops.csv"
    rows = read_csv(csv_path, TEXT_COLUMNS) if args.report or args.append or args.stops_only or args.dg_only else []
    stops = read_csv(stops_path, TEXT_COLUMNS) if args.report or args.append or args.dg_only else []
    if args.report:
        report(rows, stops, args.out)
        plot(rows, args.out / "time_to_accuracy.png")
        return rows, stops
    for name in names:
        if not args.stops_only:
            rows += measure(name, 1 if args.quick else args.repeat, args.quick, args.dg, args.dg_only)
            write_csv(csv_path, rows, FIELDS)
            report(rows, stops, args.out)
        tolerances = STOP_TOLERANCES[:1] if args.quick else STOP_TOLERANCES
        for tol, estimator in itertools.product([] if name not in ndf.examples.EXAMPLES or args.dg_only
                                                else tolerances, ESTIMATORS):
            stops.append(stopping(name, tol, estimator))
            s = stops[-1]
            say(f"{name} adapt(tol={tol:g}, estimator={estimator}): {s.get('levels')} levels, "
                f"{fmt(s['loop_seconds'], '.2f')} s = "
                f"{fmt(s.get('ratio'), '.1f')} linear solves, error {fmt(s.get('error'), '.3e')}, {s['stopped']}")
            write_csv(stops_path, stops, STOP_FIELDS)
            report(rows, stops, args.out)
    plot(rows, args.out / "time_to_accuracy.png")
    return rows, stops


def comparison(rows):
    """Per case and target: adapt, the best baseline p, the best DG method, SIPG's and Bassi et al.'s own adapt, and
    the ratios adapt / baseline, best DG / baseline, SIPG / baseline and Bassi / SIPG (NaN where a run is missing)."""
    table, verdicts = [], []
    cases = list(dict.fromkeys(r["case"] for r in rows))  # rows added by --dg-only come after their case's
    ordered = sorted(rows, key=lambda r: (cases.index(r["case"]), r["target"]))
    for (name, target), group in itertools.groupby(ordered, key=lambda r: (r["case"], r["target"])):
        group = list(group)
        adapt = _fastest([r for r in group if r["run"] == "adapt"])
        base = _fastest([r for r in group if r["run"].startswith("baseline")])
        dg = _fastest([r for r in group if r["run"] in ndf.DG_METHODS])
        sipg, bassi = (_fastest([r for r in group if r["run"] == m]) for m in ("sipg", "bassi"))
        ratios = [a["seconds"] / b["seconds"] if a and b else math.nan
                  for a, b in ((adapt, base), (dg, base), (sipg, base), (bassi, sipg))]
        verdicts.append((name, target, *ratios))
        show = lambda r: "-" if r is None else f"{r['seconds']:.2f} ({r['ndof']}, {r['levels']})"  # noqa: E731
        table.append([name, f"{group[0]['relative']:g}" + ("" if name in ndf.examples.EXAMPLES else " rel."),
                      show(adapt), "-" if base is None else f"{base['run'][-2:]}: {show(base)}",
                      "-" if dg is None else f"{dg['run']}: {show(dg)}", show(sipg), show(bassi),
                      *(fmt(ratio, ".2f") for ratio in ratios)])
    return table, verdicts


def _fastest(rows):
    return min(rows, key=lambda r: r["seconds"]) if rows else None


SETTING = """\
The cases: Examples 6.1 and 6.2 (true errors against the stored hp references of
[the reference solutions](reference.md); absolute targets $10^{-1}, \\dots, 10^{-4}$) and the scenes of
[the scenes page](scenes.md) that have an hp reference and that the baseline can solve (straight contact sides,
$m_t = 0$: l-shape, hertz, wedge; targets relative to $|\\!|\\!| u_\\mathrm{ref} |\\!|\\!|$: $10^{-1}, \\dots, 10^{-3}$,
the references of `python scripts/scenes.py`).  Runs per case, one process, alternating, best of `--repeat` (2):

- `adapt`: `ndf.adapt(problem)` with its defaults (the method it chooses), its tolerance far below the targets, the
  true error of every level measured outside the timing;
- the conforming baseline (`benchmarks/conforming.py`: $H^1$ of fixed degree $p = 3$ and 4, exact friction by
  semismooth Newton, ZZ estimator, Dörfler $\\theta = 0.5$, `mesh.Refine`), the best $p$ per target;
- every DG method's own `adapt(problem, method=m)` (one run each), the best method per target.

Time to a target: the cumulative seconds (solve, estimate, mark and refine of the levels before, solve and estimate
of the level itself) to the first level whose true error is at or below it; DOFs and levels of that level.  Then the
stopping runs: what `adapt(problem, tol=t)` with its defaults delivers against $t$ (the method it chooses, `cg`
here; hp from $p = 4$ up to 8, Dörfler $\\theta = 0.8$, geometric layers, the estimator in energy units) for
$t = 10^{-1}, 10^{-2}, 10^{-3}, 5 \\cdot 10^{-4}$ and $10^{-5}$ on both examples, with the residual estimator and
with the guaranteed bound (`estimator=\"equilibrated\"`): levels, DOFs, the loop's seconds, one linear solve of its
final mesh (`ndf.solve` of the problem without contact, same method and orders, best of 3), their ratio, $\\eta_h$,
the true error $|\\!|\\!| u - u_h |\\!|\\!|_h$ of the answer, error / $t$ and $\\eta_h$ / error.  Timings on a shared
2-core machine."""
"""What the page measured, how (Markdown)."""


def headline(verdicts):
    """The page's opening: what is compared and, from the ratios, what it shows (Markdown)."""
    text = ("The seconds `ndf.adapt` needs to reach a true error, with its defaults and with each DG method, against "
            "a plain conforming code with its own adaptive loop (the baseline), on the paper's examples and three "
            "scenes.")
    adapt = sorted(v[2] for v in verdicts if math.isfinite(v[2]))
    dg = sorted(v[3] for v in verdicts if math.isfinite(v[3]))
    if adapt:
        text += (f"  With its defaults `adapt` takes {adapt[len(adapt) // 2]:.2f} times the baseline's seconds "
                 f"(median over {len(adapt)} targets; at most {adapt[-1]:.2f})")
        text += (f", the best DG method {dg[len(dg) // 2]:.2f} times (at most {dg[-1]:.2f})." if dg else ".")
    return text


def report(rows, stops, out):
    table, verdicts = comparison(rows)
    lines = ["# Time to an answer: adapt against a conforming baseline", "", headline(verdicts), "", SETTING, "",
             "![seconds to each true error](time_to_accuracy.png)", ""]
    lines += findings(rows, verdicts)
    lines += [markdown_table(["case", "target", "adapt s (DOFs, levels)", "baseline: best $p$, s (DOFs, levels)",
                              "best DG method, s (DOFs, levels)", "sipg", "bassi", "adapt / baseline",
                              "DG / baseline", "SIPG / baseline", "Bassi / SIPG"], table), ""]
    lines += stopping_section(stops)
    lines += ["All runs, each at its first level below the target:", "",
              markdown_table(["case", "run", "target", "s", "DOFs", "levels", "true error"],
                             [[r["case"], r["run"], f"{r['target']:.3g}", f"{r['seconds']:.2f}", r["ndof"],
                               r["levels"], f"{r['error']:.3e}"] for r in rows]), "",
              "Regenerate: `python benchmarks/time_to_accuracy.py` (about 20 minutes on 2 cores: the examples 12 "
              "min, the three scenes 4 min, NIPG's runs 3 min and up to DG_SECONDS on the wedge; `--case 6.2` for one "
              "case, `--dg nipg --dg-only` "
              "for one method's runs added to the CSVs, `--stops-only` for the stopping runs alone)", ""]
    ndf.files.write_text(out / "time_to_accuracy.md", "\n".join(lines))


def findings(rows, verdicts):
    """The Markdown lines summing up the ratios (none without a finite ratio) and the DG runs without a result."""
    lines = ["## Findings", ""]
    for column, text, bound in ((2, "adapt / baseline", 1), (3, "best DG method / baseline", 2),
                                (4, "adapt(method='sipg') / baseline", 2), (5, "adapt(method='bassi') / SIPG's", 1.5)):
        finite = [v for v in verdicts if math.isfinite(v[column])]
        if finite:
            worst = max(finite, key=lambda v: v[column])
            lines.append(f"- {text}: at most {worst[column]:.2f} ({worst[0]}, target {worst[1]:.3g}); at or below "
                         f"{bound:g} in {sum(v[column] <= bound for v in finite)} of {len(finite)} (case, target) "
                         f"pairs; median {sorted(v[column] for v in finite)[len(finite) // 2]:.2f}.")
    missing = [f"{method} on {name}" for name in dict.fromkeys(r["case"] for r in rows) for method in ndf.DG_METHODS
               if not any(r["case"] == name and r["run"] == method for r in rows)]
    lines.append(f"- DG runs without a result at any target (not run, see `--dg`, or their solver failed before the "
                 "first target: a SolverError, named in the run's output): "
                 f"{', '.join(missing) if missing else 'none'}.")
    return lines + [""] if len(lines) > 2 else []


def stopping_section(stops):
    """The Markdown lines of the stopping runs: what adapt(problem, tol=t) delivers against t, and its cost."""
    if not stops:
        return []
    lines = ["## Stopping at a tolerance: `adapt(problem, tol)`", ""]
    for estimator, (low, word) in zip(ESTIMATORS, ((0.1, "1/10"), (0.5, "1/2")), strict=True):
        resolved = [s["error_over_tol"] for s in stops if s["tol"] >= RESOLVED and "error_over_tol" in s
                    and s.get("estimator", "residual") == estimator]
        if resolved:
            lines.append(f"- {estimator} estimator: true error / $t$ = {min(resolved):.2f} - {max(resolved):.2f} "
                         f"over the {len(resolved)} runs with $t \\ge {RESOLVED:g}$ "
                         f"({'all' if all(low <= q <= 1 for q in resolved) else 'not all'} within [{word}, 1]).")
    pairs = [(s, r) for s in stops for r in stops if s.get("estimator") == "equilibrated"
             and r.get("estimator") == "residual" and (s["case"], s["tol"]) == (r["case"], r["tol"])
             and "ndof" in s and "ndof" in r]
    if pairs:
        ratios = [s["ndof"] / r["ndof"] for s, r in pairs]
        lines.append(f"- DOFs of the equilibrated run / the residual run's at the same $t$: {min(ratios):.2f} - "
                     f"{max(ratios):.2f}.")
    lines += ["", "The runs:", "",
              markdown_table(["case", "estimator", "$t$", "method", "levels", "DOFs", "$p$ max", "stopped",
                              "DOF growth (mean, last)"],
                             [[s["case"], s.get("estimator", "residual"), f"{s['tol']:g}", s.get("method", "-"),
                               s.get("levels", "-"), s.get("ndof", "-"), s.get("p_max", "-"), s["stopped"],
                               f"{fmt(s.get('mean_growth'), '.2f')}, {fmt(s.get('last_growth'), '.2f')}"]
                              for s in stops]), "",
              "Their cost and accuracy:", "",
              markdown_table(["case", "estimator", "$t$", "loop seconds", "linear solve seconds", "loop / linear",
                              "$\\eta_h$", "true error", "error / $t$", "$\\eta_h$ / error"],
                             [[s["case"], s.get("estimator", "residual"), f"{s['tol']:g}",
                               fmt(s["loop_seconds"], ".2f"), fmt(s.get("linear_seconds"), ".3f"),
                               fmt(s.get("ratio"), ".1f"), fmt(s.get("eta_h"), ".3e"), fmt(s.get("error"), ".3e"),
                               fmt(s.get("error_over_tol"), ".2f"), fmt(s.get("effectivity"), ".2f")]
                              for s in stops]), ""]
    floors = {s["case"]: s["error"] for s in stops if s["tol"] == min(STOP_TOLERANCES) and "error" in s
              and s.get("estimator", "residual") == "residual"}
    if floors:
        lines += ["At $t = 10^{-5}$ the true errors (" + ", ".join(f"{error:.2e} on {name}" for name, error in
                                                              sorted(floors.items())) +
                  ") are those of the stored references (every method's runs stall there alike, "
                  "[the reference solutions](reference.md)): what these runs show is $\\eta_h \\le t$, not the true "
                  "error, which the references cannot resolve.", ""]
    return lines


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(r["case"] for r in rows))
    fig, axes = plt.subplots(1, len(names), figsize=(4 * len(names), 3.6), squeeze=False)
    for ax, name in zip(axes[0], names, strict=True):
        labels = dict.fromkeys(r["run"] for r in rows if r["case"] == name)
        for label, marker in zip(labels, itertools.cycle("osd^v<>ph"), strict=False):
            chosen = [r for r in rows if r["case"] == name and r["run"] == label]
            style = "-" if label == "adapt" else ":" if label.startswith("baseline") else "--"
            ax.loglog([r["relative"] for r in chosen], [r["seconds"] for r in chosen], marker + style, label=label,
                      lw=2.5 if label == "adapt" else 1)
        ax.invert_xaxis()
        ax.set(title=name, xlabel="true error reached" + ("" if name in ndf.examples.EXAMPLES else " (relative)"),
               ylabel="seconds")
        ax.legend(fontsize=6)
    save_figure(fig, path)


if __name__ == "__main__":
    run_script(main)
