"""Reproduce Tables 6.1 and 6.2: errors and orders of convergence on uniform meshes.

Porwal & Tanvi, Section 6: uniform meshes h = 2^-1 ... 2^-5, P1, penalty eta = 30 mu.  Two errors
per row: the relative energy error |||u - u_h|||_h / |||u||| against the hp reference solution of
results/reference.md (the true error; the measure whose behaviour matches the paper's numbers,
results/table_investigation.md), compared with the paper's, and |||u_h - u_{h/2}|||_h (difference
of consecutive solutions on the finer mesh, as Section 6's text says), so the meshes run to
h = 2^-6.  Writes results/table_6_1.md (or table_6_2.md) and a CSV with our numbers, the
paper's, and the ratio ours/paper for every entry.

    python scripts/uniform_convergence.py --example 6.1 [--method sipg nipg bassi brezzi ldg]
        [--uzawa sipg nipg] [--quick]
"""

import time

from common import RESULTS, command_line, fmt, run_script, say, script_parser, write_csv

import ngdgfric as ndf
from ngdgfric.dg.methods import METHODS
from ngdgfric.examples import EXAMPLES
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.reference import reference_errors
from ngdgfric.studies import max_rel_diff, rates, uniform_study
from ngdgfric.studies.paper import TABLES


def parse(argv=None):
    parser = script_parser(__doc__, "levels 2^-1 ... 2^-3 only (smoke test)", example="one")
    parser.add_argument("--method", nargs="+", choices=sorted(METHODS), default=["sipg", "nipg"],
                        help="DG methods of Section 3 (default: the paper's two)")
    parser.add_argument("--order", type=int, default=1)
    parser.add_argument("--solver", choices=["newton", "uzawa"], default="newton",
                        help="solver for the table's solutions (default: newton)")
    parser.add_argument("--uzawa", nargs="*", choices=sorted(METHODS), default=None, metavar="METHOD",
                        help="also solve every level of these methods (all listed if none given) with the "
                             "paper's Uzawa method and report iterations, seconds and difference")
    return parser.parse_args(argv)


def compare_uzawa(problem, method, order, solutions, rows):
    """Add Uzawa's iterations, seconds and max relative difference to the rows."""
    for row, sol in zip(rows, solutions, strict=False):
        start = time.perf_counter()
        uz = ndf.solve(problem, sol.mesh, method=method, order=order, solver="uzawa")
        row["uzawa_iterations"] = uz.iterations
        row["uzawa_seconds"] = time.perf_counter() - start
        row["uzawa_difference"] = max_rel_diff(uz, sol)
        say(f"  uzawa h = 2^-{row['k']}: {uz.iterations} iterations, {row['uzawa_seconds']:.1f} s, "
            f"max rel. difference {row['uzawa_difference']:.1e}")


def main(argv=None):
    args = parse(argv)
    problem = EXAMPLES[args.example]()
    levels = (1, 2, 3) if args.quick else (1, 2, 3, 4, 5, 6)
    tag = args.example.replace(".", "_")
    args.out.mkdir(parents=True, exist_ok=True)
    results, csv_rows = {}, []
    reference = ndf.load_reference(RESULTS / f"reference_{tag}.npz", problem)
    for method in args.method:
        say(f"Example {args.example}, {method.upper()}, P{args.order}, solver {args.solver}")
        rows, solutions = uniform_study(problem, method, args.order, levels, solver=args.solver, progress=say)
        uzawa_methods = args.method if args.uzawa == [] else (args.uzawa or [])
        if method in uzawa_methods:
            compare_uzawa(problem, method, args.order, solutions, rows)
        paper = TABLES[args.example].get(method) if args.order == 1 else None
        true = [reference_errors(sol, reference)["relative"] for sol in solutions[:len(rows)]]
        true_rates = rates(true, [2.0**-row["k"] for row in rows])
        for i, row in enumerate(rows):
            row["method"] = method
            row["true_relative"], row["true_rate"] = true[i], true_rates[i]
            row["paper_error"] = paper["error"][i] if paper and i < len(paper["error"]) else None
            row["paper_rate"] = paper["rate"][i] if paper and i < len(paper["rate"]) else None
            row["ratio"] = row["true_relative"] / row["paper_error"] if row["paper_error"] else None
            row["consecutive_ratio"] = row["energy"] / row["paper_error"] if row["paper_error"] else None
            say(f"  h = 2^-{row['k']}: relative error {row['true_relative']:.4e} rate {fmt(row['true_rate'], '.4f')}"
                + (f"  paper {row['paper_error']:.4e} (ours/paper {row['ratio']:.2f})" if row["ratio"] else "")
                + f"  |  consecutive {row['energy']:.4e}")
        results[method] = rows
        csv_rows += rows
    write_csv(args.out / f"table_{tag}.csv", csv_rows, fields=list(dict.fromkeys(k for r in csv_rows for k in r)))
    text = report(args, results)
    write_text(args.out / f"table_{tag}.md", text)
    say("\n" + text)
    say(f"wrote {args.out / f'table_{tag}.md'}")
    return results


ENERGY_ERROR = r"$|\!|\!| u - u_h |\!|\!|_h / |\!|\!| u |\!|\!|$"
CONSECUTIVE = r"$|\!|\!| u_h - u_{h/2} |\!|\!|_h$"


def mesh_size(k):
    """The mesh size $2^{-k}$ of a row, typeset."""
    return f"$2^{{-{k}}}$"


def report(args, results):
    """The Markdown page: what was measured, the errors of every method side by side, each method against the
    paper, the command that regenerates it."""
    methods = list(results)
    first = results[methods[0]]
    names = ", ".join(m.upper() for m in methods)
    observed = [r["true_rate"] for m in methods for r in results[m] if r["true_rate"] is not None]
    ratios = [r["ratio"] for m in methods for r in results[m] if r["ratio"] is not None]
    # no TeX in the title: the navigation shows it as plain text
    lines = [f"# Table {args.example}: DG methods on uniform meshes, degree {args.order}, penalty η = 30μ", "",
             f"Example {args.example} solved by {names} on uniform meshes $h = {mesh_size(first[0]['k'])[1:-1]}, "
             f"\\dots, {mesh_size(first[-1]['k'])[1:-1]}$ with the penalty $\\eta = 30\\mu$.  The first error is "
             f"the true one, the relative energy error {ENERGY_ERROR} against the hp reference solution "
             "([reference solutions](reference.md), estimated error $3 \\cdot 10^{-5}$)"
             + (f"; its observed rate is {min(observed):.2f} to {max(observed):.2f}" if observed else "")
             + (f", and it is {min(ratios):.2f} to {max(ratios):.2f} times the paper's numbers, a ratio nearly "
                "constant from row to row ([which measure the paper shows](table_investigation.md))" if ratios else "")
             + f".  The second is {CONSECUTIVE}, the energy norm of Section 3 of the difference of consecutive "
             "solutions on the finer mesh, the measure Section 6's text names.", ""]
    lines += ["## Relative energy error", "",
              markdown_table(["$h$", "DOFs"] + [m.upper() for m in methods],
                             [[mesh_size(r["k"]), r["ndof"]] + [fmt(results[m][i]["true_relative"]) for m in methods]
                              for i, r in enumerate(first)]), "",
              "## Its observed rate", "",
              markdown_table(["$h$"] + [m.upper() for m in methods],
                             [[mesh_size(r["k"])] + [fmt(results[m][i]["true_rate"], ".3f") for m in methods]
                              for i, r in enumerate(first)]), "",
              f"## Consecutive differences {CONSECUTIVE}", "",
              markdown_table(["$h$"] + [m.upper() for m in methods],
                             [[mesh_size(r["k"])] + [fmt(results[m][i]["energy"]) for m in methods]
                              for i, r in enumerate(first)]), ""]
    for m in methods:
        rows = results[m]
        if rows[0]["paper_error"] is None and "uzawa_iterations" not in rows[0]:
            continue
        lines += [f"## {m.upper()}: ours against the paper", ""]
        table = []
        for r in rows:
            rate_diff = (r["true_rate"] - r["paper_rate"]) if (r["true_rate"] is not None and r["paper_rate"]) else None
            table.append([mesh_size(r["k"]), r["ndof"], fmt(r["true_relative"]), fmt(r["paper_error"]),
                          fmt(r["ratio"], ".3f"), fmt(r["true_rate"], ".3f"), fmt(r["paper_rate"], ".3f"),
                          fmt(rate_diff, "+.3f")])
        lines += [markdown_table(["$h$", "DOFs", "relative error", "paper", "ours / paper", "rate", "paper's rate",
                                  "rate difference"], table), ""]
        header = ["$h$", "consecutive", "consecutive / paper", "its rate", f"{args.solver.capitalize()} iterations",
                  "seconds"]
        with_uzawa = "uzawa_iterations" in rows[0]
        if with_uzawa:
            header += ["Uzawa iterations", "Uzawa seconds", "max. relative difference"]
        table = []
        for r in rows:
            line = [mesh_size(r["k"]), fmt(r["energy"]), fmt(r["consecutive_ratio"], ".2f"), fmt(r["rate"], ".3f"),
                    r["iterations"], f"{r['seconds']:.2f}"]
            if with_uzawa:
                line += [r["uzawa_iterations"], f"{r['uzawa_seconds']:.1f}", fmt(r["uzawa_difference"], ".1e")]
            table.append(line)
        solvers = " (Newton against the paper's Uzawa method)" if with_uzawa else ""
        lines += [f"The consecutive differences and the solvers{solvers}:", "",
                  markdown_table(header, table), ""]
    lines += ["Other norms of the consecutive differences are in the CSV (columns h1, l2, relative); "
              "[which measure the paper shows](table_investigation.md) compares every measure with the paper.", "",
              f"Regenerate: `{command_line()}`", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    run_script(main)
