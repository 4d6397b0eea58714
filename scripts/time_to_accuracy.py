"""Time to an answer: ``adapt(problem, tol=t)`` against the cost of one linear solve of its final mesh.

For Examples 6.1 and 6.2 and t = 1e-1, 1e-2, 1e-3, 5e-4 (issue 15's criterion) and 1e-4:
``ndf.adapt(problem, tol=t, max_ndof=2e5)`` with its defaults (hp SIPG, p = 2..8, theta = 0.3,
every level solved fully), with theta = 0.7, and (t >= 5e-4) with inexact levels
(``gamma_lin=0.1``).  Reported per run: levels,
DOFs, the loop's seconds (solve + estimate + mark + refine, as recorded by ``adapt``), the seconds
of one linear solve on the final mesh (``ndf.solve`` of the same problem without contact,
c_tau = 0 and g_a = 1e6, same orders: assembly + factorisation + substitution, best of 3), their
ratio, the Newton iterations, and the true energy error |||u_ref - u_h|||_h of the answer against
the stored hp references (results/reference.md); also the contact points M of the final mesh and
the seconds of its contact solve (the dense Newton work grows like M^3).  Timings on a shared
2-core machine, one run at a time.

Writes results/time_to_accuracy.csv, .md and .png.
"""

import argparse
import dataclasses
import time
from pathlib import Path

from common import EXAMPLES, command_line, fmt, markdown_table, results_path, save_figure, say, write_csv

import ngdgfric as ndf
from ngdgfric.reference import energy_error, load_reference

TOLERANCES = (1e-1, 1e-2, 1e-3, 5e-4, 1e-4)
VARIANTS = {"defaults": {}, "theta 0.7": dict(theta=0.7), "gamma_lin 0.1": dict(gamma_lin=0.1)}
INEXACT_DOWN_TO = 5e-4  # smallest tol run with inexact levels (on 6.1 they steer hp into Gamma_C: slow)
MAX_NDOF = 200000
FIELDS = ["example", "variant", "tol", "levels", "ndof", "p_max", "contact_points", "stopped", "loop_seconds",
          "solve_seconds", "estimate_seconds", "mark_refine_seconds", "final_solve_seconds", "linear_seconds",
          "ratio", "iterations", "eta", "error"]


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="Example 6.2, tol = 1e-1 only (for the tests)")
    parser.add_argument("--out", type=str, default=None, help="folder for the outputs (default results/)")
    return parser.parse_args(argv)


def linear_seconds(problem, mesh, orders, repeat=3):
    """Best of ``repeat`` end-to-end solves of the problem without contact on ``mesh`` with ``orders``."""
    free = dataclasses.replace(problem, c_tau=0.0, g_a=1e6)
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        ndf.solve(free, mesh, order=orders)
        best = min(best, time.perf_counter() - start)
    return best


def run(example, variant, tol):
    """One adaptive run and its row."""
    problem = EXAMPLES[example]()
    reference = load_reference(results_path(f"reference_{example.replace('.', '_')}.npz"), problem)
    result = ndf.adapt(problem, tol=tol, max_ndof=MAX_NDOF, progress=None, **VARIANTS[variant])
    levels = result.levels
    seconds = {key: sum(r[f"{key}_seconds"] for r in levels) for key in ("solve", "estimate", "mark_refine")}
    loop = sum(seconds.values())
    sol = result.solution
    linear = linear_seconds(problem, sol.mesh, sol.discretization.orders)
    return dict(example=example, variant=variant, tol=tol, levels=len(levels), ndof=sol.ndof,
                p_max=levels[-1]["p_max"], contact_points=sol.info["contact_points"], stopped=result.stopped,
                loop_seconds=loop, final_solve_seconds=levels[-1]["solve_seconds"],
                **{f"{key}_seconds": value for key, value in seconds.items()}, linear_seconds=linear,
                ratio=loop / linear, iterations=sum(r["iterations"] for r in levels), eta=result.estimate.total,
                error=energy_error(sol, reference))


def main(argv=None):
    args = parse(argv)
    out = results_path("") if args.out is None else Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    examples, tolerances = (("6.2",), (1e-1,)) if args.quick else (("6.1", "6.2"), TOLERANCES)
    rows = []
    for example in examples:
        for tol in tolerances:
            for variant in VARIANTS:
                if "gamma_lin" in VARIANTS[variant] and tol < INEXACT_DOWN_TO:
                    continue
                rows.append(run(example, variant, tol))
                r = rows[-1]
                say(f"{example} tol {tol:g} {variant}: {r['levels']} levels, {r['ndof']} dofs, loop "
                    f"{r['loop_seconds']:.2f} s, linear {r['linear_seconds']:.3f} s, ratio {r['ratio']:.1f}, "
                    f"error {r['error']:.3e}")
                write_csv(out / "time_to_accuracy.csv", rows, FIELDS)
                report(rows, out)  # after every run: an interrupted study keeps what it measured
                plot(rows, out / "time_to_accuracy.png")
    return rows


def report(rows, out):
    lines = ["# Time to an answer: adapt(problem, tol) against one linear solve of its final mesh", "",
             __doc__.split("\n\n")[1].replace("\n", " "), "",
             "![loop seconds and ratio against the true error](time_to_accuracy.png)", ""]
    header = ["example", "variant", "tol", "levels", "DOFs", "p max", "M", "stopped", "loop s", "solve s",
              "estimate s", "mark+refine s", "last solve s", "linear s", "loop / linear", "Newton its", "eta_h",
              "true error"]
    table = [[r["example"], r["variant"], f"{r['tol']:g}", r["levels"], r["ndof"], r["p_max"], r["contact_points"],
              r["stopped"], fmt(r["loop_seconds"], ".2f"), fmt(r["solve_seconds"], ".2f"),
              fmt(r["estimate_seconds"], ".2f"), fmt(r["mark_refine_seconds"], ".2f"),
              fmt(r["final_solve_seconds"], ".2f"), fmt(r["linear_seconds"], ".3f"), fmt(r["ratio"], ".1f"),
              r["iterations"], fmt(r["eta"], ".3e"), fmt(r["error"], ".3e")] for r in rows]
    lines += [markdown_table(header, table), "", f"Regenerate: `{command_line()}`", ""]
    ndf.files.write_text(out / "time_to_accuracy.md", "\n".join(lines))


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    series = sorted({(r["example"], r["variant"]) for r in rows})
    for (example, variant), marker in zip(series, "osd^v<>", strict=False):
        chosen = [r for r in rows if (r["example"], r["variant"]) == (example, variant)]
        label = f"{example}, {variant}"
        axes[0].loglog([r["error"] for r in chosen], [r["loop_seconds"] for r in chosen], marker + "-", label=label)
        axes[1].semilogx([r["error"] for r in chosen], [r["ratio"] for r in chosen], marker + "-", label=label)
    axes[0].set(xlabel="true energy error of the answer", ylabel="loop seconds")
    axes[1].set(xlabel="true energy error of the answer", ylabel="loop / one linear solve of the final mesh")
    axes[1].axhline(5, color="gray", lw=0.8, ls="--")
    for ax in axes:
        ax.invert_xaxis()
        ax.legend(fontsize=7)
    save_figure(fig, path)


if __name__ == "__main__":
    main()
