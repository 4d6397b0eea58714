"""Reproduce Figures 6.1-6.4: the estimator on adaptive and uniform meshes, and adaptive meshes.

Porwal & Tanvi, Section 6: SOLVE -> ESTIMATE -> MARK -> REFINE with Doerfler theta = 0.3 and
newest vertex bisection, P1, eta = 30 mu.  Figure 6.1 (Example 6.1) and 6.3 (Example 6.2):
eta_h against the number of DOFs, log-log, adaptive and uniform, with a slope -1/2 line.
Figures 6.2 and 6.4: the adaptive meshes at level 28 (Example 6.1) and 23 (Example 6.2).
Writes results/figure_6_1.png ... figure_6_4.png, the data as CSV (adaptive_<example>_<method>.csv,
uniform_<example>_<method>.csv) and results/adaptivity_<example>.md.

    python scripts/adaptive.py --example 6.1 [--method sipg nipg ...] [--quick]
"""

import matplotlib
import numpy as np
from common import command_line, run_script, save_figure, say, script_parser, write_csv

import ngdgfric as ndf
from ngdgfric.dg.methods import METHODS
from ngdgfric.examples import EXAMPLES
from ngdgfric.files import write_text
from ngdgfric.meshes import mesh_arrays
from ngdgfric.output import markdown_table
from ngdgfric.studies import slope, strategy_run

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FIGURES = {"6.1": ("figure_6_1.png", "figure_6_2.png", 28), "6.2": ("figure_6_3.png", "figure_6_4.png", 23)}


def parse(argv=None):
    parser = script_parser(__doc__, "6 adaptive levels, 3 uniform meshes (smoke test)", example="one")
    parser.add_argument("--method", nargs="+", choices=sorted(METHODS), default=sorted(ndf.DG_METHODS),
                        help="default: the five DG methods of the paper")
    parser.add_argument("--levels", type=int, default=None, help="adaptive levels (default: paper's level + 12)")
    return parser.parse_args(argv)


def where_refined(problem, points, triangles, fraction=0.1):
    """Share of the smallest ``fraction`` of elements near the corners and near Gamma_C."""
    corners = np.asarray(problem.geometry.vertices)
    centers = points[triangles].mean(axis=1)
    a = points[triangles[:, 1]] - points[triangles[:, 0]]
    b = points[triangles[:, 2]] - points[triangles[:, 0]]
    areas = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    small = np.argsort(areas)[: max(1, int(fraction * len(areas)))]
    x0, y0, x1, y1 = problem.geometry.bounds
    size = max(x1 - x0, y1 - y0)
    near_corner = np.min(np.linalg.norm(centers[small, None, :] - corners[None], axis=2), axis=1) < 0.1 * size
    contact_edges = [k for k, label in enumerate(problem.geometry.labels) if label == problem.contact]
    distance = np.full(len(small), np.inf)
    for k in contact_edges:
        a, b = corners[k], corners[(k + 1) % len(corners)]
        d = b - a
        s = np.clip((centers[small] - a) @ d / (d @ d), 0, 1)
        distance = np.minimum(distance, np.linalg.norm(centers[small] - (a + s[:, None] * d), axis=1))
    near_contact = distance < 0.1 * size
    return float(near_corner.mean()), float(near_contact.mean()), float((near_corner | near_contact).mean())


def uniform_curve(problem, method, levels):
    """eta_h on uniform meshes h = 2^-1 ... 2^-levels, the estimator as printed in the paper like the adaptive runs
    it is drawn with: the uniform strategy of :func:`ngdgfric.studies.strategy_run`."""
    records = strategy_run(problem, "uniform", method=method, order=1, max_levels=levels, max_ndof=10**6,
                           variant="paper", progress=say)
    return [dict(h=2.0**-r["level"], ndof=r["ndof"], eta_h=r["eta_h"], iterations=r["iterations"]) for r in records]


def main(argv=None):
    args = parse(argv)
    problem = EXAMPLES[args.example]()
    tag = args.example.replace(".", "_")
    curve_png, mesh_png, paper_level = FIGURES[args.example]
    levels = 6 if args.quick else (args.levels or paper_level + 13)
    mesh_level = min(paper_level, levels - 1)
    args.out.mkdir(parents=True, exist_ok=True)
    adaptive, uniform, meshes, rows = {}, {}, {}, []
    for method in args.method:
        say(f"Example {args.example}, {method.upper()}: adaptive (theta = 0.3)")

        def keep(level, sol, est, method=method):
            if level == mesh_level:
                meshes[method] = mesh_arrays(sol.mesh)[:2]

        # the paper's loop: h-adaptive P1 with the estimator of Section 4 as printed
        adaptive[method] = ndf.adapt(problem, method=method, order=1, hp=False, theta=0.3, max_levels=levels,
                                     max_ndof=10**6, rtol=0, variant="paper", progress=say, keep=keep,
                                     csv_path=args.out / f"adaptive_{tag}_{method}.csv").levels
        say(f"Example {args.example}, {method.upper()}: uniform")
        uniform[method] = uniform_curve(problem, method, 3 if args.quick else 6)
        write_csv(args.out / f"uniform_{tag}_{method}.csv", uniform[method])
        last, tail, coarse = adaptive[method][-1], adaptive[method][-10:], uniform[method][-3:]
        corner, contact, either = where_refined(problem, *meshes[method])
        rows.append(dict(method=method, levels=len(adaptive[method]), ndof=last["ndof"], eta_h=last["eta_h"],
                         slope=slope([r["ndof"] for r in tail], [r["eta_h"] for r in tail]),
                         uniform_slope=slope([r["ndof"] for r in coarse], [r["eta_h"] for r in coarse]),
                         min_angle=min(r["min_angle"] for r in adaptive[method]),
                         overhead=(last["estimate_seconds"] + adaptive[method][-2]["mark_refine_seconds"])
                         / last["solve_seconds"],
                         near_corner=corner, near_contact=contact, near_either=either))
    plot_curves(args, adaptive, uniform, args.out / curve_png)
    plot_meshes(args, problem, meshes, mesh_level, args.out / mesh_png)
    write_text(args.out / f"adaptivity_{tag}.md", report(args, rows, curve_png, mesh_png, mesh_level))
    say(f"wrote {args.out / f'adaptivity_{tag}.md'}")
    return rows


def plot_curves(args, adaptive, uniform, path):
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for i, method in enumerate(adaptive):
        color = f"C{i}"
        ax.loglog([r["ndof"] for r in adaptive[method]], [r["eta_h"] for r in adaptive[method]], "o-", color=color,
                  ms=3, label=f"{method.upper()} adaptive")
        ax.loglog([r["ndof"] for r in uniform[method]], [r["eta_h"] for r in uniform[method]], "s--", color=color,
                  ms=4, label=f"{method.upper()} uniform")
    first = next(iter(adaptive.values()))
    n = np.array([first[0]["ndof"], first[-1]["ndof"]], dtype=float)
    ax.loglog(n, first[0]["eta_h"] * (n / n[0]) ** -0.5, "k:", label="slope -1/2")
    ax.set_xlabel("degrees of freedom")
    ax.set_ylabel(r"estimator $\eta_h$")
    ax.set_title(f"Example {args.example}: estimator, theta = 0.3")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, path, dpi=120)


def plot_meshes(args, problem, meshes, level, path):
    fig, axes = plt.subplots(1, len(meshes), figsize=(4.5 * len(meshes), 4.5), squeeze=False)
    for ax, (method, (points, triangles)) in zip(axes[0], meshes.items(), strict=True):
        ax.triplot(points[:, 0], points[:, 1], triangles, lw=0.3, color="k")
        ax.set_aspect("equal")
        ax.set_title(f"{method.upper()}, level {level}: {len(triangles)} elements")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(f"Example {args.example}: adaptive mesh")
    save_figure(fig, path, dpi=150)


def report(args, rows, curve_png, mesh_png, mesh_level):
    """The Markdown page: what was measured and what it shows, the figures, the tables, the command."""
    slopes = [r["slope"] for r in rows]
    uniform = [r["uniform_slope"] for r in rows]
    header = ["method", "levels", "final DOFs", "final $\\eta_h$", "adaptive slope (last 10)", "uniform slope (last 3)",
              "min. angle (degrees)", "(estimate + mark + refine) / solve, finest"]
    table = [[r["method"], r["levels"], r["ndof"], f"{r['eta_h']:.4e}", f"{r['slope']:.3f}",
              f"{r['uniform_slope']:.3f}", f"{r['min_angle']:.1f}", f"{r['overhead']:.2f}"] for r in rows]
    where = [[r["method"], f"{100 * r['near_corner']:.0f}%", f"{100 * r['near_contact']:.0f}%",
              f"{100 * r['near_either']:.0f}%"] for r in rows]
    return "\n".join([
        f"# Adaptivity, Example {args.example} (Figures {'6.1, 6.2' if args.example == '6.1' else '6.3, 6.4'})", "",
        f"The paper's adaptive loop on Example {args.example} for every DG method: the estimator $\\eta_h$ against "
        f"the DOFs $N$ falls like $N^{{-1/2}}$ (fitted slopes {min(slopes):.3f} to {max(slopes):.3f}, the optimal "
        f"order for $P_1$) against {min(uniform):.3f} to {max(uniform):.3f} on uniform meshes, and the mesh is "
        "refined at the corners where the boundary parts meet.", "",
        f"![estimator]({curve_png})", "", f"![mesh at level {mesh_level}]({mesh_png})", "",
        "Dörfler marking with $\\theta = 0.3$, Netgen newest vertex bisection (one bisection per marked "
        "element plus closure), $P_1$, $\\eta = 30\\mu$, semismooth Newton warm-started from the previous level.  "
        "Slopes are least-squares fits of $\\log \\eta_h$ against $\\log N$; optimal is $-1/2$.", "",
        markdown_table(header, table), "",
        "The paper reports that the mesh is refined most near the intersections of the boundary parts and "
        "along the contact edge.  Where the smallest 10% of the elements of the "
        f"level-{mesh_level} mesh lie (element centre within 10% of the domain size of a corner, of $\\Gamma_C$):", "",
        markdown_table(["method", "near corners", "near $\\Gamma_C$", "either"], where), "",
        "Newest vertex bisection creates no new angles, so the minimum angle over all levels equals the "
        "initial mesh's (45 degrees).", "",
        f"Regenerate: `{command_line()}`", ""])


if __name__ == "__main__":
    run_script(main)
