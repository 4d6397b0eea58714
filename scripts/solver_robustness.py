"""Robustness of the default solver (condensation + semismooth Newton) over the data.

Runs the named hard cases and ``COUNT`` cases drawn with a fixed seed (scripts/robustness_cases.py: the
cases, the pass criteria, the ranges drawn over) and writes solver_robustness.csv (one row per case,
rewritten after every case, so an interrupted run keeps what is done) and solver_robustness.md into
--out (default results/).  tests/test_solver_robustness.py checks the same property with cases drawn by
hypothesis.

Cases run in ``--workers`` processes (default 2), each case in one process, single-threaded.

    python scripts/solver_robustness.py [--quick] [--only ID ...] [--workers N] [--out DIR]
"""

import collections
import functools
import math
import time

import numpy as np
import robustness_cases as robustness
from common import command_line, in_processes, run_script, say, script_parser, write_csv

from ngdgfric.files import write_text
from ngdgfric.output import markdown_table

FIELDS = ["id", "name", "family", "method", "order", "p_min", "p_max", "mesh", "size", "elements", "ndof", "nu", "E",
          "E_varies", "c_n", "c_n_varies", "m_n", "c_tau", "c_tau_varies", "m_t", "g_a", "g_a_kind", "passed",
          "status", "reasons", "message", "existence", "iterations", "steps", "seconds", "contact_points",
          "penetrating", "stick", "lam_excess", "complementarity", "equilibrium", "rounding", "equilibrium_ratio",
          "uzawa_status", "uzawa_iterations", "uzawa_seconds", "uzawa_difference", "uzawa_complementarity",
          "uzawa_equilibrium", "uzawa_message", "warnings"]


def parse(argv=None):
    parser = script_parser(__doc__, "8 small cases (smoke test)")
    parser.add_argument("--only", nargs="+", metavar="ID", help="run only these case ids (e.g. N07 R123)")
    parser.add_argument("--workers", type=int, default=2, help="processes running cases (default 2; 1: no pool)")
    return parser.parse_args(argv)


# ============================================================================ REPORT
def g(value, spec=".3g"):
    if value is None or value == "" or (isinstance(value, float) and math.isnan(value)):
        return "-"
    if isinstance(value, float):
        return format(value, spec)
    return str(value)


def size_text(row):
    if row["mesh"] == "uniform":
        return f"h = 1/{round(1 / row['size'])}"
    if row["mesh"] == "netgen":
        return f"maxh = {row['size']:g}"
    return f"{row['size']} levels"


def order_text(row):
    if row.get("p_min") is not None and row["p_min"] != row["p_max"]:
        return f"{row['p_min']}-{row['p_max']}"
    return str(row["order"] if row.get("p_min") is None else row["p_min"])


def data_text(row, name):
    value = row[name]
    if value is None:
        return "manuf."
    suffix = {"E": "(1+x/4)", "c_n": "(1+x)", "c_tau": "2x"}[name] if row[f"{name}_varies"] else ""
    return f"{value:.4g}" + ("*" + suffix if suffix else "")


def order_kind(row):
    return "hp" if row["order"] == "hp" else f"p = {row['order']}"


def uzawa_text(row):
    if row["uzawa_status"] == "converged":
        return f"{row['uzawa_difference']:.1e} ({row['uzawa_iterations']} its)"
    if row["uzawa_status"] == "not run":
        return "-"
    its = row.get("uzawa_iterations")
    return f"{row['uzawa_status']} ({its} its)" if its else row["uzawa_status"]


def counts(rows, key):
    return ", ".join(f"{k}: {n}" for k, n in sorted(collections.Counter(key(r) for r in rows).items(),
                                                     key=lambda item: str(item[0])))


def value_range(rows, name):
    values = [r[name] for r in rows if r.get(name) is not None]
    return f"{min(values):.4g} ... {max(values):.4g}" if values else "-"


def report(rows, total, seconds, interrupted, budget):
    solved = [r for r in rows if r["status"] == "solved" and r.get("rounding") is not None]
    passed = [r for r in rows if r["passed"]]
    unsolvable = [r for r in rows if r["status"] == "no solution found"]
    failed = [r for r in rows if not r["passed"] and r["status"] != "no solution found"]
    converged = [r for r in rows if r["uzawa_status"] == "converged"]
    uzawa_failed = [r for r in rows if r["uzawa_status"] in ("failed", "stopped", "error")]
    iterations = [r["iterations"] for r in rows if r.get("iterations") is not None]

    def worst(name):
        if not solved:
            return "-"
        r = max(solved, key=lambda r: r[name])
        return f"{r[name]:.2e} ({r['id']})"

    lines = ["# Robustness of the default solver (semismooth Newton)", "",
             "The default contact solver on cases drawn over the ranges of the data (fixed seed) and on named hard "
             "cases: each solution is checked against the KKT conditions and, where Uzawa's method converges, "
             "against Uzawa's solution.", "",
             "A case passes iff the solve raises nothing, lam_excess $\\le 10^{-14}$, complementarity "
             "$\\le 10^{-12}$, equilibrium $\\le 10 \\max(\\mathrm{rounding}, 10^{-14})$ (rounding: the equilibrium "
             "residual of $u (1 \\pm \\epsilon)$) and, for $m_t = 0$ and at most "
             f"{robustness.UZAWA_MAX_NDOF} DOFs where Uzawa (solver_tol $= 10^{{-11}}$, maxit $= 20000$) converges, "
             "$\\max \\lvert u_\\mathrm{Newton} - u_\\mathrm{Uzawa} \\rvert / \\max \\lvert u_\\mathrm{Uzawa} \\rvert "
             f"\\le 10^{{-7}}$.  Uzawa is stopped after a time budget of {budget:g} s (wall time; 12 ms per "
             "iteration where its inner Newton for $m_n > 1$ is busy).  Adapted meshes come from `ndf.adapt` on "
             "the family's base problem (hp: order 2 up to 5; h: $P_1$ from $h = 1/4$), used with the case's data "
             "and method.  The ranges are in the module docstring of `scripts/solver_robustness.py`; one case "
             "again: `python scripts/solver_robustness.py --only ID --out DIR`.", ""]
    if interrupted:
        lines += [f"**Interrupted: {len(rows)} of {total} cases done.**", ""]
    lines += ["## Summary", "",
              f"- cases: {len(rows)}, passed: {len(passed)}, failed: {len(failed)}, no solution found: "
              f"{len(unsolvable)} (the solver raised SolverError and plain Newton from "
              f"{robustness.EXISTENCE_STARTS} random starting forces found no solution either; below); run time "
              f"{seconds:.0f} s.",
              f"- worst lam_excess {worst('lam_excess')}, complementarity {worst('complementarity')}, "
              f"equilibrium {worst('equilibrium')}; worst equilibrium / max(rounding, 1e-14) "
              f"{worst('equilibrium_ratio')}.",
              f"- Uzawa: {len(converged)} converged, {len(uzawa_failed)} failed "
              f"({sum(r['uzawa_status'] == 'stopped' for r in rows)} of them stopped by the time budget), "
              f"{len(rows) - len(converged) - len(uzawa_failed)} not run (m_t > 0, ndof > "
              f"{robustness.UZAWA_MAX_NDOF} or Newton failed); largest difference where it converged: "
              + (f"{max(r['uzawa_difference'] for r in converged):.2e} "
                 f"({max(converged, key=lambda r: r['uzawa_difference'])['id']})." if converged else "-."),
              f"- Newton iterations: median {np.median(iterations):.0f}, max {max(iterations)} "
              f"({max(rows, key=lambda r: r.get('iterations') or -1)['id']})." if iterations else "- no solve.",
              f"- ndof {value_range(rows, 'ndof')}; Newton solve "
              f"{sum(r.get('seconds') or 0 for r in rows):.1f} s in all, Uzawa "
              f"{sum(r.get('uzawa_seconds') or 0 for r in rows):.1f} s.", ""]
    limited = [r for r in converged if robustness.AGREEMENT_TOL < r["uzawa_difference"] <= robustness.UZAWA_LIMITED]
    if limited:
        lines += ["Uzawa differences between 1e-7 and 1e-5 (counted as failures above).  Uzawa stops on its change",
                  "(solver_tol = 1e-11), which bounds its own accuracy only through the rate of convergence; its KKT",
                  "residuals against Newton's show which solution is the less accurate one:", "",
                  markdown_table(["case", "difference", "Uzawa its", "Uzawa complementarity", "Uzawa equilibrium",
                                  "Newton complementarity", "Newton equilibrium"],
                                 [[r["id"], g(r["uzawa_difference"], ".2e"), r["uzawa_iterations"],
                                   g(r["uzawa_complementarity"], ".1e"), g(r["uzawa_equilibrium"], ".1e"),
                                   g(r["complementarity"], ".1e"), g(r["equilibrium"], ".1e")] for r in limited]), ""]
    lines += ["Coverage:", "",
              f"- methods: {counts(rows, lambda r: r['method'])}",
              f"- orders: {counts(rows, order_kind)}",
              f"- meshes: {counts(rows, lambda r: r['mesh'])}",
              f"- problem families: {counts(rows, lambda r: r['family'])}",
              f"- g_a: {counts(rows, lambda r: robustness.g_a_kind(r['g_a']))}",
              f"- spatially varying: E {sum(r['E_varies'] for r in rows)}, c_n {sum(r['c_n_varies'] for r in rows)}, "
              f"c_tau {sum(r['c_tau_varies'] for r in rows)} "
              f"(+ {sum(r['c_tau'] is None for r in rows)} manufactured c_tau)",
              f"- ranges: c_n {value_range(rows, 'c_n')}, c_tau {value_range(rows, 'c_tau')}, nu "
              f"{value_range(rows, 'nu')}, m_n {value_range(rows, 'm_n')}, m_t {value_range(rows, 'm_t')} "
              f"(m_t > 0 in {sum(r['m_t'] > 0 for r in rows)} cases), E {value_range(rows, 'E')}", ""]
    lines += ["## Failures", ""]
    if failed:
        raised = sum(r["status"] != "solved" for r in failed)
        complementarity = [r["complementarity"] for r in failed if r.get("complementarity") is not None
                           and r["complementarity"] > robustness.COMPLEMENTARITY_TOL]
        lines += [f"By criterion: the solve raised in {raised}; lam_excess in "
                  f"{sum('lam_excess' in r['reasons'] for r in failed)}; complementarity in {len(complementarity)} "
                  f"({sum(c <= 1e-10 for c in complementarity)} of them <= 1e-10); equilibrium in "
                  f"{sum('equilibrium' in r['reasons'] for r in failed)}; agreement with Uzawa in "
                  f"{sum('Uzawa' in r['reasons'] for r in failed)}.", ""]
    lines += [f"- **{r['id']}** ({r['family']}, {r['method']}, p = {order_text(r)}, {r['mesh']} {size_text(r)}, "
              f"ndof {g(r.get('ndof'))}, nu = {r['nu']:g}, E = {data_text(r, 'E')}, c_n = {data_text(r, 'c_n')}, "
              f"m_n = {r['m_n']:g}, c_tau = {data_text(r, 'c_tau')}, m_t = {r['m_t']:g}, g_a = {r['g_a']}"
              + (f"; {r['name']}" if r["name"] else "") + f"): {r['reasons']}"
              + (f" (Newton: {r['iterations']} iterations, steps {r['steps']})" if r.get("iterations") is not None
                 else "") for r in failed] or ["None."]
    lines += ["", "## Cases without a solution found", "",
              "The solver raised a SolverError; a search for a solution of the same condensed problem by plain",
              f"semismooth Newton from {robustness.EXISTENCE_STARTS} random starting forces (scales 1e-3 ... 1e9)",
              "found none.  For m_t > 0 the problem is a quasi-variational inequality, which has a solution for a",
              "friction bound that grows slowly with the penetration; a huge c_tau against a tiny c_n is outside",
              "that regime.", ""]
    lines += [f"- **{r['id']}** ({r['family']}, {r['method']}, p = {order_text(r)}, {r['mesh']} {size_text(r)}, "
              f"c_n = {data_text(r, 'c_n')}, m_n = {r['m_n']:g}, c_tau = {data_text(r, 'c_tau')}, m_t = {r['m_t']:g}): "
              f"`{r['message']}`" for r in unsolvable] or ["None."]  # the solver's whole message, as it printed it
    lines += ["", "## Uzawa failures (not failures of the cases)", ""]
    lines += [f"- {r['id']}: {r['uzawa_message'][:240]}" for r in uzawa_failed] or ["None."]
    lines += ["", "## All cases", "",
              "Seconds: Newton's `ndf.solve` (assembly included).  Uzawa: difference (iterations), or why not.", "",
              markdown_table(["case", "family", "method", "p", "mesh", "ndof", "nu", "E", "c_n", "m_n", "c_tau", "m_t",
                              "g_a", "its", "s", "lam_excess", "compl.", "equil.", "rounding", "Uzawa", "pass"],
                             [[r["id"], r["family"], r["method"], order_text(r), f"{r['mesh']} {size_text(r)}",
                               g(r.get("ndof")), f"{r['nu']:g}", data_text(r, "E"), data_text(r, "c_n"),
                               f"{r['m_n']:g}", data_text(r, "c_tau"), f"{r['m_t']:g}", r["g_a"],
                               g(r.get("iterations")), g(r.get("seconds"), ".2f"), g(r.get("lam_excess"), ".1e"),
                               g(r.get("complementarity"), ".1e"), g(r.get("equilibrium"), ".1e"),
                               g(r.get("rounding"), ".1e"), uzawa_text(r),
                               verdict_text(r)]
                              for r in rows]), ""]
    named = [r for r in rows if r["name"]]
    if named:
        lines += ["Named cases: " + "; ".join(f"{r['id']} {r['name']}" for r in named) + ".", ""]
    lines += [f"Regenerate: `{command_line()}`", ""]
    return "\n".join(lines)


def verdict_text(row):
    if row["passed"]:
        return "yes"
    return "no solution" if row["status"] == "no solution found" else "**no**"


def progress_line(index, total, row):
    head = (f"[{index}/{total}] {row['id']} {row['family']} {row['method']} p={order_text(row)} {row['mesh']} "
            f"{size_text(row)} ndof {g(row.get('ndof'))}")
    if row["status"] == "no solution found":
        return f"{head}: no solution found ({row['message'][:120]})"
    if row["status"] != "solved":
        return f"{head}: FAIL {row['message'][:160]} ({row.get('existence', '')})"
    return (f"{head}: {'pass' if row['passed'] else 'FAIL'} its {row['iterations']} {row['seconds']:.2f} s, "
            f"equil/rounding {g(row.get('equilibrium_ratio'), '.2g')}, Uzawa {uzawa_text(row)}"
            + ("" if row["passed"] else f" -- {row['reasons'][:200]}"))


# ============================================================================ MAIN
def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    cases = robustness.quick_cases() if args.quick else robustness.named_cases() + robustness.random_cases()
    if args.only:
        unknown = sorted(set(args.only) - {c["id"] for c in cases})
        if unknown:
            raise SystemExit(f"unknown case id(s): {', '.join(unknown)}")
        cases = [c for c in cases if c["id"] in args.only]
    csv_path, md_path = args.out / "solver_robustness.csv", args.out / "solver_robustness.md"
    budget = robustness.QUICK_UZAWA_SECONDS if args.quick else robustness.UZAWA_SECONDS
    done, start = {}, time.perf_counter()
    finished = in_processes(functools.partial(robustness.run_case, uzawa_seconds=budget), cases,
                            min(args.workers, len(cases)))
    try:
        for index, row in finished:
            done[index] = row
            say(progress_line(len(done), len(cases), row))
            write_csv(csv_path, [done[i] for i in sorted(done)], FIELDS)
    except BaseException:  # Ctrl-C or a crashed worker: keep what is done
        finished.close()
        if done:
            rows = [done[i] for i in sorted(done)]
            write_csv(csv_path, rows, FIELDS)
            write_text(md_path, report(rows, len(cases), time.perf_counter() - start, True, budget))
            say(f"interrupted: wrote {len(rows)} of {len(cases)} cases to {csv_path} and {md_path}")
        raise
    rows = [done[i] for i in sorted(done)]
    write_text(md_path, report(rows, len(cases), time.perf_counter() - start, False, budget))
    say(f"{sum(r['passed'] for r in rows)} of {len(rows)} cases passed; wrote {md_path}")
    return rows


if __name__ == "__main__":
    run_script(main)
