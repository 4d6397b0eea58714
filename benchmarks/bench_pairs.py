"""Pair benchmark: the contact solve of two bodies in contact (a ContactPair) against one linear solve of the same
mesh, M = 100 ... 5,000 pair points.

The scene: two strips stacked, each 1/16 high, of a length that gives about M pair points (``stacked_strips``):
the lower strip's bottom held (u_D = 0), the upper strip's top pushed down and along (u_D = (0.0005, -0.002)), the
interface a ContactPair (c_n = 100, c_tau = 0.002: stick in the middle, slip towards the ends), E = 1, nu = 0.3;
Netgen meshes that do not match at the interface (h = 1/64 above, 1.3/64 below), SIPG, p = 1 and 2 (p + 1 points
per edge of the pair's side, on the jump projected from the pieces of the common refinement).  Per size:

* pairing: ``Contact(disc).pairs`` (the pairs' points, the traces of both sides, the rows of B), and of it
  ``pair_points`` alone (the search of :mod:`ngdgfric.contact.pairing`);
* contact: ``ndf.solve(problem, mesh, method, order)`` with the default solver from zero (cold), end to end;
* linear: ``ndf.solve`` of the same problem without contact forces (the pair's c_tau = 0 and g_a = 1e6, as
  ``contact_free`` of scripts/common.py does for the foundation), end to end: the ratio contact / linear is the
  one benchmarks/bench_solvers.py reports;
* floor: assembly + one factorisation and back-substitution of A with NGSolve's fastest direct solver
  (``floor_solve`` of benchmarks/bench_solvers.py): a linear elasticity solve without any contact code;

best of ``--repeat`` runs in one process.  Writes results/pair_benchmark.md and .csv.

    python benchmarks/bench_pairs.py [--quick] [--points 100 300 1000 2500 5000] [--orders 1 2] [--repeat 3]

``--one contact|linear|floor`` builds the scene of ``--points[0]`` and ``--orders[0]`` and runs that solve once,
writing nothing: the whole-process timing of one solve from outside.
"""

import dataclasses
import sys
import time
from pathlib import Path

import ngdgfric as ndf
from ngdgfric.contact.pairing import pair_points
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_solvers import floor_solve  # noqa: E402
from common import best, command_line, run_script, say, script_parser, write_csv  # noqa: E402

METHOD = "sipg"
HEIGHT = 1 / 16
H_UPPER, H_LOWER = 1 / 64, 1.3 / 64
GOAL = 3.0  # contact / linear (issue 49)
FIELDS = ["order", "points", "pieces", "ndof", "pairing", "pair_points", "contact", "contact_its", "formulation",
          "linear", "floor", "ratio", "floor_ratio", "assemble", "condense", "newton", "recover"]


def stacked_strips(points, order):
    """The scene of the module docstring with a length that gives about ``points`` pair points at degree
    ``order`` (the law's points: order + 1 per edge of the pair's side, the upper strip's bottom)."""
    length = points * H_UPPER / (order + 1)
    lower = ndf.Loop([(0, 0), (length, 0), (length, HEIGHT), (0, HEIGHT)], ["bottom", "right1", "c1", "left1"])
    upper = ndf.Loop([(0, HEIGHT), (length, HEIGHT), (length, 2 * HEIGHT), (0, 2 * HEIGHT)],
                     ["c2", "right2", "top", "left2"])
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0, 0), g=(0, 0), c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
                                 geometry=ndf.Domain({"lower": lower, "upper": upper}), dirichlet=("bottom", "top"),
                                 traction=("right1", "left1", "right2", "left2"), contact=(),
                                 pairs=[ndf.ContactPair("c2", "c1", c_n=100.0, c_tau=0.002)],
                                 u_D={"top": (0.0005, -0.002)})
    return problem, ndf.netgen_mesh(problem, {"lower": H_LOWER, "upper": H_UPPER})


def without_contact(problem):
    """The same problem without contact forces: the pairs without friction, their gap one no displacement closes."""
    return dataclasses.replace(problem, pairs=[dataclasses.replace(pair, c_tau=0.0, g_a=1e6)
                                               for pair in problem.pairs])


def pairing(problem, mesh, order):
    """(seconds of ``Contact.pairs``, seconds of ``pair_points`` alone, the PairPoints) on a fresh discretisation."""
    disc = ndf.Discretization(problem, mesh, method=METHOD, order=order)
    start = time.perf_counter()
    (pair, points, _), = ndf.Contact(disc).pairs
    total = time.perf_counter() - start
    start = time.perf_counter()
    pair_points(disc.mesh, pair, order + 1, 0.1 * problem.geometry.diameter())
    return total, time.perf_counter() - start, points


def measure(points, order, repeat):
    """One row (module docstring)."""
    problem, mesh = stacked_strips(points, order)
    runs = [pairing(problem, mesh, order) for _ in range(repeat)]
    pairs_seconds, search_seconds = min(r[0] for r in runs), min(r[1] for r in runs)
    found = runs[0][2]
    contact_seconds, sol = best(repeat, lambda: ndf.solve(problem, mesh, method=METHOD, order=order))
    free = without_contact(problem)
    linear_seconds, _ = best(repeat, lambda: ndf.solve(free, mesh, method=METHOD, order=order))
    floor_seconds, _ = best(repeat, lambda: floor_solve(problem, mesh, METHOD, order))
    parts = sol.info["timings"]
    return dict(order=order, points=found.M, pieces=found.pieces, ndof=sol.ndof, pairing=pairs_seconds,
                pair_points=search_seconds, contact=contact_seconds, contact_its=sol.iterations,
                formulation=sol.info["linear_solver"], linear=linear_seconds, floor=floor_seconds,
                ratio=contact_seconds / linear_seconds, floor_ratio=contact_seconds / floor_seconds,
                assemble=sol.timings["setup"], condense=parts.get("condense", float("nan")),
                newton=parts.get("newton", float("nan")), recover=parts.get("recover", float("nan")))


def one(kind, points, order):
    """Build the scene and run one solve of ``kind`` (contact, linear or floor), for timing the whole process."""
    problem, mesh = stacked_strips(points, order)
    if kind == "contact":
        ndf.solve(problem, mesh, method=METHOD, order=order)
    elif kind == "linear":
        ndf.solve(without_contact(problem), mesh, method=METHOD, order=order)
    else:
        floor_solve(problem, mesh, METHOD, order)


def parse(argv=None):
    parser = script_parser(__doc__, "p = 1, M = 100 and 300, one run each (smoke test)")
    parser.add_argument("--points", type=int, nargs="+", default=[100, 300, 1000, 2500, 5000],
                        help="the numbers of pair points M (about)")
    parser.add_argument("--orders", type=int, nargs="+", default=[1, 2], help="the degrees p")
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement (best is kept)")
    parser.add_argument("--one", choices=("contact", "linear", "floor"),
                        help="run one solve of the first size and degree, write nothing")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse(argv)
    if args.one:
        return one(args.one, args.points[0], args.orders[0])
    sizes, orders = ([100, 300], [1]) if args.quick else (args.points, args.orders)
    repeat = 1 if args.quick else args.repeat
    rows = []
    args.out.mkdir(parents=True, exist_ok=True)
    for order in orders:
        for m in sizes:
            row = measure(m, order, repeat)
            rows.append(row)
            say(f"p = {order}, M = {row['points']}: {row['ndof']} DOFs | pairing {row['pairing']:.3f} s "
                f"(search {row['pair_points']:.3f} s) | contact {row['contact']:.2f} s ({row['contact_its']} its, "
                f"{row['formulation']}) | linear {row['linear']:.2f} s | floor {row['floor']:.2f} s | "
                f"contact/linear {row['ratio']:.2f}, /floor {row['floor_ratio']:.2f}")
            write_csv(args.out / "pair_benchmark.csv", rows, FIELDS)
            write_text(args.out / "pair_benchmark.md", report(rows))
    return rows


SETTING = """\
The scene: two strips stacked, each $1/16$ high, of a length that gives about $M$ pair points (`stacked_strips`):
the lower strip's bottom held ($u_D = 0$), the upper strip's top pushed down and along ($u_D = (0.0005, -0.002)$),
the interface a contact pair ($c_n = 100$, $c_\\tau = 0.002$: stick in the middle, slip towards the ends), $E = 1$,
$\\nu = 0.3$; Netgen meshes that do not match at the interface ($h = 1/64$ above, $1.3/64$ below), SIPG, $p = 1$ and
2 ($p + 1$ points per edge of the pair's side, on the jump projected from the pieces of the common refinement).  Per
size: the pairing (`Contact(disc).pairs`, and of it the search `pair_points` alone); the contact solve (`ndf.solve`
with the default solver from zero, end to end); the linear solve of the same problem without contact forces; and the
floor, assembly and one factorisation and back-substitution of $A$ with NGSolve's fastest direct solver (a linear
elasticity solve without any contact code).  Times in seconds, best of the runs in one process, 2 shared cores."""
"""The setting of the page (Markdown)."""


def report(rows):
    worst = max(rows, key=lambda r: r["ratio"])
    worst_floor = max(rows, key=lambda r: r["floor_ratio"])
    lines = ["# Pair benchmark: the contact solve of two bodies against one linear solve", "",
             f"The contact solve of two bodies on meshes that do not match at their interface (a contact pair), "
             f"from {min(r['points'] for r in rows)} to {max(r['points'] for r in rows)} pair points $M$, against "
             f"one linear solve of the same system: at most {worst['ratio']:.2f} times its seconds.", "",
             SETTING, "", "## Summary (computed)", "",
             f"- contact / linear at most {worst['ratio']:.2f} ($p = {worst['order']}$, $M = {worst['points']}$); "
             f"{sum(r['ratio'] <= GOAL for r in rows)} of {len(rows)} sizes within the goal {GOAL:g}.",
             f"- contact / floor at most {worst_floor['floor_ratio']:.2f} ($p = {worst_floor['order']}$, "
             f"$M = {worst_floor['points']}$); {sum(r['floor_ratio'] <= GOAL for r in rows)} of {len(rows)} within "
             f"{GOAL:g}.",
             f"- The pairing (`Contact.pairs`) takes at most {max(r['pairing'] / r['contact'] for r in rows):.1%} "
             "of the contact solve.", "",
             "## Contact against linear", ""]
    lines += [markdown_table(
        ["$p$", "$M$", "pieces", "DOFs", "contact seconds (iterations)", "solver", "linear seconds", "floor seconds",
         "contact / linear", "contact / floor"],
        [[r["order"], r["points"], r["pieces"], r["ndof"], f"{r['contact']:.2f} ({r['contact_its']})",
          r["formulation"], f"{r['linear']:.2f}", f"{r['floor']:.2f}", f"{r['ratio']:.2f}",
          f"{r['floor_ratio']:.2f}"] for r in rows]), "",
        "## Where the contact solve's seconds go", "",
        markdown_table(
        ["$p$", "$M$", "`Contact.pairs`", "of it `pair_points`", "assembly", "condensation", "Newton", "recovery"],
        [[r["order"], r["points"], f"{r['pairing']:.3f}", f"{r['pair_points']:.3f}", f"{r['assemble']:.2f}",
          f"{r['condense']:.2f}", f"{r['newton']:.2f}", f"{r['recover']:.2f}"] for r in rows]), "",
        f"Regenerate: `{command_line()}` (run alone: timings on a busy machine are meaningless).", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    run_script(main)
