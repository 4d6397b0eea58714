"""Where each method fails: penalty, near incompressibility, stiff compliance, friction extremes, Uzawa's rho.

Beyond the paper: the limits of its assumptions (the penalty threshold of Section 3's coercivity, the data of
Section 6's examples pushed to extremes, the step of its Uzawa iteration).

Every case is one independent solve (:mod:`ngdgfric.studies.cases`) run through dask.distributed
(:mod:`ngdgfric.studies.runner`: a LocalCluster with one worker per core, or ``--scheduler ADDRESS``),
cached in ``--cache`` so a restarted study recomputes nothing.  Writes results/stability.md,
stability.png and stability_<section>.csv; ``--speedup`` also times the locking section with one
and with two workers (no cache).

    python scripts/stability.py [--quick] [--scheduler tcp://host:8786] [--workers N] [--speedup]
"""

import csv
import math
import time
from pathlib import Path

import matplotlib
import numpy as np
from common import RESULTS, command_line, run_script, save_figure, say, script_parser, write_csv

from ngdgfric.dg.methods import DG_METHODS, SIPG_THRESHOLD
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.studies import cases
from ngdgfric.studies.runner import run_cases

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METHOD_NAMES = sorted(DG_METHODS)  # the five DG methods (not the conforming baseline cg)


def parse(argv=None):
    parser = script_parser(__doc__, "a few cases per section (smoke test)")
    parser.add_argument("--scheduler", default=None, help="address of a running dask scheduler")
    parser.add_argument("--workers", type=int, default=None, help="local worker processes (default: cores)")
    parser.add_argument("--cache", type=Path, default=Path(".cache/stability"))
    parser.add_argument("--speedup", action="store_true", help="time the locking section with 1 and 2 workers")
    return parser.parse_args(argv)


def sections(quick, reference):
    """The case lists of the five sections."""
    methods = ["sipg", "bassi"] if quick else METHOD_NAMES
    orders = [1] if quick else [1, 2, 3]
    ratios = [0.1, 10.0, 1000.0] if quick else [float(r) for r in np.logspace(-2, 3, 11)]
    return {
        "threshold": [dict(example=e, method=m, order=p, h=0.25) for e in ("6.1", "6.2") for m in methods
                      for p in orders],
        "penalty": [dict(example="6.1", method=m, order=p, ratio=r, h_eig=0.25, h=0.125, reference=reference)
                    for m in methods for p in orders for r in ratios],
        "locking": [dict(method=m, order=p, nu=nu, h=0.125) for m in methods for p in orders
                    for nu in ([0.3, 0.4999] if quick else [0.3, 0.45, 0.49, 0.499, 0.4999])],
        "compliance": [dict(example="6.1", c_n=c, solver=s, h=0.125, maxit=5000)
                       for c in ([1.0, 1e8] if quick else [1.0, 1e2, 1e4, 1e6, 1e8]) for s in ("newton", "uzawa")],
        "friction": [dict(example="6.1", c_tau=c, solver=s, h=0.125, maxit=5000)
                     for c in ([0.0, 1e6] if quick else [0.0, 1e-2, 1.0, 450.0, 1e4, 1e6])
                     for s in ("newton", "uzawa")],
        "rho": [dict(example="6.1", factor=f, h=0.125 if not quick else 0.25, maxit=1000)
                for f in ([1.0, 4.0] if quick else [0.1, 0.5, 1.0, 1.3, 1.5, 2.0, 4.0])],
    }


FUNCTIONS = {"threshold": cases.threshold_case, "penalty": cases.penalty_case, "locking": cases.locking_case,
             "compliance": cases.compliance_case, "friction": cases.friction_case, "rho": cases.rho_case}


def fmt(value, spec=".3g"):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return format(value, spec) if isinstance(value, (int, float)) else str(value)


def ok(row):
    return row["status"] == "converged"


LOCKS = 2.0  # a method locks where its error is more than twice its value at nu = 0.3 (results/locking.md's test)


def failure(section, row, rows):
    """Whose failure a case shows: the method's (its linear part is not coercive, so Section 3's solution may not
    exist and the error is not bounded; or it locks: error more than LOCKS times its value at nu = 0.3), the
    solver's (a problem with a coercive linear part and m_t = 0 has exactly one solution, Lemma 3.1, so a
    SolverError there is the solver's), or '-' for neither."""
    if section == "penalty" and row["lam_min"] <= 0:
        return "method: not coercive"
    if section == "locking" and ok(row):
        growth = _growth([r for r in rows if ok(r)], row["method"], row["order"], row["nu"])
        if growth > LOCKS:
            return f"method: locks (x{growth:.1f})"
    if not ok(row):
        return "solver: rho beyond 2/L" if section == "rho" and row["factor"] * 1.5 >= 2 else "solver"
    return "-"


def failures_section(results):
    """Markdown lines: every failure, the method's or the solver's."""
    rows = [(section, r, failure(section, r, results[section])) for section in ("penalty", "locking", "compliance",
                                                                                 "friction", "rho")
            for r in results[section]]
    method = [(s, r, f) for s, r, f in rows if f.startswith("method")]
    solver = [(s, r, f) for s, r, f in rows if f.startswith("solver")]
    unexplained = [(s, r, f) for s, r, f in solver if f == "solver"]
    lines = ["## Whose failure: the method's or the solver's", "",
             f"{len(rows)} cases: {len(method)} failures of the method (not coercive, or locking), {len(solver)} of "
             f"the solver, of which {len(unexplained)} on a case with a unique solution and a step the theory "
             "allows: " + (", ".join(f"{s} {_label(r)}" for s, r, _ in unexplained) or "none") + ".", ""]
    return lines


def headline(results):
    """The page's opening: what was measured and, computed from the rows, the thresholds and whose failures."""
    sipg1 = [r for r in results["threshold"] if r["method"] == "sipg" and r["order"] == 1]
    rows = [failure(section, r, results[section]) for section in ("penalty", "locking", "compliance", "friction", "rho")
            for r in results[section]]
    method, solver = sum(f.startswith("method") for f in rows), sum(f.startswith("solver") for f in rows)
    text = ("Where each DG method and each solver fails: the penalty $\\eta$ below the coercivity threshold, "
            "near incompressibility ($\\nu \\to 1/2$), a stiff compliance $c_n$, extreme friction $c_\\tau$ and "
            "Uzawa's step $\\rho$.")
    if sipg1:
        text += ("  SIPG with $P_1$ needs $\\eta$ above " + " and ".join(
            f"${r['threshold_mu']:.3g}\\mu$ (Example {r['example']})" for r in sipg1)
            + "; the paper's $30\\mu$ clears it.")
    return text + (f"  Of {len(rows)} cases, {method} fail because of the method (not coercive, or locking) and "
                   f"{solver} because of the solver.")


def _label(row):
    """A case's parameters in a few words."""
    keys = ("method", "order", "ratio", "nu", "c_n", "c_tau", "solver", "factor")
    return " ".join(f"{k}={row[k]:.3g}" if isinstance(row[k], float) else f"{k}={row[k]}" for k in keys if k in row)


def report(results, speedup):
    lines = ["# Stability: where each method fails", "", headline(results), "",
             "Example 6.1 unless said otherwise; uniform meshes; $P_1$ to $P_3$; Newton unless said otherwise.  Every",
             "number below comes from `stability_<section>.csv`.", "", "![stability](stability.png)", ""]
    lines += thresholds_section(results["threshold"]) + penalty_section(results["penalty"])
    lines += locking_section(results["locking"]) + extremes_section(results) + failures_section(results)
    if speedup:
        lines += ["## Parallel speed-up (dask.distributed LocalCluster)", "",
                  "The locking section (small cases: dask's start-up and scheduling are a visible share), without",
                  "the cache, 1 and 2 worker processes; `stability_speedup.csv`, from `--speedup`.", "",
                  markdown_table(["workers", "locking section wall time (s)", "speed-up"],
                                 [[w, f"{t:.1f}", f"{speedup[1] / t:.2f}"] for w, t in speedup.items()]), ""]
    lines += [f"Regenerate: `{command_line()}`", ""]
    return "\n".join(lines)


def thresholds_section(thresholds):
    """Markdown lines: the coercivity thresholds of the penalty."""
    lines = []
    sipg1 = [r for r in thresholds if r["method"] == "sipg" and r["order"] == 1]
    lines += ["## Penalty: coercivity thresholds", "",
              "Smallest $\\eta / \\mu$ (lifting methods: the dimensionless $\\eta$ multiplying $(C r_e, r_e)$) for",
              "which the linear part is coercive, $\\min B_h(v, v) / |\\!|\\!| v |\\!|\\!|_h^2 > 0$ (dense generalised",
              "eigenvalue problem, $h = 1/4$; the value does not change from $h = 1/4$ to $1/8$), by bisection on",
              "$[10^{-2}, 10^3]$.  0.01 means: coercive over the whole range.", "",
              markdown_table(["example", "method", "$p$", "threshold $\\eta / \\mu$", "$\\eta / (2\\mu + \\lambda)$",
                              "theory"],
                             [[r["example"], r["method"], r["order"], fmt(r["threshold_mu"]),
                               fmt(r["threshold_2mu_lam"]), THEORY[r["method"]]] for r in thresholds]), "",
              "SIPG's threshold is a constant times $2\\mu + \\lambda$ (at $p = 1$: " + ", ".join(
                  f"Example {r['example']} {r['threshold_2mu_lam']:.2f}" for r in sipg1) + "), falling with $p$",
              "because the penalty carries $p^2$; the library warns below the factor "
              + ", ".join(f"{factor} ($p = {p}$)" for p, factor in SIPG_THRESHOLD.items())
              + " times $2\\mu + \\lambda$",
              "(`ngdgfric.dg.methods.SIPG_THRESHOLD`, which also covers $\\nu = 0, \\dots, 0.49$) and raises its",
              "default above $30\\mu$ where $30\\mu$ is not enough.  The paper's $30\\mu$ is " + ", ".join(
                  f"{30 / r['threshold_mu']:.2f} times the $P_1$ threshold of Example {r['example']}" for r in sipg1)
              + ".", ""]
    return lines


def penalty_section(penalty):
    """Markdown lines: the penalty sweep."""
    lines = []
    lines += ["## Penalty sweep: coercivity, error against the reference, Newton iterations", "",
              "$h = 1/8$ for the solve; error $|\\!|\\!| u_\\mathrm{ref} - u_h |\\!|\\!|_h$ against the hp reference "
              "of Example 6.1 ([reference solutions](reference.md)); $\\lambda_\\mathrm{min}$ the smallest eigenvalue "
              "of the coercivity problem above.", "",
              markdown_table(["method", "$p$", "$\\eta / \\mu$", "$\\lambda_\\mathrm{min}$", "error",
                              "Newton iterations", "status", "failure"],
                             [[r["method"], r["order"], fmt(r["ratio"]), fmt(r["lam_min"]), fmt(r["error"]),
                               fmt(r["iterations"]), r["status"][:50], failure("penalty", r, penalty)]
                              for r in penalty]), ""]
    failed = [r for r in penalty if not ok(r)]
    unstable = [r for r in penalty if r["lam_min"] <= 0]
    coercive_failures = [r for r in failed if r["lam_min"] > 0]
    lines += [f"- {len(unstable)} of {len(penalty)} cases are not coercive ($\\lambda_\\mathrm{{min}} \\le 0$); "
              f"Newton failed on "
              f"{sum(not ok(r) for r in unstable)} of them (30 iterations), and the others' errors are "
              f"{_error_range(unstable)} against {_error_range([r for r in penalty if r['lam_min'] > 0 and ok(r)])} "
              "for the coercive cases.",
              f"- {len(coercive_failures)} coercive cases failed: " + (", ".join(
                  f"{r['method']} $P_{r['order']}$ $\\eta / \\mu = {r['ratio']:.3g}$" for r in coercive_failures)
                  or "none")
              + ".  (The norm's jump term carries no $\\mu$, so NIPG's symmetric part stays above the norm for any "
              "$\\eta$ here.)", ""]
    return lines


def locking_section(locking):
    """Markdown lines: near incompressibility."""
    lines = []
    lines += ["## Near incompressibility (volumetric locking)", "",
              "Smooth manufactured solution (`ngdgfric.studies.manufactured.elasticity_manufactured`, $E = 1000$),",
              "$h = 1/8$, relative energy error; its stresses grow with $\\lambda$, so this is a test of stability "
              "([the locking page](locking.md) has a solution that stays bounded).", "",
              markdown_table(["method", "$p$"] + [f"$\\nu = {nu}$" for nu in sorted({r['nu'] for r in locking})],
                             [[m, p] + [fmt(r["relative_error"]) for r in sorted(
                                 (r for r in locking if r["method"] == m and r["order"] == p), key=lambda r: r["nu"])]
                              for m in sorted({r["method"] for r in locking})
                              for p in sorted({r["order"] for r in locking})]), ""]
    pairs = sorted({(r["method"], r["order"]) for r in locking})
    last = max(r["nu"] for r in locking)
    lines += [f"- Error growth from $\\nu = 0.3$ to {last}: " + ", ".join(
        f"{m} $P_{p}$ {_growth(locking, m, p, last):.1f} times" for m, p in pairs) + ".",
              f"- Locking (error more than {LOCKS:g} times its value at $\\nu = 0.3$), from the smallest such $\\nu$: "
              + (", ".join(f"{m} $P_{p}$ from $\\nu = {_locks_from(locking, m, p)}$" for m, p in pairs
                            if _locks_from(locking, m, p) is not None) or "none") + ".", ""]
    return lines


def extremes_section(results):
    """Markdown lines: stiff compliance, friction extremes, Uzawa's step."""
    lines = []
    lines += ["## Stiff compliance (towards Signorini)", "",
              markdown_table(["$c_n$", "solver", "iterations", "seconds", "max. penetration", "$\\eta_h$",
                              "$\\operatorname{cond}(A + c_n N)$",
                              "status", "failure"],
                             [[fmt(r["c_n"]), r["solver"], fmt(r.get("iterations")), fmt(r["seconds"]),
                               fmt(r.get("penetration")), fmt(r.get("eta_h")), fmt(r["condition"]), r["status"][:40],
                               failure("compliance", r, results["compliance"])] for r in results["compliance"]]), ""]
    lines += ["## Friction extremes", "",
              markdown_table(["$c_\\tau$", "solver", "iterations", "seconds", "stick share",
                              "$\\max \\lvert u_\\tau \\rvert$",
                              "complementarity", "status", "failure"],
                             [[fmt(r["c_tau"]), r["solver"], fmt(r.get("iterations")), fmt(r["seconds"]),
                               fmt(r.get("stick_fraction")), fmt(r.get("max_slip")), fmt(r.get("complementarity")),
                               r["status"][:40], failure("friction", r, results["friction"])]
                              for r in results["friction"]]), ""]
    lines += ["## Uzawa's step $\\rho$", "",
              "$\\rho$ = factor times the default $1.5 / L$ ($L$: largest eigenvalue of the linearised Uzawa map, "
              "power iteration); projected gradient theory: convergence for $\\rho < 2 / L$, i.e. factor < 1.33.", "",
              markdown_table(["factor", "$\\rho$", "iterations", "seconds", "status", "failure"],
                             [[fmt(r["factor"]), fmt(r["rho"]), r["iterations"], fmt(r["seconds"]), r["status"][:70],
                               failure("rho", r, results["rho"])] for r in results["rho"]]), ""]
    return lines


THEORY = {"sipg": "large enough", "nipg": "any > 0", "bassi": "> 3", "brezzi": "any > 0", "ldg": "any > 0"}


def _error_range(rows):
    errors = [r["error"] for r in rows if r.get("error") is not None]
    return f"{min(errors):.3g} to {max(errors):.3g}" if errors else "-"


def _locks_from(rows, method, order):
    """The smallest nu at which (method, order) locks (:func:`failure`), or None."""
    locked = [r["nu"] for r in rows if (r["method"], r["order"]) == (method, order)
              and failure("locking", r, rows).startswith("method")]
    return min(locked, default=None)


def _growth(rows, method, order, nu):
    """The relative error of (method, order) at nu over its value at the smallest nu of the study (0.3)."""
    chosen = sorted((r for r in rows if r["method"] == method and r["order"] == order), key=lambda r: r["nu"])
    at = next(r for r in chosen if r["nu"] == nu)
    return at["relative_error"] / chosen[0]["relative_error"]


def plot(results, path):
    fig, axes = plt.subplots(1, 5, figsize=(24, 4.5))
    colours = dict(zip(METHOD_NAMES, plt.rcParams["axes.prop_cycle"].by_key()["color"], strict=False))
    for r_method in METHOD_NAMES:
        for order, line in zip((1, 2, 3), ("-", "--", ":"), strict=True):
            rows = [r for r in results["penalty"] if r["method"] == r_method and r["order"] == order]
            if rows:
                axes[0].semilogx([r["ratio"] for r in rows], [r["lam_min"] for r in rows], line,
                                 color=colours[r_method], label=f"{r_method} P{order}" if order == 1 else None)
            rows = sorted((r for r in results["locking"] if r["method"] == r_method and r["order"] == order),
                          key=lambda r: r["nu"])
            if rows:
                axes[1].loglog([0.5 - r["nu"] for r in rows], [r["relative_error"] for r in rows], line,
                               color=colours[r_method], marker="o", markersize=3)
    axes[0].axhline(0, color="k", linewidth=0.5)
    axes[0].set(xlabel="eta / mu", ylabel="min B_h(v,v) / |||v|||^2", title="coercivity (P1 -, P2 --, P3 :)",
                ylim=(-2, 1.1))
    axes[0].legend(fontsize=7)
    axes[1].set(xlabel="0.5 - nu", ylabel="relative energy error", title="volumetric locking")
    axes[1].invert_xaxis()
    for ax, section, key, title in ((axes[2], "compliance", "c_n", "stiff compliance"),
                                    (axes[3], "friction", "c_tau", "friction extremes")):
        for solver, marker in (("newton", "o"), ("uzawa", "s")):
            rows = [r for r in results[section] if r["solver"] == solver and ok(r)]
            ax.loglog([max(r[key], 1e-3) for r in rows], [r["iterations"] for r in rows], marker=marker, label=solver)
        ax.set(xlabel=key + " (0 drawn at 1e-3)" if section == "friction" else key, ylabel="iterations", title=title)
        ax.legend()
    rows = results["rho"]
    axes[4].semilogx([r["factor"] for r in rows], [r["iterations"] for r in rows], "o-")
    for r in rows:
        if not ok(r):
            axes[4].plot(r["factor"], r["iterations"], "rx", markersize=12)
    axes[4].axvline(2 / 1.5, color="k", linestyle=":", label="rho = 2/L")
    axes[4].set(xlabel="rho / default rho", ylabel="Uzawa iterations (x: failed)", title="Uzawa step")
    axes[4].legend()
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    save_figure(fig, path, dpi=100)


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    reference = str((RESULTS / "reference_6_1.npz").resolve())
    results = {}
    for name, case_list in sections(args.quick, reference).items():
        say(f"{name}: {len(case_list)} cases")
        results[name] = run_cases(FUNCTIONS[name], case_list, cache=args.cache, scheduler=args.scheduler,
                                  workers=args.workers, progress=say)
        write_csv(args.out / f"stability_{name}.csv", results[name],
                  fields=list(dict.fromkeys(k for r in results[name] for k in r)))
    speedup = {}
    if args.speedup:
        for workers in (1, 2):
            start = time.perf_counter()
            run_cases(cases.locking_case, sections(args.quick, reference)["locking"], cache=None, workers=workers,
                      progress=None)
            speedup[workers] = time.perf_counter() - start
            say(f"locking section with {workers} worker(s): {speedup[workers]:.1f} s")
        write_csv(args.out / "stability_speedup.csv", [dict(workers=w, seconds=t) for w, t in speedup.items()])
    elif (args.out / "stability_speedup.csv").exists():  # measured by an earlier --speedup run
        with open(args.out / "stability_speedup.csv") as handle:
            speedup = {int(r["workers"]): float(r["seconds"]) for r in csv.DictReader(handle)}
    plot(results, args.out / "stability.png")
    write_text(args.out / "stability.md", report(results, speedup))
    say(f"wrote {args.out / 'stability.md'}")
    return results


if __name__ == "__main__":
    run_script(main)
