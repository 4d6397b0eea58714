"""Newton's iterations level by level: where an adaptive run's contact solves spend their time.

For each scene, ``ndf.adapt`` with its defaults (the method it picks, hp from p = 4, warm starts) and per level:
the contact points M, Newton's iterations, the contact points whose state (no contact, stick, slip) the solve changed
from its start (``Solution.info["changed_points"]``; from zero on the first level), the relative KKT residual at the
start and at the end, and the contact solve against the linear solve of the same mesh and degrees (the problem
without contact forces, ``contact_free``), both ``ndf.solve`` end to end, assembly included (the linear one best of
``--repeat``, the contact one the best of the level's own solve and ``--repeat`` - 1 solves from the level before),
and adapt's seconds against the sum of its levels' linear solves.  The scenes: Examples 6.1 and 6.2 (``rtol=0``: no
accuracy target, it stops on its budgets), the scenes of results/scenes.md (``rtol = 1e-2``), the long contact side of
results/long_contact_side.md (``rtol = 1e-3``) and the rubber pad (``rtol = 1e-5``, with its true error against
adapt's solution to rtol / 10).
Writes results/newton_levels.md, .csv and .png.  Run through the solver benchmark:

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
FINER = 10.0  # the rubber pad's true error: against adapt's solution to rtol / FINER


def scenes(names):
    """(name, problem, first mesh or None, adapt keywords) for the scene names of ``--scenes`` (default: all)."""
    found = []
    for name in names:
        if name in EXAMPLES:
            found.append((name, EXAMPLES[name](), None, dict(rtol=0)))
        elif name == "rubber_pad":
            found.append((name, ndf.example("rubber_pad"), None, dict(rtol=1e-5)))
        elif name == "long_strip":
            found.append((name, long_contact_side.long_strip(), None, dict(rtol=1e-3)))
        else:
            scene = SCENES[name.replace("-", "_")]()
            found.append((name, scene.problem, scene.mesh(0), dict(rtol=1e-2)))
    return found


ALL_SCENES = ["6.1", "6.2", *(name for name in SCENES), "long_strip", "rubber_pad"]


def run_scene(name, problem, mesh, keywords, repeat, max_levels=None, finer=None):
    """(the rows of one scene (FIELDS), level by level; the scene's totals: ``run_seconds`` of adapt, ``linear_sum``:
    its levels' linear solves, and with ``finer`` (a factor) ``error``: the final solution's true error against adapt's
    solution to rtol / finer, relative to its |||u|||)."""
    kept = []
    limits = {} if max_levels is None else dict(max_levels=max_levels)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        run = ndf.adapt(problem, mesh, progress=say, keep=lambda number, sol, est: kept.append((number, sol)),
                        **keywords, **limits)
        totals = dict(scene=name, run_seconds=time.perf_counter() - start, error=None, rtol=keywords.get("rtol"))
        if finer is not None:
            reference = ndf.adapt(problem, mesh, progress=None, rtol=keywords["rtol"] / finer).solution
            totals["error"] = ndf.energy_error(run.solution, reference) / ndf.energy_norm(reference)
        free = contact_free(problem)
        rows = []
        for number, sol in kept:
            orders = sol.discretization.orders
            linear_seconds, _ = best(repeat, lambda sol=sol, orders=orders: ndf.solve(free, sol.mesh, method=run.method,
                                                                                      order=orders))
            start = None if number == 0 else kept[number - 1][1]
            again, _ = best(repeat - 1, lambda sol=sol, orders=orders, start=start: ndf.solve(
                problem, sol.mesh, method=run.method, order=orders, initial=start)) if repeat > 1 else (np.inf, None)
            contact_seconds = min(sol.timings["total"], again)
            history = sol.history or [sol.info.get("initial_residual", np.nan)]
            rows.append(dict(scene=name, level=number, ndof=sol.ndof, p_max=int(np.max(orders)),
                             contact_points=sol.info.get("contact_points"), iterations=sol.iterations,
                             changed_points=sol.info.get("changed_points"),
                             initial_residual=sol.info.get("initial_residual"), residual=history[-1],
                             contact_seconds=contact_seconds, linear_seconds=linear_seconds,
                             ratio=contact_seconds / linear_seconds,
                             formulation=sol.info.get("linear_solver", "")))
    totals["linear_sum"] = sum(row["linear_seconds"] for row in rows)
    return rows, totals


def summary(rows, totals):
    """One row per scene: its levels, the largest iterations and ratio over the warm-started levels, the targets met,
    adapt's seconds over the sum of its levels' linear solves (``totals``: ``run_scene``'s, by scene)."""
    out = []
    for name in dict.fromkeys(row["scene"] for row in rows):
        warm = [row for row in rows if row["scene"] == name and row["level"] > 0]
        if not warm:  # stopped on its first level (an exact solution in V_h)
            first = next(row for row in rows if row["scene"] == name)
            out.append(dict(scene=name, levels=1, ndof=first["ndof"], iterations=None, iterations_by_level="-",
                            changed="-", ratio=None, run=totals[name]["run_seconds"] / totals[name]["linear_sum"],
                            met="-"))
            continue
        worst = max(row["iterations"] for row in warm)
        ratio = max(row["ratio"] for row in warm)
        out.append(dict(scene=name, levels=len(warm) + 1, ndof=warm[-1]["ndof"], iterations=worst,
                        iterations_by_level=" ".join(str(row["iterations"]) for row in warm),
                        changed=" ".join(str(row["changed_points"]) for row in warm), ratio=ratio,
                        run=totals[name]["run_seconds"] / totals[name]["linear_sum"],
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


def report(rows, totals, seconds):
    """The Markdown page (``totals``: :func:`run_scene`'s, by scene)."""
    scenes_ = summary(rows, totals)
    per_scene = ["scene", "levels", "final DOFs", "most iterations", "iterations, level 1 on",
                 "points changed, level 1 on", "largest contact / linear", "run / sum of linear", "targets met"]
    keys = ["scene", "levels", "ndof", "iterations", "iterations_by_level", "changed", "ratio", "run", "met"]
    level_keys = ["level", "ndof", "p_max", "contact_points", "iterations", "changed_points", "initial_residual",
                  "residual", "contact_seconds", "linear_seconds", "ratio"]
    level_header = ["level", "DOFs", "$p$ max", "contact points", "Newton iterations", "points changed",
                    "initial residual", "residual", "contact seconds", "linear seconds", "contact / linear"]
    errors = [f"{name}: true error {total['error']:.3g} $|\\!|\\!| u |\\!|\\!|$ at rtol = {total['rtol']:g} (against "
              f"adapt's solution to rtol / {FINER:g})" for name, total in totals.items() if total["error"] is not None]
    judged = [row for row in scenes_ if row["met"] != "-"]
    lines = ["# Newton's iterations level by level", "",
             "How many semismooth Newton iterations each level of an adaptive run needs when it starts from the "
             f"previous level's solution, and what its contact solve costs, on {len(scenes_)} scenes: the targets "
             f"are met on {sum(row['met'] == 'yes' for row in judged)} of the {len(judged)} scenes with more than one "
             "level.", "",
             "Every level of `ndf.adapt` with its defaults (hp from $p = 4$, each level started from the last; "
             "Examples 6.1 and 6.2 with `rtol=0`, on to the budgets, the scenes with their rtol): the "
             "semismooth Newton iterations of its contact solve, the contact points whose state (no contact, stick, "
             "slip) the solve changed from the warm start, and the contact solve against the linear solve of the "
             f"same mesh and degrees, end to end.  Targets: at most {ITERATIONS_GOAL} iterations per warm-started "
             f"level and a contact solve within {RATIO_GOAL:g} linear solves.  Measured in {seconds:.0f} s on 2 "
             "cores.", "",
             "Before the contact elements of a friction side shared one degree and the warm starts of hp runs were "
             "exact, the rubber pad to rtol $= 10^{-5}$ took 7, 5, 1, 4, 8, 10, 14, 22, 25, 25, 26, 71 iterations per "
             "level and 111 s for its last level's solve; why: the documentation's design decisions, *one degree "
             "along a friction side* and *the warm start's carrier*.", "",
             *([f"{line}." for line in errors] + [""] if errors else []),
             "## Per scene", "",
             markdown_table(per_scene, [[_cell(row[key]) for key in keys] for row in scenes_]), "",
             "![iterations and cost against the level](newton_levels.png)", "", "## Every level", ""]
    for name in dict.fromkeys(row["scene"] for row in rows):
        lines += [f"### {name}", "", markdown_table(level_header, [[_cell(row[key]) for key in level_keys]
                                                                 for row in rows if row["scene"] == name]), ""]
    lines += [f"Regenerate: `{command_line()}`", ""]
    return "\n".join(lines)


def run(args):
    """The benchmark of the module docstring; ``args``: the parsed options of bench_solvers.py."""
    start = time.perf_counter()
    names = args.scenes or (QUICK["scenes"] if args.quick else ALL_SCENES)
    args.out.mkdir(parents=True, exist_ok=True)
    rows, totals = [], {}
    for name, problem, mesh, keywords in scenes(names):
        say(f"{name}: adapt {keywords or '(defaults)'}")
        finer = FINER if name == "rubber_pad" and not args.quick else None
        mine, totals[name] = run_scene(name, problem, mesh, keywords, args.repeat,
                                       QUICK["max_levels"] if args.quick else None, finer)
        rows += mine
        write_csv(args.out / "newton_levels.csv", rows, FIELDS)
    plot(rows, args.out / "newton_levels.png")
    write_text(args.out / "newton_levels.md", report(rows, totals, time.perf_counter() - start))
    say(f"wrote {args.out / 'newton_levels.md'} ({command_line()})")
    return rows
