"""Solver benchmark: Uzawa (Section 6) against semismooth Newton, and the floor of one linear solve.

For Examples 6.1 and 6.2, SIPG and NIPG, p = 1 and 2, uniform meshes h = 2^-2 ... 2^-7 (as far as
the time budget allows): DOFs, iterations and wall time of Uzawa, Newton from zero (cold) and
from the previous level's solution (warm), and of ONE sparse direct solve (factorisation +
back-substitution) of the linear DG elasticity system of the same size with the fastest direct
solver of the NGSolve wheel (Cholesky for the symmetric SIPG, the faster of UMFPACK and SuperLU
for NIPG; the wheel's SuperLU needs scipy and is skipped without it).  All solver times exclude
the assembly of the DG matrix, which every solve needs once (it is reported separately).
Writes results/solver_benchmark.md, .csv and .png.

    python scripts/bench_solvers.py [--quick] [--budget SECONDS]
"""

import argparse
import time
from pathlib import Path

import matplotlib
import ngsolve as ngs
import numpy as np
from common import EXAMPLES, RESULTS, command_line, markdown_table, save_figure, say, write_csv

import ngdgfric as ndf
from ngdgfric.newton import newton
from ngdgfric.transfer import initial_guess
from ngdgfric.uzawa import uzawa

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PARTS = ("factor", "low_rank", "solve", "jacobian")  # Newton's timings


def floor_time(disc, repeat=2):
    """Seconds of the fastest direct solve of A x = F (factorisation + solve), and its name."""
    candidates = ["sparsecholesky"] if disc.symmetric else ["umfpack", "superlu"]
    best = (np.inf, None)
    x = disc.F.CreateVector()
    for name in candidates:
        for _ in range(repeat):
            start = time.perf_counter()
            try:
                with ngs.TaskManager():
                    inverse = disc.A.Inverse(inverse=name)
                    x.data = inverse * disc.F
            except ImportError:  # the wheel's SuperLU is a wrapper of scipy, which we do not require
                break
            best = min(best, (time.perf_counter() - start, name))
            inverse = None
    return best


def timed(function, *args, **kwargs):
    start = time.perf_counter()
    result = function(*args, **kwargs)
    return result, time.perf_counter() - start


def run_case(example, method, order, levels, budget, uzawa_budget):
    problem = EXAMPLES[example]()
    rows, previous, spent, uzawa_estimate = [], None, 0.0, 0.0
    for k in levels:
        if spent > budget:
            say(f"  stop before h = 2^-{k}: time budget used")
            break
        started = time.perf_counter()
        mesh = ndf.uniform_mesh(problem, 2.0**-k)
        disc, assemble = timed(ndf.Discretization, problem, mesh, method, order)
        floor, solver_name = floor_time(disc)
        (u, lam, cold), cold_time = timed(newton, disc)
        row = dict(example=example, method=method, order=order, k=k, ndof=disc.V.ndof, assemble=assemble,
                   floor=floor, floor_solver=solver_name, newton_its=cold["iterations"], newton=cold_time,
                   newton_factorizations=cold["factorizations"], newton_solves=cold["solves"],
                   newton_columns=cold["columns"], ratio=cold_time / floor,
                   **{f"newton_{part}_time": cold["timings"][part] for part in PARTS},
                   contact_points=cold["contact_points"], stick_points=" ".join(map(str, cold["stick_points"])))
        if previous is not None:
            guess, transfer = timed(initial_guess, previous, disc)
            (_, _, warm), warm_time = timed(newton, disc, initial=guess)
            row.update(warm_its=warm["iterations"], warm=warm_time + transfer,
                       warm_ratio=(warm_time + transfer) / floor, warm_factorizations=warm["factorizations"])
        if uzawa_estimate < uzawa_budget:
            (_, _, uz), uz_time = timed(uzawa, disc)
            row.update(uzawa_its=uz["iterations"], uzawa=uz_time)
            uzawa_estimate = 6 * uz_time  # iterations roughly double, solves cost 3-4 times more
        rows.append(row)
        previous = ndf.Solution(problem, mesh, method, order, disc.eta, "newton", u, lam, cold["iterations"],
                                cold["history"], {}, disc)
        spent += time.perf_counter() - started
        say(f"  h = 2^-{k}: {row['ndof']:7d} dofs | floor {floor:.3f} s ({solver_name}) | Newton "
            f"{row['newton_its']} its {cold_time:.2f} s ({row['ratio']:.1f}x) | warm "
            f"{row.get('warm_its', '-')} its {row.get('warm', float('nan')):.2f} s "
            f"({row.get('warm_ratio', float('nan')):.1f}x) | Uzawa {row.get('uzawa_its', '-')} its "
            f"{row.get('uzawa', float('nan')):.1f} s")
    return rows


def reuse_study(example, method, order, k):
    """Newton at one level with the three linear-algebra policies of ngdgfric.nonlinear."""
    problem = EXAMPLES[example]()
    disc = ndf.Discretization(problem, ndf.uniform_mesh(problem, 2.0**-k), method, order)
    out = []
    for label, options in (("factorise at every Newton step", dict(reuse=False)),
                           ("reuse while the sets stay", dict(low_rank=False)),
                           ("reuse + low-rank updates (default)", dict())):
        (_, _, info), seconds = timed(newton, disc, **options)
        out.append(dict(policy=label, seconds=seconds, iterations=info["iterations"],
                        factorizations=info["factorizations"], solves=info["solves"], columns=info["columns"],
                        refinements=info["refinements"]))
        say(f"  {label}: {seconds:.2f} s, {info['factorizations']} factorisations, {info['solves']} solves, "
            f"{info['columns']} low-rank columns, {info['refinements']} refinement steps")
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="h = 2^-2, 2^-3, P1 only (smoke test)")
    parser.add_argument("--budget", type=float, default=60.0, help="seconds per (example, method, order)")
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    levels = (2, 3) if args.quick else (2, 3, 4, 5, 6, 7)
    orders = (1,) if args.quick else (1, 2)
    rows = []
    for example in ("6.1", "6.2"):
        for method in ("sipg", "nipg"):
            for order in orders:
                say(f"Example {example}, {method.upper()}, P{order}")
                rows += run_case(example, method, order, levels, args.budget, uzawa_budget=args.budget / 2)
    finest = max(rows, key=lambda r: (r["ndof"], r["method"] == "sipg"))
    say(f"Linear-algebra policies at the finest SIPG P1 level of Example {finest['example']}")
    policies = reuse_study("6.1", "sipg", 1, max(r["k"] for r in rows if r["order"] == 1))
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(args.out / "solver_benchmark.csv", rows, fields=list(dict.fromkeys(k for r in rows for k in r)))
    plot(rows, args.out / "solver_benchmark.png")
    (args.out / "solver_benchmark.md").write_text(report(rows, policies))
    say(f"wrote {args.out / 'solver_benchmark.md'}")
    return rows, policies


def plot(rows, path):
    cases = sorted({(r["example"], r["method"], r["order"]) for r in rows})
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for ax, example in zip(axes, ("6.1", "6.2"), strict=True):
        for i, case in enumerate(c for c in cases if c[0] == example):
            data = [r for r in rows if (r["example"], r["method"], r["order"]) == case]
            n = [r["ndof"] for r in data]
            color = f"C{i}"
            label = f"{case[1].upper()} P{case[2]}"
            ax.loglog(n, [r["floor"] for r in data], ":", color=color, label=f"{label}: one linear solve")
            ax.loglog(n, [r["newton"] for r in data], "o-", color=color, ms=3, label=f"{label}: Newton")
            uz = [r for r in data if "uzawa" in r]
            ax.loglog([r["ndof"] for r in uz], [r["uzawa"] for r in uz], "s--", color=color, ms=3,
                      label=f"{label}: Uzawa")
        ax.set_title(f"Example {example}")
        ax.set_xlabel("degrees of freedom")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("seconds (without assembly)")
    axes[1].legend(fontsize=6, ncol=2)
    save_figure(fig, path, dpi=120)


def report(rows, policies):
    def get(r, key, spec):
        return format(r[key], spec) if key in r else "-"

    header = ["example", "method", "p", "h", "DOFs", "assembly s", "floor s", "Newton its", "Newton s",
              "Newton/floor", "warm its", "warm s", "warm/floor", "Uzawa its", "Uzawa s"]
    table = [[r["example"], r["method"], r["order"], f"2^-{r['k']}", r["ndof"], f"{r['assemble']:.2f}",
              f"{r['floor']:.3f}", r["newton_its"], f"{r['newton']:.2f}", f"{r['ratio']:.1f}",
              r.get("warm_its", "-"), get(r, "warm", ".2f"), get(r, "warm_ratio", ".1f"),
              r.get("uzawa_its", "-"), get(r, "uzawa", ".1f")] for r in rows]
    finest = [max((r for r in rows if (r["example"], r["method"], r["order"]) == case), key=lambda r: r["ndof"])
              for case in sorted({(r["example"], r["method"], r["order"]) for r in rows})]
    cold_max = max(r["newton_its"] for r in rows)
    warm_max = max((r["warm_its"] for r in rows if "warm_its" in r), default=0)
    lines = ["# Solver benchmark: Uzawa, semismooth Newton, one linear solve", "",
             f"Regenerate: `{command_line()}` (run alone: timings on a busy machine are meaningless)", "",
             "![time against DOFs](solver_benchmark.png)", "",
             "Times exclude the assembly of the DG matrix (column 'assembly s'), needed once by every solver; "
             "'floor' is one factorisation and back-substitution of that matrix.  Newton and Uzawa stop at the "
             "relative max-norm tolerance 1e-8 of Section 6; warm = started from the previous level's solution "
             "(u interpolated, multiplier transferred), transfer included.", "",
             "## Summary (computed)", "",
             f"- Newton iterations from zero: at most {cold_max}; from the previous level: at most {warm_max}.",
             ]
    for r in finest:
        lines.append(f"- Example {r['example']}, {r['method'].upper()} P{r['order']}, finest level "
                     f"({r['ndof']} DOFs): Newton / one linear solve = {r['ratio']:.1f} (cold), "
                     f"{r.get('warm_ratio', float('nan')):.1f} (warm); Newton used {r['newton_factorizations']} "
                     f"factorisations ({r['newton_factor_time']:.2f} s of {r['newton']:.2f} s) and "
                     f"{r['newton_solves']} back-substitutions.")
    profile = [[r["example"], r["method"], r["order"], r["ndof"], f"{r['newton']:.2f}",
                f"{r['newton_factor_time']:.2f} ({r['newton_factorizations']})",
                f"{r['newton_low_rank_time']:.2f} ({r['newton_columns']})",
                f"{r['newton_solve_time']:.2f} ({r['newton_solves'] - r['newton_columns']})",
                f"{r['newton_jacobian_time']:.2f}",
                f"{r['newton'] - sum(r[f'newton_{part}_time'] for part in PARTS):.2f}",
                f"{r['floor']:.3f}"] for r in finest]
    traces = [r for r in finest if r["example"] == "6.1"]
    lines += ["", "## Where Newton's time goes (cold start, finest level of each case)", "",
              "Seconds in factorisations (count), low-rank corrections (back-substitutions for their columns), "
              "solves (back-substitutions incl. refinement steps), assembling the contact Jacobians, and the "
              "rest (residuals, set decisions at the Gauss points, multiplier updates, merit function and "
              "line search).", "",
              markdown_table(["example", "method", "p", "DOFs", "Newton s", "factorise s", "low-rank s",
                              "solve s", "Jacobians s", "rest s", "floor s"], profile), "",
              "## Why cold starts need more steps on finer meshes (Example 6.1)", "",
              "Size of the stick set decided at each Newton step from zero (all points stick at u = 0, "
              "lambda = 0).  The first step releases the points whose stick force exceeds the bound; "
              "the released load moves to the neighbouring points, so the slip front advances a few "
              "Gauss points per step and a finer mesh (more points across the front's path) needs more "
              "steps.  Warm starts begin near the final front and need 1-3 steps.", ""]
    lines += [f"- {r['method'].upper()} P{r['order']}, {r['ndof']} DOFs, {r['contact_points']} contact points: "
              f"{r['stick_points']}" for r in traces]
    lines += ["", markdown_table(header, table), "",
              "## Reusing the factorisation (Example 6.1, SIPG P1, finest level)", "",
              "Back-substitutions include those for the low-rank columns and the refinement steps "
              "(ngdgfric.nonlinear.ReusedFactorization, ngdgfric.lowrank).", "",
              markdown_table(["policy", "seconds", "iterations", "factorisations", "back-substitutions",
                              "low-rank columns", "refinement steps"],
                             [[p["policy"], f"{p['seconds']:.2f}", p["iterations"], p["factorizations"],
                               p["solves"], p["columns"], p["refinements"]] for p in policies]), ""]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
