"""Scenes a user writes every day, beyond the paper's two rectangles (issue 26): results/scenes.md/.csv.

Nine scenes of :mod:`ngdgfric.studies.scenes`: material jumps along the mesh (three exact piecewise
linear solutions, one loaded by a penetration only) and across it (an exact solution with a kink inside
elements), a re-entrant corner, a block on a rigid cylinder (compared with Hertz theory), a nearly
incompressible body (exact divergence-free solution, nu = 0.4999), a bimaterial strip with the
penetration-dependent friction bound (m_t = 1) and a wedge meshed by Netgen with 6.6 degree triangles.

For every scene, method (the five of Section 3) and p = 1, 2, 3, the scene's family of meshes is solved
with the default solver and measured: the true energy error |||u - u_h|||_h (against the exact solution,
or against an hp reference computed here by hp-adaptive SIPG to a relative estimated error of
``REFERENCE_RTOL``), its observed rate in h, the estimator eta_h and its effectivity eta_h / error, the
KKT residuals of Lemma 3.1 against the round-off floor (``ndf.contact.rounding_residual``), Newton
iterations and seconds.  Then ``ndf.adapt(problem, tol=rtol |||u|||)`` with its defaults (method chosen by
the library) and its true error against tol.  Last, the shipped rubber pad under a steel plate (regions, E ratio
2e4, nu = 0.49, a hole, friction): adapt with rtol = 1e-3, its seconds of assembly, contact solve and estimate per
level, and its true error against a finer adapt solution.

    python scripts/scenes.py [--quick] [--scene NAME ...] [--workers N] [--out DIR]
"""

import math
import time
import warnings

import ngsolve as ngs
import numpy as np
from common import command_line, in_processes, run_script, say, script_parser, write_csv

import ngdgfric as ndf
from ngdgfric.contact import contact_state, rounding_residual
from ngdgfric.dg.methods import METHODS
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.problem import strain_of, stress
from ngdgfric.studies import slope
from ngdgfric.studies.scenes import (
    columns,
    hertz,
    hertz_solution,
    incompressible,
    l_shape,
    layers_indented,
    layers_pressure,
    strip,
    wedge,
)

# ============================================================================ PARAMETERS
SCENES = {"layers-pressure": layers_pressure, "layers-indented": layers_indented, "columns": columns,
          "layers-cut": lambda: layers_indented(c=1 / 3), "l-shape": l_shape, "hertz": hertz,
          "incompressible": incompressible, "strip-mt": strip, "wedge": wedge}
ORDERS = (1, 2, 3)
RTOL = {"layers-cut": 0.1}  # adapt's target relative to |||u|||; 1e-2 elsewhere (h^(1/2) where a jump cuts elements)
DEFAULT_RTOL = 1e-2
PAD_RTOL = 1e-3  # the rubber pad's adapt target, relative to |||u_h|||
ROUND_OFF = 1e-8  # relative errors below: the solution lies in V_h (round-off times the condition number)
REFERENCE_RTOL, REFERENCE_MAX_NDOF = 1e-5, 400_000  # the hp references: eta_h <= 1e-5 |||u|||
QUICK = dict(orders=(1,), methods=("sipg", "bassi"), levels=2, reference_rtol=1e-3, rtol=0.1)
FIELDS = ["scene", "method", "order", "level", "ndof", "error", "relative", "eta_h", "effectivity", "iterations",
          "seconds", "lam_excess", "complementarity", "equilibrium", "rounding", "status", "warnings"]
ADAPT_FIELDS = ["scene", "method", "tol", "stopped", "levels", "ndof", "p_max", "seconds", "eta_h", "error",
                "error_over_tol", "in_band", "exact"]


def parse(argv=None):
    parser = script_parser(__doc__, "two methods, P1, two meshes, coarse references")
    parser.add_argument("--scene", nargs="+", choices=sorted(SCENES), default=list(SCENES))
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2; 1: no pool)")
    return parser.parse_args(argv)


# ============================================================================ REFERENCES
def reference_path(out, name, quick):
    folder = out / ".cache" / "scenes"
    folder.mkdir(parents=True, exist_ok=True)
    return folder / f"{name}{'_quick' * quick}.npz"


def make_reference(name, path, rtol):
    """The hp reference of a scene without an exact solution: hp-adaptive SIPG (the library's defaults) to
    eta_h <= rtol |||u_h||| (|||u_h||| of a first P2 solve), stored at ``path`` (kept: a rerun reuses it)."""
    scene = SCENES[name]()
    if not path.exists():
        scale = ndf.energy_norm(ndf.solve(scene.problem, scene.mesh(0), order=2))
        start = time.perf_counter()
        run = ndf.adapt(scene.problem, scene.mesh(0), method="sipg", tol=rtol * scale, max_ndof=REFERENCE_MAX_NDOF,
                        progress=None)
        ndf.save_reference(run.solution, path, run.estimate.eta_h,
                           description=f"hp SIPG, {len(run.levels)} levels, {run.solution.ndof} DOFs, "
                                       f"{time.perf_counter() - start:.0f} s, stopped: {run.stopped}")
    return ndf.load_reference(path, scene.problem)


def energy(scene, reference):
    """|||u|||: (int C eps(u) : eps(u))^(1/2) of the exact solution (its own derivatives, the problem's C,
    a Gauss rule of degree 16 on the scene's finest mesh), or the reference's |||u_ref|||_h."""
    if reference is not None:
        return ndf.energy_norm(reference)
    strain = strain_of(scene.exact)
    mesh = scene.mesh(scene.levels - 1)
    return ngs.Integrate(ngs.InnerProduct(stress(scene.problem, strain), strain), mesh, order=16) ** 0.5


def true_error(scene, reference):
    """The function sol -> |||u - u_h|||_h of a scene (exact solution or reference)."""
    if scene.exact is not None:
        return lambda sol: ndf.energy_norm(sol, scene.exact)
    return lambda sol: ndf.energy_error(sol, reference)


# ============================================================================ ONE CASE
def run_case(item):
    """All meshes of one (scene, method, order): rows of FIELDS."""
    name, method, order, levels, reference_file = item
    scene = SCENES[name]()
    reference = None if reference_file is None else ndf.load_reference(reference_file, scene.problem)
    error_of, rows = true_error(scene, reference), []
    for level in range(levels):
        row = dict(scene=name, method=method, order=order, level=level, status="failed")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                mesh = scene.mesh(level)
                start = time.perf_counter()
                sol = ndf.solve(scene.problem, mesh, method=method, order=order)
                row["seconds"] = time.perf_counter() - start
            except ndf.SolverError as error:
                rows.append(dict(row, status=f"failed: {str(error)[:100]}"))
                continue
        est, error = ndf.estimate(sol), error_of(sol)
        kkt = ndf.kkt_residuals(sol)
        row.update(ndof=sol.ndof, error=error, relative=error / ndf.energy_norm(sol), eta_h=est.eta_h,
                   effectivity=est.eta_h / error if error > ROUND_OFF * ndf.energy_norm(sol) else None,
                   iterations=sol.iterations, rounding=rounding_residual(sol), status="solved", **kkt,
                   warnings="; ".join(sorted({type(w.message).__name__ for w in caught})))
        rows.append(row)
    return rows


def run_adapt(item):
    """``ndf.adapt`` with its defaults to tol = rtol |||u|||: a row of ADAPT_FIELDS (and the Hertz data)."""
    name, rtol, reference_file, max_ndof = item
    scene = SCENES[name]()
    reference = None if reference_file is None else ndf.load_reference(reference_file, scene.problem)
    tol = rtol * energy(scene, reference)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = ndf.adapt(scene.problem, scene.mesh(0), tol=tol, max_ndof=max_ndof, progress=None)
    seconds = time.perf_counter() - start
    error = true_error(scene, reference)(run.solution)
    row = dict(scene=name, method=run.method, tol=tol, stopped=run.stopped, levels=len(run.levels),
               ndof=run.solution.ndof, p_max=run.levels[-1]["p_max"], seconds=seconds, eta_h=run.estimate.eta_h,
               error=error, error_over_tol=error / tol, in_band=bool(tol / 10 <= error <= tol),
               exact=bool(error <= ROUND_OFF * tol / rtol))
    if name == "hertz":
        row["hertz"] = hertz_comparison(scene, reference if reference is not None else run.solution)
    return row


def run_pad(quick):
    """The shipped rubber pad under a steel plate (``example_file("rubber_pad")``: two regions, E ratio 2e4, nu = 0.49
    in the rubber, a circular hole, friction, a symmetry side, u_D): ``adapt(problem, rtol=PAD_RTOL)`` with its
    defaults, per level the seconds of assembly, contact solve and estimate, and its true error against a finer
    adapt solution of the same scene (rtol ten times smaller; a Reference file cannot hold curved elements)."""
    problem = ndf.load_problem(ndf.example_file("rubber_pad"))
    rtol = QUICK["rtol"] if quick else PAD_RTOL
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = ndf.adapt(problem, rtol=rtol, progress=None)
        seconds = time.perf_counter() - start
        finer = ndf.adapt(problem, rtol=rtol / 10, progress=None).solution
    norm = ndf.energy_norm(finer)
    error = ndf.energy_error(run.solution, finer)
    levels = [dict(level=r["level"], ndof=r["ndof"], p_max=r["p_max"], assemble=r["assemble_seconds"],
                   solve=r["solve_seconds"] - r["assemble_seconds"], estimate=r["estimate_seconds"],
                   refine=r["mark_refine_seconds"]) for r in run.levels]
    return dict(scene="rubber-pad", method=run.method, reason=run.method_reason, rtol=rtol, stopped=run.stopped,
                seconds=seconds, ndof=run.solution.ndof, error=error, relative=error / norm,
                finer_ndof=finer.ndof, levels=levels)


def pad_section(pad):
    """The report's section of :func:`run_pad`."""
    total = {key: sum(level[key] for level in pad["levels"]) for key in ("assemble", "solve", "estimate", "refine")}
    reason = pad["reason"].replace("results/locking.md", "[locking](locking.md)")  # the library's words, with a link
    return ["## rubber-pad: `adapt(problem, rtol)` on a scene where DG is the right tool", "",
            f"`ngdgfric adaptive rubber_pad.toml --rtol {pad['rtol']:g}` (the shipped scene, `ndf.example_file("
            f"\"rubber_pad\")`): {pad['method']} ({reason}); stopped on {pad['stopped']} after "
            f"{len(pad['levels'])} levels, {pad['ndof']} DOFs, {pad['seconds']:.1f} s; true error "
            f"{pad['relative']:.3g} $|\\!|\\!| u |\\!|\\!|$ against adapt's solution with rtol / 10 "
            f"({pad['finer_ndof']} DOFs), "
            f"error / tol = {pad['relative'] / pad['rtol']:.3g}.  Seconds per level:", "",
            markdown_table(["level", "DOFs", "$p$ max", "assembly", "contact solve", "estimate", "mark + refine"],
                           [(r["level"], r["ndof"], r["p_max"], f"{r['assemble']:.2f}", f"{r['solve']:.2f}",
                             f"{r['estimate']:.2f}", f"{r['refine']:.2f}") for r in pad["levels"]]), "",
            f"In all: assembly {total['assemble']:.1f} s, contact solve (factorisation included) {total['solve']:.1f} "
            f"s, estimate {total['estimate']:.1f} s, mark and refine {total['refine']:.1f} s.", ""]


def hertz_comparison(scene, solution):
    """Contact force P, half-width a and peak pressure p0 of ``solution`` (a Reference or Solution of the Hertz
    scene) against Hertz theory for the same P: a dict."""
    sol = solution if isinstance(solution, ndf.Solution) else \
        ndf.solve(scene.problem, solution.mesh, order=np.asarray(solution.orders, dtype=np.int64))
    state = contact_state(sol)
    weights = sol.contact.traces.omega
    force = float(np.sum(weights * state["pressure"]))
    problem = scene.problem
    a, p0 = hertz_solution(force, problem.E, problem.nu, radius=1.0)
    touching = state["pressure"] > 1e-6 * state["pressure"].max()
    width = float(np.max(np.abs(state["x"][touching])))
    peak = float(state["pressure"].max())
    inside = np.abs(state["x"]) < a
    profile = p0 * np.sqrt(np.clip(1 - (state["x"] / a) ** 2, 0, None))
    return dict(force=force, a=width, a_hertz=a, p0=peak, p0_hertz=p0,
                profile=float(np.max(np.abs(state["pressure"][inside] - profile[inside])) / p0))


# ============================================================================ REPORT
INTRO = ("Each scene is solved by the five DG methods and the conforming baseline `cg` at $p = 1, 2, 3$ on a "
         "family of meshes (the default solver), then by `ndf.adapt(problem, tol)` with its defaults.  Errors are "
         "true energy errors $|\\!|\\!| u - u_h |\\!|\\!|_h$ against the exact solution or an hp reference "
         "(hp-adaptive SIPG far below the errors studied), relative to $|\\!|\\!| u_h |\\!|\\!|_h$; the rate is "
         "the observed order in $h$ over the last two meshes (\"exact\": the solution lies in $V_h$ and every "
         "level is at round-off); $\\eta_h$ / error is the effectivity of the default estimator where the error is"
         " above round-off.")
def rate(rows):
    """The observed rate in h from the last two solved levels, -2 d log(error) / d log(DOFs), formatted;
    "exact" where every level is at round-off (relative error <= :data:`ROUND_OFF`)."""
    solved = [r for r in rows if r["status"] == "solved" and r["error"] > 0]
    if solved and all(r["relative"] <= ROUND_OFF for r in solved):
        return "exact"
    if len(solved) < 2:
        return "-"
    return f"{-2 * slope([r['ndof'] for r in solved[-2:]], [r['error'] for r in solved[-2:]]):.2f}"


def fmt(value, spec=".2e"):
    return "-" if value is None or (isinstance(value, float) and math.isnan(value)) else format(value, spec)


def scene_table(name, rows):
    """Markdown rows for one scene: method, p, errors on the levels, rate, effectivities, iterations, seconds,
    KKT equilibrium / round-off floor."""
    lines = []
    for method in dict.fromkeys(r["method"] for r in rows):
        for order in sorted({r["order"] for r in rows if r["method"] == method}):
            case = [r for r in rows if r["method"] == method and r["order"] == order]
            solved = [r for r in case if r["status"] == "solved"]
            effectivity = [r["effectivity"] for r in solved if r["effectivity"] is not None]
            ratio = max((r["equilibrium"] / max(r["rounding"], 1e-14) for r in solved), default=None)
            lines.append((method, order, " / ".join(fmt(r["relative"]) for r in solved) or "-",
                          rate(case), f"{min(effectivity):.2f}-{max(effectivity):.2f}" if effectivity
                          else "-", max((r["iterations"] for r in solved), default="-"),
                          fmt(sum(r["seconds"] for r in solved), ".2f"), fmt(ratio, ".2g"),
                          len(case) - len(solved)))
    header = ["method", "$p$", "relative errors (levels)", "rate", "$\\eta_h$ / error", "Newton iterations", "seconds",
              "equilibrium / round-off", "failures"]
    return markdown_table(header, lines)


def write_report(out, rows, adapts, references, quick, pad):
    failures = [r for r in rows if r["status"] != "solved"]
    solved = [r for r in rows if r["status"] == "solved"]
    worst_kkt = max(r["equilibrium"] / max(r["rounding"], 1e-14) for r in solved)
    worst_lam = max(r["lam_excess"] for r in solved)
    worst_comp = max(r["complementarity"] for r in solved)
    names = list(dict.fromkeys(r["scene"] for r in rows))
    lines = [f"# User scenes{' (quick run)' * quick}", "",
             f"{len(names)} scenes of `ngdgfric.studies.scenes` beyond the paper's rectangles (material jumps, a "
             "re-entrant corner, a Hertz contact, near incompressibility, a friction bound that depends on the "
             "penetration, a thin wedge), each measured by its true error, and a rubber pad on which `adapt` "
             f"chooses a DG method.  {len(rows)} solves, {len(failures)} of them failed"
             + ("; the KKT conditions of Lemma 3.1 hold to round-off on every solution." if worst_kkt <= 10
                and worst_lam <= 1e-12 and worst_comp <= 1e-8 else "."), "",
             INTRO, "",
             f"**{len(rows)} solves, {len(failures)} failures**; KKT residuals of Lemma 3.1: "
             f"$\\lvert \\lambda_\\tau \\rvert - 1 \\le$ {worst_lam:.1e}, complementarity $\\le$ {worst_comp:.1e}, "
             f"equilibrium at most {worst_kkt:.2g} times the round-off floor (the equilibrium residual of $u_h$ "
             "rounded once more).", "",
             "## The scenes", "",
             markdown_table(["scene", "what", "measured against"],
                            [(name, SCENES[name]().description, references[name]) for name in
                             dict.fromkeys(r["scene"] for r in rows)]), ""]
    for name in dict.fromkeys(r["scene"] for r in rows):
        lines += [f"## {name}", "", SCENES[name]().description + ".", "",
                  scene_table(name, [r for r in rows if r["scene"] == name]), ""]
    lines += ["## `adapt(problem, tol)` with its defaults", "",
              "tol $= \\mathrm{rtol}\\, |\\!|\\!| u |\\!|\\!|$ (rtol $= 10^{-2}$; $10^{-1}$ for the jump that cuts "
              "elements, where every method converges like $h^{1/2}$); the method is the library's choice.", "",
              markdown_table(["scene", "method", "tol", "stopped", "levels", "DOFs", "$p$ max", "seconds", "$\\eta_h$",
                              "true error", "error / tol", "in [tol / 10, tol]"],
                             [(a["scene"], a["method"], fmt(a["tol"]), a["stopped"], a["levels"], a["ndof"],
                               a["p_max"], f"{a['seconds']:.1f}", fmt(a["eta_h"]), fmt(a["error"]),
                               f"{a['error_over_tol']:.3g}", "exact" if a["exact"] else "yes" if a["in_band"]
                               else "no") for a in adapts]), "",
              "\"exact\": the solution lies in $V_h$, the first mesh gives it to round-off and $\\eta_h$ is at "
              "round-off too, so the loop stops at once (below tol / 10: nothing to adapt).", ""]
    lines += pad_section(pad)
    hertz_rows = [a["hertz"] for a in adapts if "hertz" in a]
    if hertz_rows:
        h = hertz_rows[0]
        lines += ["## Hertz", "", "The contact of the hp reference against Hertz's line contact of a rigid cylinder "
                  "($R = 1$) on an elastic half-space in plane strain for the same total force $P$ (Johnson, *Contact "
                  "Mechanics*, Section 4.2); the block is finite ($2 \\times 1$, clamped on top) and the contact "
                  "compliant ($c_n = 10^3 E$), so a few per cent are expected; the pressure differs most at the ends "
                  "$x = \\pm a$ of the contact, where Hertz's profile has an infinite slope and the compliance smooths "
                  "it.  (A curved body against Hertz: [the Hertz page](hertz.md).)", "",
                  markdown_table(["$P$", "half-width $a$", "Hertz's $a$", "peak $p_0$", "Hertz's $p_0$",
                                  "$\\max \\lvert p - p_\\mathrm{Hertz} \\rvert / p_0$"],
                                 [(fmt(h["force"], ".4e"), fmt(h["a"], ".4f"), fmt(h["a_hertz"], ".4f"),
                                   fmt(h["p0"], ".4e"), fmt(h["p0_hertz"], ".4e"), f"{h['profile']:.3f}")]), ""]
    lines += [f"Regenerate: `{command_line()}`", ""]
    write_text(out / "scenes.md", "\n".join(lines))


# ============================================================================ MAIN
def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    methods = QUICK["methods"] if args.quick else list(METHODS)
    orders = QUICK["orders"] if args.quick else ORDERS
    references, files = {}, {}
    for name in args.scene:
        scene = SCENES[name]()
        if scene.exact is not None:
            references[name], files[name] = "exact solution", None
            continue
        path = reference_path(args.out, name, args.quick)
        reference = make_reference(name, path, QUICK["reference_rtol"] if args.quick else REFERENCE_RTOL)
        files[name] = str(path)
        references[name] = f"hp reference ({reference.u.space.ndof} DOFs, eta_h = {reference.eta_h:.2e})"
        say(f"reference {name}: {reference.description}")
    items = [(name, method, order, QUICK["levels"] if args.quick else SCENES[name]().levels, files[name])
             for name in args.scene for method in methods for order in orders]
    rows = []
    for _, case_rows in in_processes(run_case, items, args.workers):
        rows += case_rows
        last = case_rows[-1]
        say(f"{last['scene']} {last['method']} P{last['order']}: {last['status']}, relative error "
            f"{fmt(last.get('relative'))}")
        write_csv(args.out / "scenes.csv", rows, FIELDS)
    order_of = {(name, method, order): k for k, (name, method, order, *_) in enumerate(items)}
    rows.sort(key=lambda r: (order_of[(r["scene"], r["method"], r["order"])], r["level"]))
    write_csv(args.out / "scenes.csv", rows, FIELDS)
    adapt_items = [(name, QUICK["rtol"] if args.quick else RTOL.get(name, DEFAULT_RTOL), files[name],
                    20_000 if args.quick else 300_000) for name in args.scene]
    adapts = [None] * len(adapt_items)
    for index, row in in_processes(run_adapt, adapt_items, args.workers):
        adapts[index] = row
        say(f"adapt {row['scene']}: {row['stopped']} after {row['levels']} levels, error / tol = "
            f"{row['error_over_tol']:.3g}")
    write_csv(args.out / "scenes_adapt.csv", [{k: a[k] for k in ADAPT_FIELDS} for a in adapts], ADAPT_FIELDS)
    pad = run_pad(args.quick)
    say(f"rubber pad: {pad['method']}, {len(pad['levels'])} levels, {pad['seconds']:.1f} s, error / tol = "
        f"{pad['relative'] / pad['rtol']:.3g}")
    write_csv(args.out / "scenes_pad.csv", pad["levels"])
    write_report(args.out, rows, adapts, references, args.quick, pad)
    say(f"wrote {args.out / 'scenes.md'}")
    return rows, adapts, pad


if __name__ == "__main__":
    run_script(main)
