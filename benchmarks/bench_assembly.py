"""Assembly cost of the five DG methods relative to SIPG (issue: the lifting methods).

For each method: the time to build the linear DG system (B_h and the load vector, with the
liftings of Bassi et al., Brezzi et al. and LDG) on uniform meshes of Example 6.1, its nonzeros,
and one sparse direct solve with it.  Times are the best of ``--repeat`` runs in one process.
Writes results/assembly_benchmark.md and .csv.

    python benchmarks/bench_assembly.py [--quick] [--repeat 4]
"""

import sys
import time
from pathlib import Path

import ngdgfric as ndf
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.sparse import direct_inverse
from ngdgfric.threads import threads

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
from common import command_line, run_script, say, script_parser, write_csv  # noqa: E402


def parse(argv=None):
    parser = script_parser(__doc__, "h = 2^-3 only, one run")
    parser.add_argument("--levels", type=int, nargs="+", default=[5, 6, 7], help="h = 2^-k")
    parser.add_argument("--repeat", type=int, default=2)
    return parser.parse_args(argv)


def measure(problem, mesh, method, repeat):
    best = float("inf")
    for _ in range(repeat):
        disc = ndf.Discretization(problem, mesh, method=method)
        best = min(best, disc.timings["assemble"])
    start = time.perf_counter()
    with threads(disc.V.ndof):
        inverse = direct_inverse(disc.A, disc.symmetric)
        x = disc.F.CreateVector()
        x.data = inverse * disc.F
    solve = time.perf_counter() - start
    return dict(ndof=disc.V.ndof, assemble=best, nonzeros=disc.A.nze, factor_solve=solve)


def main(argv=None):
    args = parse(argv)
    levels, repeat = ([3], 1) if args.quick else (args.levels, args.repeat)
    problem = ndf.example_6_1()
    rows = []
    for k in levels:
        mesh = ndf.uniform_mesh(problem, 2.0**-k)
        base = None
        for method in ndf.DG_METHODS:  # the five DG methods (the baseline cg has another space)
            row = dict(h=f"2^-{k}", method=method, **measure(problem, mesh, method, repeat))
            base = base or row
            row.update(assemble_ratio=row["assemble"] / base["assemble"],
                       nonzeros_ratio=row["nonzeros"] / base["nonzeros"],
                       solve_ratio=row["factor_solve"] / base["factor_solve"])
            rows.append(row)
            say(f"h = 2^-{k}, {method}: {row['ndof']} dofs, assemble {row['assemble']:.2f} s "
                f"({row['assemble_ratio']:.2f} x SIPG), {row['nonzeros']} nonzeros, solve {row['factor_solve']:.2f} s")
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(args.out / "assembly_benchmark.csv", rows)
    table = markdown_table(
        ["h", "method", "DOFs", "assemble s", "x SIPG", "nonzeros", "x SIPG", "factor+solve s", "x SIPG"],
        [[r["h"], r["method"], r["ndof"], f"{r['assemble']:.2f}", f"{r['assemble_ratio']:.2f}", r["nonzeros"],
          f"{r['nonzeros_ratio']:.2f}", f"{r['factor_solve']:.2f}", f"{r['solve_ratio']:.2f}"] for r in rows])
    text = "\n".join([
        "# Assembly of the five DG methods", "",
        "Example 6.1, P1, uniform meshes; assembly of B_h (with the lifting terms) and the load vector, best of",
        f"{repeat} runs; then one sparse direct factorisation + solve of the linear system (sparsecholesky for the",
        "symmetric methods, umfpack for NIPG).  Target: lifting methods <= 2x SIPG at ~1e5 DOFs.",
        "", table, "", f"Regenerate: `{command_line()}`", ""])
    write_text(args.out / "assembly_benchmark.md", text)
    say(text)
    return rows


if __name__ == "__main__":
    run_script(main)
