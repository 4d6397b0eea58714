"""Newton's iterations level by level: where an adaptive run's contact solves spend their time.

For each scene, ``ndf.adapt`` with its defaults (the method it picks, hp from p = 4, warm starts) and per level:
the contact points M, Newton's iterations, the contact points whose state (no contact, stick, slip) the solve changed
from the warm start (``Solution.info["changed_points"]``), the relative KKT residual at the start and at the end, and
the contact solve against the linear solve of the same mesh and degrees (the problem without contact forces,
``contact_free``), both ``ndf.solve`` end to end, assembly included (the linear one best of ``--repeat``; the contact
one is the level's own solve, timed once inside the run).  The scenes: Examples 6.1 and 6.2 (adapt without a
target: it stops on its budgets), the scenes of results/scenes.md (``rtol = 1e-2``), the long contact side of
results/long_contact_side.md (``rtol = 1e-3``) and the rubber pad (``rtol = 1e-5``).  Writes
results/newton_levels.md, .csv and .png.  Run through the solver benchmark:

    python benchmarks/bench_solvers.py --levels-count [--quick] [--scenes 6.1 rubber_pad ...] [--repeat 2]
"""

import sys
import time
import warnings
from pathlib import Path

import numpy as np

import ngdgfric as ndf
from ngdgfric.examples import EXAMPLES
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.studies.scenes import SCENES

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
import long_contact_side  # noqa: E402  (benchmarks/long_contact_side.py, beside this file)
from common import best, command_line, contact_free, save_figure, say, write_csv  # noqa: E402

FIELDS = ["scene", "level", "ndof", "p_max", "contact_points", "iterations", "changed_points", "initial_residual",
          "residual", "contact_seconds", "linear_seconds", "ratio", "formulation"]
ITERATIONS_GOAL, RATIO_GOAL = 8, 2.0  # the targets: Newton iterations per warm-started level, contact / linear
QUICK = dict(scenes=["6.2"], max_levels=4)


def scenes(names):
    """(name, problem, first mesh or None, adapt keywords) for the scene names of ``--scenes`` (default: all)."""
    found = []
    for name in names:
        if name in EXAMPLES:
            found.append((name, EXAMPLES[name](), None, {}))
        elif name == "rubber_pad":
            found.append((name, ndf.example("rubber_pad"), None, dict(rtol=1e-5)))
        elif name == "long_strip":
            found.append((name, long_contact_side.long_strip(), None, dict(rtol=1e-3)))
        else:
            scene = SCENES[name.replace("-", "_")]()
            found.append((name, scene.problem, scene.mesh(0), dict(rtol=1e-2)))
    return found


ALL_SCENES = ["6.1", "6.2", *(name for name in SCENES), "long_strip", "rubber_pad"]


def run_scene(name, problem, mesh, keywords, repeat, max_levels=None):
    """The rows of one scene (FIELDS), level by level."""
    kept = []
    limits = {} if max_levels is None else dict(max_levels=max_levels)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = ndf.adapt(problem, mesh, progress=say, keep=lambda number, sol, est: kept.append((number, sol)),
                        **keywords, **limits)
        free = contact_free(problem)
        rows = []
        for number, sol in kept:
            orders = sol.discretization.orders
            linear_seconds, _ = best(repeat, lambda sol=sol, orders=orders: ndf.solve(free, sol.mesh, method=run.method,
                                                                                      order=orders))
            history = sol.history or [sol.info.get("initial_residual", np.nan)]
            rows.append(dict(scene=name, level=number, ndof=sol.ndof, p_max=int(np.max(orders)),
                             contact_points=sol.info.get("contact_points"), iterations=sol.iterations,
                             changed_points=sol.info.get("changed_points"),
                             initial_residual=sol.info.get("initial_residual"), residual=history[-1],
                             contact_seconds=sol.timings["total"], linear_seconds=linear_seconds,
                             ratio=sol.timings["total"] / linear_seconds,
                             formulation=sol.info.get("linear_solver", "")))
    return rows


def summary(rows):
    """One row per scene: its levels, the largest iterations and ratio over the warm-started levels, the targets met."""
    out = []
    for name in dict.fromkeys(row["scene"] for row in rows):
        warm = [row for row in rows if row["scene"] == name and row["level"] > 0]
        if not warm:
            continue
        worst = max(row["iterations"] for row in warm)
        ratio = max(row["ratio"] for row in warm)
        out.append(dict(scene=name, levels=len(warm) + 1, ndof=warm[-1]["ndof"], iterations=worst,
                        iterations_by_level=" ".join(str(row["iterations"]) for row in warm),
                        changed=" ".join(str(row["changed_points"]) for row in warm), ratio=ratio,
                        met="yes" if worst <= ITERATIONS_GOAL and ratio <= RATIO_GOAL else "no"))
    return out


def plot(rows, path):
    """Newton's iterations and contact / linear against the level, one line per scene."""
    import matplotlib.pyplot as plt

    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    for name in dict.fromkeys(row["scene"] for row in rows):
        mine = [row for row in rows if row["scene"] == name and row["level"] > 0]
        levels = [row["level"] for row in mine]
        left.plot(levels, [row["iterations"] for row in mine], "o-", label=name)
        right.semilogy(levels, [row["ratio"] for row in mine], "o-", label=name)
    left.axhline(ITERATIONS_GOAL, color="k", ls="--", lw=0.8)
    right.axhline(RATIO_GOAL, color="k", ls="--", lw=0.8)
    left.set(xlabel="level", ylabel="Newton iterations (warm start)")
    right.set(xlabel="level", ylabel="contact solve / linear solve")
    left.legend(fontsize=7)
    save_figure(figure, path)


def _cell(value):
    """A table cell: floats in 3 significant digits, None as "-"."""
    if value is None:
        return "-"
    return f"{value:.3g}" if isinstance(value, float) else str(value)


def report(rows, seconds):
    """The Markdown page."""
    scenes_ = summary(rows)
    per_scene = ["scene", "levels", "final DOFs", "most iterations", "iterations, level 1 on",
                 "points changed, level 1 on", "largest contact / linear", "targets met"]
    keys = ["scene", "levels", "ndof", "iterations", "iterations_by_level", "changed", "ratio", "met"]
    level_keys = ["level", "ndof", "p_max", "contact_points", "iterations", "changed_points", "initial_residual",
                  "residual", "contact_seconds", "linear_seconds", "ratio"]
    lines = ["# Newton's iterations level by level", "",
             "Every level of `ndf.adapt` with its defaults (hp from p = 4, each level started from the last): the "
             "semismooth Newton iterations of its contact solve, the contact points whose state (no contact, stick, "
             "slip) the solve changed from the warm start, and the contact solve against the linear solve of the "
             f"same mesh and degrees, end to end.  Targets: at most {ITERATIONS_GOAL} iterations per warm-started "
             f"level and a contact solve within {RATIO_GOAL:g} linear solves.  Measured in {seconds:.0f} s on 2 "
             "cores.", "", "Regenerate with `python benchmarks/bench_solvers.py --levels-count`.", "",
             "## Per scene", "",
             markdown_table(per_scene, [[_cell(row[key]) for key in keys] for row in scenes_]), "",
             "![iterations and cost against the level](newton_levels.png)", "", "## Every level", ""]
    for name in dict.fromkeys(row["scene"] for row in rows):
        lines += [f"### {name}", "", markdown_table(level_keys, [[_cell(row[key]) for key in level_keys]
                                                               for row in rows if row["scene"] == name]), ""]
    return "\n".join(lines)


def run(args):
    """The benchmark of the module docstring; ``args``: the parsed options of bench_solvers.py."""
    start = time.perf_counter()
    names = args.scenes or (QUICK["scenes"] if args.quick else ALL_SCENES)
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for name, problem, mesh, keywords in scenes(names):
        say(f"{name}: adapt {keywords or '(defaults)'}")
        rows += run_scene(name, problem, mesh, keywords, args.repeat, QUICK["max_levels"] if args.quick else None)
        write_csv(args.out / "newton_levels.csv", rows, FIELDS)
    plot(rows, args.out / "newton_levels.png")
    write_text(args.out / "newton_levels.md", report(rows, time.perf_counter() - start))
    say(f"wrote {args.out / 'newton_levels.md'} ({command_line()})")
    return rows
