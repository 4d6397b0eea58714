"""What the guaranteed bound costs: ``ndf.estimate(sol, kind="equilibrated")`` against one linear solve of the mesh.

Cases: Examples 6.1, 6.2 and the manufactured solution with data that are not polynomials (``any data`` of
scripts/effectivity.py, E = 1e3, nu = 0.3); SIPG, Bassi et al. and the conforming baseline cg, p = 1..4 on uniform
meshes h = 1/16 and 1/32; and the final hp meshes of ``adapt(problem, tol=1e-3)`` (cg, p up to 8) and of
``adapt(problem, method="sipg", tol=1e-2)`` on both examples.  Per mesh, in one process, best of ``--repeat``:

* ``linear``: ``ndf.solve`` of the problem without contact (c_tau = 0, a gap nothing closes), same method and
  degrees, end to end (assembly included): the cost unit the issue names, as in results/solver_benchmark.md;
* ``bound``: ``ndf.estimate(sol, kind="equilibrated")`` of the contact solution, end to end: the potential (one
  conforming solve of degree p_T + 1), the stress (one statically condensed mixed solve on the edges, RT of
  degree p_T, p_T + 2 on the contact elements) and the integrals of the bound;
* ``contact``: the contact solve itself, for scale.

Writes results/equilibration_cost.md and .csv.

    python benchmarks/bench_equilibration.py [--quick] [--repeat 3]    # about 10 minutes; run it alone
"""

import sys
import time
from pathlib import Path

import ngdgfric as ndf
from ngdgfric.examples import example
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.studies import manufactured

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
from common import best, command_line, contact_free, run_script, say, script_parser, write_csv  # noqa: E402

CASES = ("6.1", "6.2", "any data")
METHODS = ("sipg", "bassi", "cg")
ORDERS = (1, 2, 3, 4)
SIZES = (1 / 16, 1 / 32)
LARGE = 10_000  # the claim is made on meshes of at least this many DOFs (below, fixed costs dominate)
FIELDS = ["case", "mesh", "method", "ndof", "p_max", "linear_seconds", "bound_seconds", "contact_seconds",
          "bound_over_linear", "guaranteed"]


def parse(argv=None):
    parser = script_parser(__doc__, "one case, p = 1 and 2 on h = 1/8, no hp meshes (smoke test)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement (best is kept)")
    return parser.parse_args(argv)


def problem_of(case):
    if case == "any data":
        return manufactured.incompressible_contact_manufactured(E=1e3, nu=0.3, c_n=10.0)[0]
    return example(case)


def meshes(case, quick):
    """(label, method, mesh, orders) of every measurement of a case."""
    problem = problem_of(case)
    out = []
    for h in (1 / 8,) if quick else SIZES:
        mesh = ndf.uniform_mesh(problem, h)
        out += [(f"uniform h = 1/{round(1 / h)}, p = {p}", method, mesh, p)
                for method in (METHODS[:1] if quick else METHODS) for p in ((1, 2) if quick else ORDERS)]
    if not quick and case != "any data":
        for method, tol in (("cg", 1e-3), ("sipg", 1e-2)):
            run = ndf.adapt(problem, method=method, tol=tol, progress=None)
            out.append((f"hp, adapt(tol={tol:g})", method, run.solution.mesh, run.solution.orders))
    return out


def measure(case, label, method, mesh, orders, repeat):
    problem = problem_of(case)
    linear, _ = best(repeat, lambda: ndf.solve(contact_free(problem), mesh, method=method, order=orders))
    contact, sol = best(repeat, lambda: ndf.solve(problem, mesh, method=method, order=orders))
    bound, est = best(repeat, lambda: ndf.estimate(sol, kind="equilibrated"))
    return dict(case=case, mesh=label, method=method, ndof=sol.ndof, p_max=int(sol.orders.max()),
                linear_seconds=linear, bound_seconds=bound, contact_seconds=contact, bound_over_linear=bound / linear,
                guaranteed=est.guaranteed)


def report(rows, seconds):
    large = [r for r in rows if r["ndof"] >= LARGE]
    ratios = [r["bound_over_linear"] for r in large] or [float("nan")]
    hp = [r["bound_over_linear"] for r in large if r["mesh"].startswith("hp")] or [float("nan")]
    lines = ["# The cost of the guaranteed bound", "",
             "What the guaranteed error bound costs: the seconds of `ndf.estimate(sol, kind=\"equilibrated\")` "
             "against one linear solve of the same mesh, method and degrees (`ndf.solve` without contact, assembly "
             f"included).  On meshes of at least {LARGE:,} DOFs it costs {min(ratios):.2f} to {max(ratios):.2f} "
             f"linear solves; it is guaranteed on {sum(bool(r['guaranteed']) for r in rows)} of {len(rows)} meshes.",
             "",
             "The cases: Examples 6.1, 6.2 and the manufactured solution with data that are not polynomials (the "
             "*any data* family of [the effectivity page](effectivity.md), $E = 10^3$, $\\nu = 0.3$); SIPG, Bassi "
             "et al. and the conforming baseline `cg`, $p = 1, \\dots, 4$ on uniform meshes $h = 1/16$ and $1/32$; "
             "and the final hp meshes of `adapt(problem, tol=1e-3)` (`cg`, $p$ up to 8) and of "
             "`adapt(problem, method=\"sipg\", tol=1e-2)` on both examples.  Best of several runs in one process on a "
             "shared 2-core machine; the contact solve itself is shown for scale.", "",
             "## Summary", "",
             f"- Meshes of at least {LARGE:,} DOFs ({len(large)}): the bound costs {min(ratios):.2f} - "
             f"{max(ratios):.2f} linear solves; on the hp meshes {min(hp):.2f} - {max(hp):.2f}.",
             f"- Below {LARGE:,} DOFs (fixed costs of assembling three small systems dominate): "
             + (f"{min(r['bound_over_linear'] for r in rows if r['ndof'] < LARGE):.2f} - "
                f"{max(r['bound_over_linear'] for r in rows if r['ndof'] < LARGE):.2f}."
                if any(r["ndof"] < LARGE for r in rows) else "none."),
             f"- Guaranteed on {sum(bool(r['guaranteed']) for r in rows)} of {len(rows)} meshes.", "",
             markdown_table(["case", "mesh", "method", "DOFs", "$p$ max", "linear seconds", "bound seconds",
                             "contact seconds", "bound / linear"],
                            [[r["case"], r["mesh"], r["method"], r["ndof"], r["p_max"], f"{r['linear_seconds']:.3f}",
                              f"{r['bound_seconds']:.3f}", f"{r['contact_seconds']:.3f}",
                              f"{r['bound_over_linear']:.2f}"] for r in rows]), "",
             f"Regenerate: `{command_line()}` ({seconds:.0f} s)", ""]
    return "\n".join(lines)


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    rows, start = [], time.perf_counter()
    csv_path, md_path = args.out / "equilibration_cost.csv", args.out / "equilibration_cost.md"
    for case in CASES[1:2] if args.quick else CASES:
        for label, method, mesh, orders in meshes(case, args.quick):
            rows.append(measure(case, label, method, mesh, orders, 1 if args.quick else args.repeat))
            r = rows[-1]
            say(f"{case} {label} {method}: {r['ndof']} DOFs, bound {r['bound_seconds']:.3f} s = "
                f"{r['bound_over_linear']:.2f} linear solves")
            write_csv(csv_path, rows, FIELDS)
            write_text(md_path, report(rows, time.perf_counter() - start))
    return rows


if __name__ == "__main__":
    run_script(main)
