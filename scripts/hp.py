"""hp-adaptivity against h-adaptivity and uniform refinement, measured against reference solutions.

Beyond the paper, whose Section 6 (Figures 6.1-6.4) refines in h only, in P1.

For each example: uniform P1, P2, P3; h-adaptive P1, P2, P3 (Doerfler theta = 0.5, bisection);
hp-adaptive (p from 2, Melenk-Wohlmuth decision, :mod:`ngdgfric.hp`); SIPG, semismooth Newton.
Per level: DOFs, eta_h, the true error |||u_ref - u_h|||_h against results/reference_<example>.npz
(scripts/reference.py) and seconds.  Writes results/hp_<example>.csv, hp_<example>.png (eta_h and
error against DOFs), hp_exponential_<example>.png (log eta_h against N^(1/3)), hp_mesh_<example>.png
(final hp mesh coloured by order) and results/hp.md.

    python scripts/hp.py [--example 6.1 6.2] [--quick]
"""

from pathlib import Path

import matplotlib
import numpy as np
from common import RESULTS, command_line, run_script, save_figure, say, script_parser, write_csv

import ngdgfric as ndf
from ngdgfric.examples import EXAMPLES
from ngdgfric.files import write_text
from ngdgfric.meshes import mesh_arrays
from ngdgfric.output import markdown_table
from ngdgfric.studies import strategy_run

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RUNS = [("uniform", 1), ("uniform", 2), ("uniform", 3), ("h", 1), ("h", 2), ("h", 3), ("hp", 2)]
STYLE = {"uniform": ("s", "--"), "h": ("o", "-"), "hp": ("D", "-")}
THETA = 0.5  # Doerfler's theta of the h- and hp-adaptive runs


def parse(argv=None):
    parser = script_parser(__doc__, "small runs against a coarse reference (smoke test)", example="many")
    parser.add_argument("--max-ndof", type=int, default=200_000, help="for uniform and h-adaptive runs")
    parser.add_argument("--hp-max-ndof", type=int, default=30_000)
    parser.add_argument("--max-order", type=int, default=8)
    parser.add_argument("--reference", type=Path, default=RESULTS, help="folder of reference_<example>.npz")
    return parser.parse_args(argv)


def label(strategy, order):
    return "hp-adaptive" if strategy == "hp" else f"{'uniform' if strategy == 'uniform' else 'h-adaptive'} P{order}"


def exponential_fit(records, last=5):
    """Least-squares line log eta_h = a + b N^(1/3) over the last levels; (b, max residual)."""
    n = np.array([r["ndof"] for r in records[-last:]]) ** (1 / 3)
    e = np.log([r["eta_h"] for r in records[-last:]])
    b, a = np.polyfit(n, e, 1)
    return float(b), float(np.max(np.abs(a + b * n - e)))


def dofs_to_reach(records, error):
    """DOFs at which a run's error first falls to ``error`` (log-log interpolation), None if never."""
    for prev, rec in zip(records[:-1], records[1:], strict=True):
        if rec["error"] <= error:
            t = np.log(prev["error"] / error) / np.log(prev["error"] / rec["error"])
            return float(np.exp(np.log(prev["ndof"]) + t * np.log(rec["ndof"] / prev["ndof"])))
    return None


def run_example(example, args, budget):
    problem = EXAMPLES[example]()
    reference = ndf.load_reference(args.reference / f"reference_{example.replace('.', '_')}.npz", problem)
    runs, final = {}, {}

    def keep_mesh(level, sol, est):  # the last hp mesh, for the picture
        final["points"], final["triangles"] = mesh_arrays(sol.mesh)[:2]
        final["orders"] = sol.discretization.orders.copy()

    for strategy, order in RUNS:
        say(f"Example {example}: {label(strategy, order)}")
        max_ndof = budget["hp"] if strategy == "hp" else budget["max"] // (1 if order == 1 else 2)
        # explicit, so that adapt's defaults (theta = 0.8, geometric layers since issue 28) leave the study as it is
        options = dict(keep=keep_mesh, theta=THETA, layers=0) if strategy == "hp" else {}
        if strategy == "h":
            options["theta"] = THETA
        runs[label(strategy, order)] = strategy_run(problem, strategy, order=order, reference=reference,
                                                    max_ndof=max_ndof, max_order=args.max_order, progress=say,
                                                    **options)
    return runs, final, reference


def plot(example, runs, final, out):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for name, records in runs.items():
        marker, line = STYLE[name.split()[0].split("-")[0]]
        for ax, key in zip(axes, ("eta_h", "error"), strict=True):
            ax.loglog([r["ndof"] for r in records], [r[key] for r in records], marker=marker, linestyle=line,
                      markersize=3, label=name)
    for ax, title in zip(axes, ("estimator $\\eta_h$", "true error $|||u_{ref} - u_h|||_h$"), strict=True):
        ax.set_xlabel("degrees of freedom")
        ax.set_title(f"Example {example}: {title}")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    save_figure(fig, out / f"hp_{example.replace('.', '_')}.png", dpi=110)

    hp = runs["hp-adaptive"]
    b, residual = exponential_fit(hp)
    n = np.array([r["ndof"] for r in hp]) ** (1 / 3)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.semilogy(n, [r["eta_h"] for r in hp], "D-", markersize=3, label="$\\eta_h$")
    ax.semilogy(n, [r["error"] for r in hp], "o-", markersize=3, label="true error")
    tail = n[-5:]
    ax.semilogy(tail, np.exp(np.log(hp[-1]["eta_h"]) + b * (tail - tail[-1])), "k:", label=f"fit, slope {b:.3f}")
    ax.set_xlabel("$N^{1/3}$")
    ax.set_title(f"Example {example}: hp-adaptive, exponential convergence")
    ax.legend()
    ax.grid(True, alpha=0.3)
    save_figure(fig, out / f"hp_exponential_{example.replace('.', '_')}.png", dpi=110)

    fig, ax = plt.subplots(figsize=(6.5, 6))
    pts, tri = final["points"], final["triangles"]
    art = ax.tripcolor(pts[:, 0], pts[:, 1], tri, facecolors=final["orders"].astype(float), edgecolors="k",
                       linewidth=0.3, cmap=plt.get_cmap("viridis", int(final["orders"].max()) - 1))
    fig.colorbar(art, ax=ax, label="polynomial order p_T")
    ax.set_aspect("equal")
    ax.set_title(f"Example {example}: final hp mesh ({len(tri)} elements)")
    save_figure(fig, out / f"hp_mesh_{example.replace('.', '_')}.png", dpi=110)
    return b, residual


def effectivity_range(runs, floor=1e-3):
    values = [r["eta_h"] / r["error"] for records in runs.values() for r in records if r["error"] >= floor]
    return f"{min(values):.2f} - {max(values):.2f}" if values else "-"


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    budget = dict(max=4000, hp=2000) if args.quick else dict(max=args.max_ndof, hp=args.hp_max_ndof)
    setting = (f"SIPG, $\\eta = 30\\mu$, semismooth Newton, Dörfler $\\theta = {THETA}$, no geometric layers.  hp: "
               f"$p$ from 2 up to {args.max_order}, marked elements refined in $p$ where the estimator fell as "
               "predicted for a smooth solution and in $h$ (two bisections) elsewhere (Melenk & Wohlmuth 2001, "
               "`ngdgfric.hp`).  True errors $|\\!|\\!| u_\\mathrm{ref} - u_h |\\!|\\!|_h$ against the hp reference "
               "solutions of [the reference page](reference.md) (made by the same hp loop with the paper's estimator, "
               "so the meshes here are not nested in theirs).  $\\eta_h$ is the default estimator (energy units, "
               "`ndf.estimate`; [its effectivity](effectivity.md)).  Timings: 2-core machine, one run at a time.")
    lines, factors = [], {}
    for example in args.example:
        runs, final, reference = run_example(example, args, budget)
        rows = [dict(run=name, **r) for name, records in runs.items() for r in records]
        write_csv(args.out / f"hp_{example.replace('.', '_')}.csv", rows,
                  ["run", "level", "ndof", "eta_h", "error", "seconds", "iterations", "p_max"])
        b, residual = plot(example, runs, final, args.out)
        target = runs["h-adaptive P1"][-1]
        needed = dofs_to_reach(runs["hp-adaptive"], target["error"])
        factor = target["ndof"] / needed if needed else None
        factors[example] = factor
        table = [[name, len(records), records[-1]["ndof"], f"{records[-1]['eta_h']:.3e}", f"{records[-1]['error']:.3e}",
                  f"{records[-1]['seconds']:.1f}"] for name, records in runs.items()]
        lines += [f"## Example {example}", "",
                  f"![estimator and error](hp_{example.replace('.', '_')}.png)", "",
                  markdown_table(["run", "levels", "final DOFs", "final $\\eta_h$", "final error", "seconds"], table),
                  "", f"- The h-adaptive $P_1$ run (the loop of Figure 6.{1 if example == '6.1' else 3}, default "
                  f"estimator) ends with error "
                  f"{target['error']:.3e} at {target['ndof']} DOFs; hp reaches that error with "
                  + (f"{needed:.0f} DOFs: **{factor:.0f} times fewer** (goal: 10)." if needed else
                     "- (not reached within its DOF budget)."),
                  f"- $\\log \\eta_h$ against $N^{{1/3}}$ over the last five hp levels: slope {b:.3f}, largest fit "
                  f"residual {residual:.3f} (in $\\log \\eta_h$): a straight line, i.e. exponential convergence "
                  f"$\\eta_h \\sim \\exp({b:.3f} N^{{1/3}})$.",
                  f"- $\\eta_h$ / true error over the levels with error $\\ge 10^{{-3}}$ (30 times the reference's "
                  f"estimated error): {effectivity_range(runs)}.",
                  f"- Reference: {reference.description}.", "",
                  f"![exponential convergence](hp_exponential_{example.replace('.', '_')}.png)", "",
                  f"![final hp mesh](hp_mesh_{example.replace('.', '_')}.png)", ""]
    fewer = [f"{factor:.0f}" for factor in factors.values() if factor]
    headline = ("hp-adaptivity against h-adaptive and uniform refinement of every degree on the paper's examples "
                f"({', '.join(factors)}), measured by the true error"
                + (f": hp reaches the final error of the paper's h-adaptive $P_1$ loop with {' and '.join(fewer)} "
                   "times fewer DOFs, and its estimator falls exponentially in $N^{1/3}$." if fewer else "."))
    lines = ["# hp-adaptivity", "", headline, "", setting, "", *lines,
             f"Regenerate: `{command_line()}` (after `python scripts/reference.py`)", ""]
    write_text(args.out / "hp.md", "\n".join(lines))
    say("\n".join(lines))


if __name__ == "__main__":
    run_script(main)
