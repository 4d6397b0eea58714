"""The five DG methods at their own cost: assembly and one solve of Bassi et al., Brezzi et al. and LDG against SIPG.

The liftings of Bassi et al. (local, one per edge) and of Brezzi et al. and LDG (the global r_0, whose stencil
reaches the neighbours' neighbours) are assembled from the moments of the jumps and small element kernels
(ngdgfric.dg.liftings).  Measured, in one process, best of ``--repeat`` runs, wall seconds of
``Discretization(...).timings["assemble"]`` (B_h with the lifting terms and the load vector):

1. uniform meshes: Example 6.2, h = 1/16, p = 1 ... 8, with each method's nonzeros per row;
2. an hp mesh: the final mesh and degrees of ``adapt(example_6_1(), method="sipg", tol=1e-4)`` (layers towards the
   corners, p = 4 ... 8 per element);
3. curved elements: the shipped block with a circular hole, Netgen maxh = 0.25, p = 1 ... 8;
4. one solve of Example 6.2, h = 1/16, p = 1, 4, 7 (``ndf.solve(...).timings``: assembly, contact solve, total),
   and what the global lifting's stencil costs the factorisation.

Writes results/assembly_benchmark.md and .csv.

    python benchmarks/bench_assembly.py [--quick] [--repeat 3]
"""

import sys
import warnings
from pathlib import Path

import ngdgfric as ndf
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
from common import command_line, run_script, say, script_parser, write_csv  # noqa: E402

METHODS = ("sipg", "bassi", "brezzi", "ldg")


def parse(argv=None):
    parser = script_parser(__doc__, "h = 1/4, p = 1 and 2, a small hp mesh, one run each")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--orders", type=int, nargs="+", default=list(range(1, 9)))
    return parser.parse_args(argv)


def assembly(problem, mesh, order, repeat):
    """{method: (best assembly seconds, DOFs, nonzeros per row)} on one mesh, methods alternating."""
    best = {}
    for _ in range(repeat):
        for method in METHODS:
            disc = ndf.Discretization(problem, mesh, method=method, order=order)
            seconds = disc.timings["assemble"]
            previous = best.get(method, (float("inf"),))[0]
            best[method] = (min(previous, seconds), disc.V.ndof, disc.A.nze / disc.V.ndof)
    return best


def rows_of(scene, label, best):
    sipg = best["sipg"]
    return [dict(scene=scene, p=label, method=method, ndof=ndof, assemble=seconds, ratio=seconds / sipg[0],
                 nonzeros_per_row=per_row, nonzeros_ratio=per_row / sipg[2])
            for method, (seconds, ndof, per_row) in best.items()]


def hp_mesh(quick):
    """(problem, mesh, degrees) of an hp-adaptive SIPG run on Example 6.1."""
    problem = ndf.example_6_1()
    run = ndf.adapt(problem, method="sipg", tol=1e-2 if quick else 1e-4, progress=None)
    return problem, run.solution.mesh, run.solution.orders


def solves(problem, mesh, order, repeat):
    """{method: (assembly, contact solve, total seconds)} of one ndf.solve each, best total of ``repeat``."""
    best = {}
    for _ in range(repeat):
        for method in METHODS:
            t = ndf.solve(problem, mesh, method=method, order=order).timings
            if method not in best or t["total"] < best[method][2]:
                best[method] = (t["assemble"], t["solve"], t["total"])
    return best


def main(argv=None):
    args = parse(argv)
    repeat, orders, h = (1, [1, 2], 1 / 4) if args.quick else (args.repeat, args.orders, 1 / 16)
    rows = []
    example = ndf.example_6_2()
    mesh = ndf.uniform_mesh(example, h)
    for order in orders:
        rows += rows_of("uniform", order, assembly(example, mesh, order, repeat))
        say(_line(rows[-4:]))
    problem, hp, degrees = hp_mesh(args.quick)
    rows += rows_of("hp", f"{degrees.min()}-{degrees.max()}", assembly(problem, hp, degrees, repeat))
    say(_line(rows[-4:]))
    hole = ndf.load_problem(ndf.example_file("block_with_hole"))
    curved = ndf.netgen_mesh(hole, 0.25)
    for order in orders:
        rows += rows_of("curved", order, assembly(hole, curved, order, repeat))
        say(_line(rows[-4:]))
    solve_rows = []
    for order in ([1] if args.quick else [1, 4, 7]):
        best = solves(example, mesh, order, min(repeat, 2))
        for method, (assemble, solve, total) in best.items():
            solve_rows.append(dict(p=order, method=method, assemble=assemble, solve=solve, total=total,
                                   ratio=total / best["sipg"][2]))
        say(_line(solve_rows[-4:], key="total"))
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(args.out / "assembly_benchmark.csv", rows)
    write_csv(args.out / "solve_benchmark.csv", solve_rows)
    write_text(args.out / "assembly_benchmark.md", report(rows, solve_rows, repeat, h))
    return rows, solve_rows


def _line(rows, key="assemble"):
    return ", ".join(f"{r['method']} {r[key]:.3f} s ({r['ratio']:.2f} x)" for r in rows) + \
        (f"  [{rows[0].get('scene', 'solve')} p = {rows[0]['p']}]" if rows else "")


def report(rows, solve_rows, repeat, h):
    def table(scene):
        chosen = [r for r in rows if r["scene"] == scene]
        labels = list(dict.fromkeys(r["p"] for r in chosen))
        seconds, stencil = [], []
        for label in labels:
            by = {r["method"]: r for r in chosen if r["p"] == label}
            seconds.append([label, by["sipg"]["ndof"]] + [f"{by[m]['assemble']:.3f}" for m in METHODS] +
                           [f"{by[m]['ratio']:.2f}" for m in METHODS[1:]])
            stencil.append([label, by["sipg"]["ndof"]] + [f"{by[m]['nonzeros_per_row']:.0f}" for m in METHODS])
        return "\n\n".join([
            markdown_table(["$p$", "DOFs"] + [f"{m} seconds" for m in METHODS] + [f"{m} / SIPG" for m in METHODS[1:]],
                           seconds),
            "Nonzeros per row of the matrix:",
            markdown_table(["$p$", "DOFs"] + list(METHODS), stencil)])

    worst = max(r["ratio"] for r in rows if r["method"] != "sipg")
    solve_table = markdown_table(
        ["$p$", "method", "assembly seconds", "contact solve seconds", "total seconds", "total / SIPG"],
        [[r["p"], r["method"], f"{r['assemble']:.3f}", f"{r['solve']:.3f}", f"{r['total']:.3f}", f"{r['ratio']:.2f}"]
         for r in solve_rows])
    return "\n".join([
        "# The five DG methods at their own cost", "",
        "What assembling each DG method costs against SIPG on uniform, hp and curved meshes, and what that does to "
        f"one solve: the methods with a lifting operator take up to {worst:.2f} times SIPG's assembly seconds, and "
        "those of Brezzi et al. and LDG have the wider stencil.", "",
        f"Wall seconds of the assembly of $B_h$ with its lifting terms and of the load vector (best of {repeat} runs",
        "in one process, the methods alternating; 2 cores; NGSolve's TaskManager from 20,000 DOFs), the ratio to",
        "SIPG on the same mesh and degrees, and the nonzeros per row of the matrix (Bassi et al. has SIPG's stencil;",
        "the global lifting $r_0$ of Brezzi et al. and LDG reaches the neighbours' neighbours).  Largest assembly",
        f"ratio over all rows: {worst:.2f}.", "",
        f"## Uniform meshes: Example 6.2, $h = {h:g}$", "", table("uniform"), "",
        "## An hp mesh: the final mesh of `adapt(example_6_1(), method='sipg', tol=1e-4)`", "", table("hp"), "",
        "## Curved elements: the block with a hole, Netgen maxh = 0.25", "", table("curved"), "",
        f"## One solve: Example 6.2, $h = {h:g}$ (`ndf.solve(...).timings`; best total of {min(repeat, 2)})", "",
        solve_table, "",
        "The contact solve of Brezzi et al. and LDG factorises the matrix of the larger stencil above.", "",
        f"Regenerate: `{command_line()}`", ""])


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ndf.PenaltyWarning)
        run_script(main)
