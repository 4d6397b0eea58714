"""Effectivity of the estimator: eta_h / |||u - u_h|||_h, in energy units and as printed in the paper.

Cases (the five DG methods and the conforming baseline cg, p = 1..4, uniform and h-adaptive levels):

* ``divergence-free``: :func:`ngdgfric.studies.manufactured.incompressible_contact_manufactured` (contact and
  no-contact, stick and slip zones, div u = 0, data independent of nu) at E = 1, 1e3, 1e6 (c_n
  scaled with E: the same displacement) and nu = 0.3, 0.49, 0.4999; uniform h = 2^-2..2^-4, and
  at E = 1e3 six h-adaptive levels from h = 1/4.  True error against the exact u.
* ``lam-scaled``: :func:`ngdgfric.studies.manufactured.contact_manufactured` (stresses grow like lam as
  nu -> 1/2) at E = 1e3, nu = 0.3, 0.49, 0.4999, p = 1..3, uniform (reported, outside the
  robustness claim: see results/effectivity.md).
* ``6.1``, ``6.2``: the paper's examples, uniform h = 2^-2..2^-4 and eight h-adaptive levels from
  h = 1/2; true error against the hp reference solutions of results/reference.md (estimated
  error 3e-5), rows with a true error below 1e-3 left out.
* ``any data``: the solution of ``divergence-free`` (its f, g, g_a and c_tau are not polynomials, c_tau and g_a
  vary along Gamma_C) at E = 1, 1e3 and nu = 0.3, 0.45, 0.4999, uniform h = 2^-2..2^-5: the equilibrated
  bound's claims (guaranteed, never below the error, bounded under refinement).

Every level has both estimators: the residual one (``ndf.estimate(sol)``) and the guaranteed bound
(``ndf.estimate(sol, kind="equilibrated")``), with its cost as a fraction of the level's solve.

A method "locks" at (nu, p) when its error on the finest uniform divergence-free level exceeds
1.5 times the best method's.  Writes results/effectivity.md, .csv and .png.

    python scripts/effectivity.py [--quick] [--workers N] [--out DIR]
"""

import math
import time

from common import RESULTS, command_line, in_processes, run_script, save_figure, say, script_parser, write_csv

from ngdgfric.dg.methods import METHODS
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table

ORDERS = (1, 2, 3, 4)
YOUNG = (1.0, 1e3, 1e6)
POISSON = (0.3, 0.49, 0.4999)
LOCKING_RATIO = 1.5
MIN_EXAMPLE_ERROR = 1e-3  # 30 times the hp references' estimated error
ANY_DATA = {"E": (1.0, 1e3), "nu": (0.3, 0.45, 0.4999)}
BOUNDED = 3.0  # the equilibrated bound's max / min over h and p, per method (nu <= 0.45)
FIELDS = ["family", "E", "nu", "method", "order", "mode", "level", "ndof", "error", "eta_h", "eta_paper",
          "effectivity", "effectivity_paper", "eta_eq", "effectivity_eq", "guaranteed", "eq_over_solve", "seconds",
          "failure"]


def parse(argv=None):
    parser = script_parser(__doc__, "a few small cases (smoke test)")
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2; 1: no pool)")
    return parser.parse_args(argv)


def tasks(quick):
    """One task per (family, E, nu, method, p, mode): a sequence of levels."""
    if quick:
        return [dict(family="divergence-free", E=1e3, nu=0.3, method="sipg", order=1, mode=mode, levels=2)
                for mode in ("uniform", "adaptive")] + [
                dict(family="divergence-free", E=1.0, nu=0.4999, method="brezzi", order=2, mode="uniform", levels=2),
                dict(family="6.2", E=None, nu=None, method="nipg", order=1, mode="uniform", levels=2),
                dict(family="6.2", E=None, nu=None, method="cg", order=2, mode="uniform", levels=2),
                dict(family="any data", E=1.0, nu=0.45, method="ldg", order=2, mode="uniform", levels=2)]
    out = []
    for method in METHODS:
        for order in ORDERS:
            for E in YOUNG:
                for nu in POISSON:
                    out.append(dict(family="divergence-free", E=E, nu=nu, method=method, order=order, mode="uniform",
                                    levels=3))
                    if E == 1e3:  # E only scales the problem (the uniform levels show it): adaptive at one E
                        out.append(dict(family="divergence-free", E=E, nu=nu, method=method, order=order,
                                        mode="adaptive", levels=6))
            if order <= 3:
                out += [dict(family="lam-scaled", E=1e3, nu=nu, method=method, order=order, mode="uniform", levels=3)
                        for nu in POISSON]
            for example in ("6.1", "6.2"):
                out += [dict(family=example, E=None, nu=None, method=method, order=order, mode=mode, levels=levels)
                        for mode, levels in (("uniform", 3), ("adaptive", 8))]
            out += [dict(family="any data", E=E, nu=nu, method=method, order=order, mode="uniform", levels=4)
                    for E in ANY_DATA["E"] for nu in ANY_DATA["nu"]]
    return out


def setup(task):
    """(problem, error function of a Solution, initial mesh) of a task."""
    import ngdgfric as ndf
    from ngdgfric.examples import example
    from ngdgfric.reference import reference_errors
    from ngdgfric.studies import manufactured

    family = task["family"]
    if family in ("6.1", "6.2"):
        problem = example(family)
        reference = ndf.load_reference(RESULTS / f"reference_{family.replace('.', '_')}.npz", problem)
        return problem, lambda sol: reference_errors(sol, reference)["energy"], 0.5
    build = (manufactured.contact_manufactured if family == "lam-scaled"
             else manufactured.incompressible_contact_manufactured)
    problem, u = build(E=task["E"], nu=task["nu"], c_n=10.0 * task["E"] / 1e3)
    return problem, lambda sol: ndf.energy_norm(sol, u), 0.25


def run_task(task):
    """The rows of one task (run in a worker process, single-threaded)."""
    import ngsolve as ngs

    import ngdgfric as ndf

    ngs.SetNumThreads(1)
    problem, error_of, h0 = setup(task)
    rows = []

    def record(level, sol, est, seconds):
        error = error_of(sol)
        paper = ndf.estimate(sol, variant="paper").eta_h
        clock = time.perf_counter()
        bound = ndf.estimate(sol, kind="equilibrated")
        cost = (time.perf_counter() - clock) / sol.timings["total"]
        rows.append(dict(task, level=level, ndof=sol.ndof, error=error, eta_h=est.eta_h, eta_paper=paper,
                         effectivity=est.eta_h / error, effectivity_paper=paper / error, eta_eq=bound.eta_h,
                         effectivity_eq=bound.eta_h / error, guaranteed=bound.guaranteed, eq_over_solve=cost,
                         seconds=seconds))

    start = time.perf_counter()
    try:
        if task["mode"] == "uniform":
            for level in range(task["levels"]):
                sol = ndf.solve(problem, ndf.uniform_mesh(problem, h0 / 2**level), method=task["method"],
                                order=task["order"])
                record(level, sol, ndf.estimate(sol), time.perf_counter() - start)
        else:
            ndf.adapt(problem, ndf.uniform_mesh(problem, h0), method=task["method"], order=task["order"], hp=False,
                      max_levels=task["levels"], rtol=0, theta=0.3, progress=None,
                      keep=lambda level, sol, est: record(level, sol, est, time.perf_counter() - start))
    except ndf.SolverError as error:  # reported, never dropped
        rows.append(dict(task, level=len(rows), ndof=None, error=math.nan, eta_h=math.nan, eta_paper=math.nan,
                         effectivity=math.nan, effectivity_paper=math.nan, eta_eq=math.nan, effectivity_eq=math.nan,
                         guaranteed=None, eq_over_solve=math.nan, seconds=time.perf_counter() - start,
                         failure=str(error).splitlines()[0][:160]))
    for row in rows:
        row.pop("levels")
    return rows


def locking(rows):
    """{(nu, method, p): error / best method's error} on the finest uniform divergence-free levels."""
    finest = {}
    for r in rows:
        if r["family"] == "divergence-free" and r["mode"] == "uniform":
            key = (r["E"], r["nu"], r["order"], r["method"])
            if r["level"] >= finest.get(key, {}).get("level", -1):
                finest[key] = r
    ratio = {}
    for (E, nu, order, method), r in finest.items():
        best = min(s["error"] for (E2, nu2, o2, _), s in finest.items() if (E2, nu2, o2) == (E, nu, order))
        ratio[(nu, method, order)] = max(ratio.get((nu, method, order), 0.0), r["error"] / best)
    return ratio


def in_scope(row, ratio):
    """Rows of the robustness claim: no locking, examples' errors well above the reference's."""
    if row["family"] == "lam-scaled":
        return False
    if row["family"] in ("6.1", "6.2"):
        return row["error"] >= MIN_EXAMPLE_ERROR
    return ratio.get((row["nu"], row["method"], row["order"]), 1.0) <= LOCKING_RATIO


def spread(rows, key="effectivity"):
    values = [r[key] for r in rows]
    return (min(values), max(values), max(values) / min(values)) if values else (math.nan,) * 3


def report(rows, seconds):
    failures = [r for r in rows if r.get("failure")]
    rows = [r for r in rows if not r.get("failure")]
    ratio = locking(rows)
    scope = [r for r in rows if in_scope(r, ratio)]
    lo, hi, q = spread(scope)
    plo, phi, pq = spread(scope, "effectivity_paper")
    ulo, uhi, uq = spread([r for r in scope if not (r["family"] == "6.1" and r["method"] == "sipg")])
    guaranteed = sum(bool(r["guaranteed"]) for r in rows)
    lines = ["# Effectivity of the a posteriori estimator", "",
             f"How far the estimators are from the true error over {len(rows)} uniform and adaptive levels (the five "
             "DG methods and `cg`, $p = 1, \\dots, 4$, manufactured solutions and the paper's examples): the "
             f"effectivity $\\eta_h / |\\!|\\!| u - u_h |\\!|\\!|_h$ of the default estimator stays within {lo:.2f} "
             f"to {hi:.2f} wherever no method locks, and the equilibrated bound is guaranteed on {guaranteed} of the "
             f"{len(rows)} levels.", "",
             "![effectivity](effectivity.png)", "",
             "The default estimator is `ndf.estimate(sol)`, its residual terms divided by $2\\mu$ (energy units); the "
             "paper's is `variant=\"paper\"`.  True errors: against the exact solution (manufactured) or the hp "
             "reference solutions ([reference solutions](reference.md), Examples 6.1 and 6.2; rows with an error "
             f"below {MIN_EXAMPLE_ERROR:g} left out).  One constant is calibrated: the default estimator's factor "
             "$p_T^{-1/2}$, chosen on Example 6.1 with SIPG (`ngdgfric.estimator.estimate`); every other row checks "
             "it.", "",
             "## Summary", "",
             f"- Robustness scope (every case but the locking ones and the $\\lambda$-scaled solution, {len(scope)} "
             "levels): "
             f"effectivity {lo:.2f} - {hi:.2f}, max/min {q:.2f}; the paper's weights {plo:.3g} - {phi:.3g}, "
             f"max/min {pq:.3g}.",
             f"- The same without the calibration cases (Example 6.1, SIPG): effectivity {ulo:.2f} - {uhi:.2f}, "
             f"max/min {uq:.2f}.",
             f"- Solver failures (levels not measured): {len(failures)}"
             + "".join(f"; {r['family']} E={r['E']} nu={r['nu']} {r['method']} p={r['order']} {r['mode']} level "
                       f"{r['level']}: {r['failure']}" for r in failures) + ".", ""]
    groups = {}
    for r in rows:
        name = r["family"] if r["family"] in ("6.1", "6.2", "lam-scaled") else f"{r['family']}, $\\nu = {r['nu']:g}$"
        groups.setdefault((name, r["method"]), []).append(r)
    header = ["case", "method", "locks (error / best)", "levels", "effectivity min - max ($p = 1, \\dots, 4$)",
              "by p (mean)", "paper's weights", "equilibrated min - max"]
    table = []
    for (name, method), group in sorted(groups.items()):
        lo, hi, _ = spread(group)
        plo, phi, _ = spread(group, "effectivity_paper")
        by_p = " / ".join(f"{sum(r['effectivity'] for r in g) / len(g):.2f}" for g in
                          ([r for r in group if r["order"] == p] for p in ORDERS) if g)
        lock = "-"
        if name.startswith("divergence-free"):
            worst = max(ratio.get((group[0]["nu"], method, p), 1.0) for p in ORDERS)
            lock = f"{'yes' if worst > LOCKING_RATIO else 'no'} ({worst:.2f})"
        elo, ehi, _ = spread(group, "effectivity_eq")
        table.append([name, method, lock, len(group), f"{lo:.2f} - {hi:.2f}", by_p, f"{plo:.3g} - {phi:.3g}",
                      f"{elo:.2f} - {ehi:.2f}"])
    lines += equilibrated_report(rows)
    lines += ["## By case and method", "", markdown_table(header, table), ""]
    by_E = {}
    for r in rows:
        if r["family"] == "divergence-free":
            by_E.setdefault(r["E"], []).append(r["effectivity"])
    lines += ["## Scale of $E$ (divergence-free, all methods, $p$, $\\nu$, levels)", "",
              markdown_table(["$E$", "levels", "effectivity min - max"],
                             [[f"{E:g}", len(v), f"{min(v):.3f} - {max(v):.3f}"] for E, v in sorted(by_E.items())]),
              "", f"Regenerate: `{command_line()}` ({seconds:.0f} s)", ""]
    return "\n".join(lines)


def equilibrated_report(rows):
    """The lines on the guaranteed bound: every level, then the ``any data`` family method by method."""
    values = [r["effectivity_eq"] for r in rows]
    unguaranteed = [r for r in rows if not r["guaranteed"]]
    below = [r for r in rows if r["effectivity_eq"] < 1.0]
    lines = ["## The equilibrated bound (`kind=\"equilibrated\"`)", "",
             f"- Every level ({len(rows)}): guaranteed on {len(rows) - len(unguaranteed)}; effectivity "
             f"{min(values):.2f} - {max(values):.2f}, mean {sum(values) / len(values):.2f}; below 1 on {len(below)}; "
             f"its cost {min(r['eq_over_solve'] for r in rows):.2f} - {max(r['eq_over_solve'] for r in rows):.2f} "
             "of the level's solve ([the equilibration cost](equilibration_cost.md) measures it against the linear "
             "solve).", ""]
    data = [r for r in rows if r["family"] == "any data"]
    if not data:
        return lines
    header = ["$E$", "$\\nu$", "method", "levels", "min - max", "max / min", "mean", "by $p$ (max / min over $h$)"]
    table, bounded = [], [r for r in data if r["nu"] <= 0.45]
    for (E, nu, method), group in sorted(_groups(data, ("E", "nu", "method")).items()):
        lo, hi, q = spread(group, "effectivity_eq")
        by_p = " / ".join(f"{spread(g, 'effectivity_eq')[2]:.2f}" for g in _groups(group, ("order",)).values())
        table.append([f"{E:g}", f"{nu:g}", method, len(group), f"{lo:.2f} - {hi:.2f}", f"{q:.2f}",
                      f"{sum(r['effectivity_eq'] for r in group) / len(group):.2f}", by_p])
    per_method = {m: spread(g, "effectivity_eq") for (m,), g in _groups(bounded, ("method",)).items()}
    mean = sum(r["effectivity_eq"] for r in bounded) / len(bounded)
    over_h = max(spread(g, "effectivity_eq")[2] for g in _groups(bounded, ("E", "nu", "method", "order")).values())
    lines += ["### Any data ($f$, $g$, $g_a$, $c_\\tau$ not polynomials; contact and separation, stick and slip)", "",
              "- $\\nu = 0.3, 0.45$, $E = 1, 10^3$, $p = 1, \\dots, 4$, $h = 1/4, \\dots, 1/32$ "
              f"({len(bounded)} levels): mean {mean:.2f}; max / min over $E$, $\\nu$, $h$ and $p$ per method: "
              + ", ".join(f"{m} {q:.2f}" for m, (_, _, q) in sorted(per_method.items()))
              + f" (target $\\le {BOUNDED:g}$); over $h$ alone ($p$, $E$, $\\nu$ fixed): {over_h:.2f} at most.", "",
              markdown_table(header, table), ""]
    return lines


def _groups(rows, keys):
    out = {}
    for r in rows:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def plot(rows, path):
    rows = [r for r in rows if not r.get("failure")]
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ratio = locking(rows)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    colors = {method: f"C{k}" for k, method in enumerate(METHODS)}
    for ax, families in zip(axes, (("divergence-free",), ("6.1", "6.2")), strict=True):
        for method in METHODS:
            group = [r for r in rows if r["family"] in families and r["method"] == method]
            for scope, marker in ((True, "o"), (False, "x")):
                part = [r for r in group if in_scope(r, ratio) == scope]
                ax.scatter([r["ndof"] for r in part], [r["effectivity"] for r in part], s=12, marker=marker,
                           color=colors[method], label=method.upper() if scope else None, alpha=0.7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axhline(1.0, color="k", lw=0.8)
        ax.set_xlabel("degrees of freedom")
        ax.set_title("divergence-free manufactured (x: locking)" if families[0] != "6.1" else "Examples 6.1, 6.2")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel(r"$\eta_h / |||u - u_h|||_h$")
    axes[0].legend()
    save_figure(fig, path)


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    work = tasks(args.quick)
    rows, start = [], time.perf_counter()
    csv_path, md_path = args.out / "effectivity.csv", args.out / "effectivity.md"
    try:
        for done, (_, task_rows) in enumerate(in_processes(run_task, work, min(args.workers, len(work))), 1):
            rows += task_rows
            last = task_rows[-1]
            say(f"[{done}/{len(work)}] {last['family']} E={last['E']} nu={last['nu']} {last['method']} "
                f"p={last['order']} {last['mode']}: effectivity "
                + " ".join(f"{r['effectivity']:.2f}" for r in task_rows))
    finally:
        if rows:
            rows.sort(key=lambda r: tuple(str(r[k]) for k in ("family", "E", "nu", "method", "order", "mode"))
                      + (r["level"],))
            write_csv(csv_path, rows, FIELDS)
            write_text(md_path, report(rows, time.perf_counter() - start))
            plot(rows, args.out / "effectivity.png")
            say(f"wrote {md_path} ({len(rows)} levels)")
    return rows


if __name__ == "__main__":
    run_script(main)
