"""Hertz's line contact on a curved half-disk: half-width and peak pressure against Hertz, and exponential
convergence of hp-adaptivity on curved elements against a polygonal approximation of the circle.

The half-disk of radius R = 1, centre (0, R), pressed onto the rigid plane y = 0 by a prescribed displacement
u_D = (0, -delta) of its flat top; Gamma_C the lower half circle with the gap g_a = y R / (R - y) along its normal,
frictionless, m_n = 1, a stiff compliance c_n (the Signorini limit is c_n -> infinity); plane strain E = 1,
nu = 0.3 (:func:`ngdgfric.studies.curved.hertz_problem`).  hp-adaptive SIPG (``ndf.adapt``, p from 2 to 8) on
curved elements.  Hertz (Johnson, Contact Mechanics, 1985, Section 4.2): for the force F per unit length,
a = (4 F R / (pi E*))^(1/2), p0 = 2 F / (pi a), E* = E / (1 - nu^2).  F is the vertical resultant of the contact
pressure by the discrete contact rule; a is where u_n - g_a changes sign, found on 33 points per contact edge on
the curved edges (a zero of the straight line between the two points around the sign change); p0 the pressure at
x = 0 (a mesh vertex: the mean of its two edges).  Energy error: 2 (J_h(u_h) - J_h(u_ref)) with the energy J_h the
discrete solution minimises (:func:`ngdgfric.studies.curved.discrete_energy`), u_ref the last level of an hp run to
a much smaller tolerance; checked against |||u_h - u_ref|||_h by point evaluation of u_ref
(:func:`~ngdgfric.studies.curved.reference_error`).  The polygon: the same problem on inscribed polygons with 64
and 256 straight sides, errors against the curved reference (the true solution) and against its own last level.
Writes results/hertz.md, results/hertz.csv and results/hertz.png.

    python scripts/hertz.py [--quick] [--out results/]
"""

import math
import time

import numpy as np
from common import command_line, run_script, say, script_parser, write_csv

import ngdgfric as ndf
from ngdgfric.files import write_text
from ngdgfric.output import figure, markdown_table, write_png
from ngdgfric.studies.curved import (
    contact_profile,
    discrete_energy,
    fit_algebraic,
    fit_exponential,
    hertz_measures,
    hertz_problem,
    reference_error,
)

# ==============================================================================================================
# PARAMETERS
# ==============================================================================================================

R, E, NU = 1.0, 1.0, 0.3
DELTA, C_N = 0.002, 1e5  # the main case: a / R ~ 0.03, c_n a / E* ~ 3000
SOLVER_TOL = 1e-11  # Newton's KKT tolerance (the default 1e-13 is not reached at c_n = 1e6: round-off)
FIRST_MAXH = 0.25
FULL = dict(reference_rtol=3e-6, study_rtol=1e-4, sides=(64, 256), polygon_rtol=3e-6, polygon_max_ndof=60_000,
            sweep_rtol=3e-4, deltas=(0.0005, 0.001, 0.002, 0.004, 0.008, 0.016), c_ns=(1e2, 1e3, 1e4, 1e5, 1e6),
            nus=(0.0, 0.3, 0.45))
QUICK = dict(reference_rtol=3e-3, study_rtol=3e-2, sides=(16,), polygon_rtol=3e-2, polygon_max_ndof=4_000,
             sweep_rtol=3e-2, deltas=(0.004,), c_ns=(1e3,), nus=())
FIT_RANGE = (1e-2, 30.0)  # levels fitted: eta_h below 1e-2 |||u_h|||_h and above 30 times the reference's eta_h


def parse(argv=None):
    parser = script_parser(__doc__, "coarse tolerances, one polygon, two sweep points")
    return parser.parse_args(argv)


# ==============================================================================================================
# MAIN
# ==============================================================================================================


def adaptive(problem, rtol, keep=None, max_ndof=10**6):
    """``ndf.adapt`` (hp, p 2...8, SIPG, Doerfler theta = 0.5, no geometric layers) from a Netgen mesh of maxh
    FIRST_MAXH, silent; every setting explicit, so that adapt's defaults (which changed) leave the study as it is."""
    return ndf.adapt(problem, ndf.netgen_mesh(problem, FIRST_MAXH), method="sipg", order=2, max_order=8, theta=0.5,
                     layers=0, rtol=rtol, keep=keep, progress=None, solver_tol=SOLVER_TOL, max_ndof=max_ndof)


def reference_run(problem, rtol):
    """The hp run to ``rtol``: (Adaptation, one record per level: ndof, eta_h, energy norm, J_h, Hertz measures)."""
    records = []

    def keep(level, sol, est):
        records.append(dict(level=level, ndof=sol.ndof, eta_h=est.eta_h, eta6=math.sqrt(est.terms_squared["eta6"]),
                            norm=ndf.energy_norm(sol), J=discrete_energy(sol), **hertz_measures(sol)))

    start = time.perf_counter()
    run = adaptive(problem, rtol, keep)
    say(f"  {len(records)} levels, {run.solution.ndof} DOFs, eta_h = {run.estimate.eta_h:.3e}, "
        f"{time.perf_counter() - start:.0f} s")
    J_ref = records[-1]["J"]
    for record in records:
        record["error_J"] = math.sqrt(max(2 * (record["J"] - J_ref), 0.0))
    return run, records


def interpolated_run(problem, rtol, reference, max_ndof=10**6):
    """An hp run to ``rtol`` with |||u_h - u_ref|||_h (point evaluation of ``reference``) and J_h per level."""
    records = []

    def keep(level, sol, est):
        records.append(dict(level=level, ndof=sol.ndof, eta_h=est.eta_h, norm=ndf.energy_norm(sol),
                            error_interp=reference_error(sol, reference), J=discrete_energy(sol)))

    run = adaptive(problem, rtol, keep, max_ndof)
    return run, records


def fit_range(records, eta_ref, n_min=None, n_max=None):
    """The records fitted: eta_h below FIT_RANGE[0] |||u_h|||_h and above FIT_RANGE[1] eta_ref (or, given, DOFs
    in [n_min, n_max])."""
    if n_min is not None:
        return [r for r in records if n_min <= r["ndof"] <= n_max]
    return [r for r in records if FIT_RANGE[1] * eta_ref <= r["eta_h"] <= FIT_RANGE[0] * r["norm"]]


def fits(records, key):
    """Exponential and algebraic fits of ``key`` over ``records`` (:mod:`ngdgfric.studies.curved`); None for fewer
    than three records."""
    if len(records) < 3:
        return None
    ndof, errors = [r["ndof"] for r in records], [r[key] for r in records]
    return dict(exponential=fit_exponential(ndof, errors), algebraic=fit_algebraic(ndof, errors), first=ndof[0],
                last=ndof[-1], points=len(ndof), fall=errors[0] / errors[-1], end=errors[-2] / errors[-1])


def sweep(settings):
    """Hertz's quantities for delta, c_n and nu varied about the main case, each by an hp run to sweep_rtol."""
    cases = [dict(delta=d, c_n=C_N, nu=NU, vary="delta") for d in settings["deltas"]]
    cases += [dict(delta=DELTA, c_n=c, nu=NU, vary="c_n") for c in settings["c_ns"]]
    cases += [dict(delta=DELTA, c_n=C_N, nu=n, vary="nu") for n in settings["nus"]]
    rows = []
    for case in cases:
        start = time.perf_counter()
        run = adaptive(hertz_problem(case["delta"], case["c_n"], E=E, nu=case["nu"], radius=R), settings["sweep_rtol"])
        m = hertz_measures(run.solution)
        modulus = E / (1 - case["nu"] ** 2)
        rows.append(dict(study="sweep", **case, ndof=run.solution.ndof, eta_h=run.estimate.eta_h, a_over_R=m["a"] / R,
                         compliance=case["c_n"] * m["a"] / modulus, seconds=time.perf_counter() - start, **m))
        say(f"  {case['vary']}: delta {case['delta']:g}, c_n {case['c_n']:g}, nu {case['nu']:g}: a/R {m['a'] / R:.4f}, "
            f"a {m['rel_a']:+.2%}, p0 {m['rel_p0']:+.2%} against Hertz ({rows[-1]['seconds']:.0f} s)")
    return rows


def main(argv=None):
    args = parse(argv)
    settings = QUICK if args.quick else FULL
    args.out.mkdir(parents=True, exist_ok=True)
    problem = hertz_problem(DELTA, C_N, E=E, nu=NU, radius=R)
    say(f"reference: hp-adaptive to rtol {settings['reference_rtol']:g}")
    reference, levels = reference_run(problem, settings["reference_rtol"])
    eta_ref = reference.estimate.eta_h
    say(f"check: hp-adaptive to rtol {settings['study_rtol']:g}, errors by point evaluation of the reference")
    _, check = interpolated_run(problem, settings["study_rtol"], reference.solution)
    J_ref = levels[-1]["J"]
    for record in check:
        record["error_J"] = math.sqrt(max(2 * (record["J"] - J_ref), 0.0))
    polygons = {}
    for sides in settings["sides"]:
        say(f"polygon with {sides} sides: hp-adaptive to rtol {settings['polygon_rtol']:g}")
        start = time.perf_counter()
        run, records = interpolated_run(hertz_problem(DELTA, C_N, E=E, nu=NU, radius=R, sides=sides),
                                        settings["polygon_rtol"], reference.solution, settings["polygon_max_ndof"])
        for record in records:
            record["error_own"] = math.sqrt(max(2 * (record["J"] - records[-1]["J"]), 0.0))
        polygons[sides] = dict(records=records, measures=hertz_measures(run.solution), eta_last=run.estimate.eta_h,
                               stopped=run.stopped)
        say(f"  {len(records)} levels, {run.solution.ndof} DOFs, {time.perf_counter() - start:.0f} s")
    say("sweeps")
    sweeps = sweep(settings)
    curved = fit_range(levels, eta_ref)
    results = dict(levels=levels, check=check, polygons=polygons, sweeps=sweeps, reference=levels[-1],
                   eta_ref=eta_ref, fit_levels=curved,
                   fits=dict(curved=fits(curved, "error_J"), curved_eta=fits(curved, "eta_h")))
    if curved:
        for sides, polygon in polygons.items():
            chosen = fit_range(polygon["records"], eta_ref, curved[0]["ndof"], curved[-1]["ndof"])
            results["fits"][f"{sides}-gon, against the curved reference"] = fits(chosen, "error_interp")
    write_csv(args.out / "hertz.csv", csv_rows(results), FIELDS)
    plot(args.out / "hertz.png", results, reference.solution)
    text = report(results, settings)
    write_text(args.out / "hertz.md", text)
    say("\n" + text)
    return results


FIELDS = ["study", "sides", "level", "ndof", "eta_h", "eta6", "error_J", "error_interp", "error_own", "F", "a",
          "a_hertz", "rel_a", "p0", "p0_hertz", "rel_p0", "profile", "delta", "c_n", "nu", "a_over_R", "compliance",
          "seconds"]


def csv_rows(results):
    rows = [dict(study="reference run", **r) for r in results["levels"]]
    rows += [dict(study="check run", **r) for r in results["check"]]
    for sides, polygon in results["polygons"].items():
        rows += [dict(study="polygon", sides=sides, **r) for r in polygon["records"]]
    rows += results["sweeps"]
    return [{k: row.get(k) for k in FIELDS} for row in rows]


def plot(path, results, sol):
    """Pressure against Hertz; errors against N^(1/3) and against N."""
    fig = figure(15, 4.6)
    ax = fig.add_subplot(1, 3, 1)
    ref = results["reference"]
    profile = contact_profile(sol)
    x = np.linspace(-1.3, 1.3, 400) * ref["a_hertz"]
    ax.plot(profile["x"] / ref["a_hertz"], profile["pressure"] / ref["p0_hertz"], "-", lw=2, label="hp solution")
    ax.plot(x / ref["a_hertz"], np.sqrt(np.clip(1 - (x / ref["a_hertz"]) ** 2, 0, None)), "k--", label="Hertz")
    ax.set_xlim(-1.3, 1.3)
    ax.set_xlabel("x / a (Hertz)")
    ax.set_ylabel("p / p0 (Hertz)")
    ax.set_title(f"pressure, delta = {DELTA:g}, c_n = {C_N:g}")
    ax.legend()
    for k, scale in ((2, "cube root"), (3, "log")):
        ax = fig.add_subplot(1, 3, k)
        t = (lambda n: np.asarray(n, dtype=float) ** (1 / 3)) if scale == "cube root" else np.asarray
        levels = [r for r in results["levels"] if r["error_J"] > 0 and r["eta_h"] >= 10 * results["eta_ref"]]
        ax.plot(t([r["ndof"] for r in levels]), [r["error_J"] for r in levels], "o-", ms=3,
                label="curved: (2 (J_h - J_ref))^1/2")
        ax.plot(t([r["ndof"] for r in levels]), [r["eta_h"] for r in levels], ":", color="C0", label="curved: eta_h")
        ax.plot(t([r["ndof"] for r in results["check"]]), [r["error_interp"] for r in results["check"]], "x", ms=5,
                color="C1", label="curved: |||u_h - u_ref|||_h")
        for i, (sides, polygon) in enumerate(results["polygons"].items()):
            records = polygon["records"]
            ax.plot(t([r["ndof"] for r in records]), [r["error_interp"] for r in records], "s-", ms=3,
                    color=f"C{i + 2}", label=f"{sides}-gon: against the curved reference")
            own = [r for r in records[:-1] if r["error_own"] > 0]
            ax.plot(t([r["ndof"] for r in own]), [r["error_own"] for r in own], "--", color=f"C{i + 2}",
                    label=f"{sides}-gon: against its own last level")
        fit = results["fits"]["curved"]
        if fit is not None:
            n = np.array([fit["first"], fit["last"]], dtype=float)
            chosen = results["fit_levels"]
            shift = np.mean([np.log(r["error_J"]) + fit["exponential"][0] * r["ndof"] ** (1 / 3) for r in chosen])
            ax.plot(t(n), np.exp(shift - fit["exponential"][0] * n ** (1 / 3)), "k-", lw=0.8,
                    label=f"exp(-{fit['exponential'][0]:.3f} N^1/3)")
        ax.set_yscale("log")
        if scale == "log":
            ax.set_xscale("log")
        ax.set_xlabel("N^(1/3)" if scale == "cube root" else "N (DOFs)")
        ax.set_ylabel("energy error")
        ax.grid(True, which="both", alpha=0.3)
        if k == 2:
            ax.legend(fontsize=7)
    write_png(fig, path, 120)


def _f(value, spec=".4e"):
    return "-" if value is None or (isinstance(value, float) and math.isnan(value)) else format(value, spec)


SETTING = r"""
The setting: the half-disk of radius $R = 1$, centre $(0, R)$, pressed onto the rigid plane $y = 0$ by a prescribed
displacement $u_D = (0, -\delta)$ of its flat top; $\Gamma_C$ the lower half circle with the gap
$g_a = y R / (R - y)$ along its normal, frictionless, $m_n = 1$, a stiff compliance $c_n$ (the Signorini limit is
$c_n \to \infty$); plane strain, $E = 1$, $\nu = 0.3$ (`ngdgfric.studies.curved.hertz_problem`).  hp-adaptive
SIPG (`ndf.adapt`, $p$ from 2 to 8) on curved elements.  Hertz (Johnson, *Contact Mechanics*, 1985, Section 4.2):
for the force $F$ per unit length, $a = (4 F R / (\pi E^*))^{1/2}$, $p_0 = 2 F / (\pi a)$, $E^* = E / (1 - \nu^2)$.
$F$ is the vertical resultant of the contact pressure by the discrete contact rule; $a$ is where $u_n - g_a$ changes
sign, found on 33 points per contact edge on the curved edges (a zero of the straight line between the two points
around the sign change); $p_0$ the pressure at $x = 0$ (a mesh vertex: the mean of its two edges).  Energy error:
$2 (J_h(u_h) - J_h(u_\mathrm{ref}))$ with the energy $J_h$ the discrete solution minimises
(`ngdgfric.studies.curved.discrete_energy`), $u_\mathrm{ref}$ the last level of an hp run to a much smaller
tolerance; checked against $|\!|\!| u_h - u_\mathrm{ref} |\!|\!|_h$ by point evaluation of $u_\mathrm{ref}$
(`ngdgfric.studies.curved.reference_error`).  The polygon: the same problem on inscribed polygons with 64 and
256 straight sides, errors against the curved reference (the true solution) and against its own last level.
""".strip()
"""The setting of the page, in Markdown."""


NORM = r"$|\!|\!| u_h - u_\mathrm{ref} |\!|\!|_h$"
ENERGY = r"$(2 (J_h(u_h) - J_h(u_\mathrm{ref})))^{1/2}$"
"""The two measures of the energy error against the reference."""
PROFILE = r"$\max \lvert p - p_H \rvert / p_{0,H}$"
"""The largest deviation of the pressure from Hertz's, relative to Hertz's peak (a table header)."""


def report(results, settings):
    ref = results["reference"]
    modulus = E / (1 - NU**2)
    worst = max(abs(ref["rel_a"]), abs(ref["rel_p0"]))
    curved = results["fits"].get("curved")
    kind = ("exponentially, like $e^{-b N^{1/3}}$ in the number $N$ of DOFs," if curved and
            curved["exponential"][1] < curved["algebraic"][1] else "like a power of the number $N$ of DOFs")
    lines = ["# Hertz's line contact on a curved half-disk", "",
             "An elastic half-disk pressed onto a rigid plane, solved by hp-adaptive SIPG on curved elements and "
             f"compared with Hertz's theory of line contact: the half-width $a$ and the peak pressure $p_0$ are within "
             f"{worst:.2%} of Hertz's.  On curved elements the energy error falls {kind} while on polygons with "
             "straight sides it stops at the error of the geometry.", "", SETTING, "",
             "## Hertz against the hp solution", "",
             f"$\\delta = {DELTA:g}$, $c_n = {C_N:g}$ ($c_n a / E^* = {C_N * ref['a'] / modulus:.0f}$), the last "
             f"level of the reference run: {ref['ndof']} DOFs, $\\eta_h$ = {ref['eta_h']:.2e} "
             f"({ref['eta_h'] / ref['norm']:.1e} of $|\\!|\\!| u_h |\\!|\\!|_h$).", ""]
    lines += [markdown_table(["$F$", "$F_n$ (pressure integral)", "$a$", "$a_H$ (Hertz)", "$a / a_H - 1$", "$p_0$",
                              "$p_{0,H}$ (Hertz)", "$p_0 / p_{0,H} - 1$", "$a / R$", PROFILE],
                             [[_f(ref["F"]), _f(ref["F_n"]), _f(ref["a"], ".6f"), _f(ref["a_hertz"], ".6f"),
                               _f(ref["rel_a"], "+.3%"), _f(ref["p0"], ".5e"), _f(ref["p0_hertz"], ".5e"),
                               _f(ref["rel_p0"], "+.3%"), _f(ref["a"] / R, ".4f"), _f(ref["profile"], ".3f")]]), ""]
    within = abs(ref["rel_a"]) < 0.01 and abs(ref["rel_p0"]) < 0.01
    lines += [f"Both within 1 % of Hertz: {'yes' if within else 'no'}.  The pressure profile (figure, left) follows "
              "Hertz's ellipse; its largest deviation is at the ends $x = \\pm a$, where Hertz's profile has an "
              "infinite slope and a shift of $a$ by a fraction $s$ moves $p$ there by about $(2 s)^{1/2} p_0$.", "",
              "Convergence of the measured quantities over the levels of the reference run (every third level of the "
              "fitted range and the last):", ""]
    shown = results["fit_levels"][::3] + [ref]
    lines += [markdown_table(["DOFs", "$\\eta_h$", "$F$", "$a$", "$a / a_H - 1$", "$p_0$", "$p_0 / p_{0,H} - 1$"],
                             [[r["ndof"], _f(r["eta_h"], ".2e"), _f(r["F"], ".6e"), _f(r["a"], ".6f"),
                               _f(r["rel_a"], "+.3%"), _f(r["p0"], ".5e"), _f(r["rel_p0"], "+.3%")]
                              for r in shown]), ""]
    lines += sweep_report(results["sweeps"], settings["sweep_rtol"])
    lines += convergence_report(results, settings)
    lines += [f"Regenerate: `{command_line()}`", ""]
    return "\n".join(lines)


def sweep_report(rows, rtol):
    if not rows:
        return []
    lines = ["## Finite body and finite compliance", "",
             f"Each row an hp run to $\\eta_h \\le {rtol:g}\\,|\\!|\\!| u_h |\\!|\\!|_h$; $a / R$ measures how far the "
             "half-disk is from Hertz's half-space, $c_n a / E^*$ how stiff the compliance is against the elastic "
             "stiffness of the contact zone.", ""]
    header = ["varied", "$\\delta$", "$c_n$", "$\\nu$", "DOFs", "$F$", "$a / R$", "$c_n a / E^*$", "$a / a_H - 1$",
              "$p_0 / p_{0,H} - 1$", PROFILE]
    lines += [markdown_table(header, [[r["vary"], f"{r['delta']:g}", f"{r['c_n']:g}", f"{r['nu']:g}", r["ndof"],
                                       _f(r["F"]), _f(r["a_over_R"], ".4f"), _f(r["compliance"], ".0f"),
                                       _f(r["rel_a"], "+.3%"), _f(r["rel_p0"], "+.3%"), _f(r["profile"], ".3f")]
                                      for r in rows]), ""]
    deltas = [r for r in rows if r["vary"] == "delta"]
    if len(deltas) >= 2:
        slope = np.polyfit(np.log([r["a_over_R"] for r in deltas]), np.log([abs(r["rel_a"]) for r in deltas]), 1)[0]
        mismatch = max(abs(r["rel_p0"] + r["rel_a"]) for r in deltas)
        lines += [f"Finite body ($\\delta$ varied, $c_n = {C_N:g}$): $\\lvert a / a_H - 1 \\rvert$ grows like "
                  f"$(a / R)^{{{slope:.2f}}}$ "
                  f"(least squares over the {len(deltas)} rows), between first order (the tilted normal, see the "
                  f"Poisson ratio below) and second order (the finite body).  In these rows $p_0 / p_{{0,H}} - 1 = "
                  f"-(a / a_H - 1)$ to {mismatch:.2%}, as for an elliptic profile of the measured width carrying $F$ "
                  "($p_0 = 2 F / (\\pi a)$): the discrete contact is Hertzian in shape, with a width that differs from "
                  "Hertz's.", ""]
    c_ns = sorted((r for r in rows if r["vary"] == "c_n"), key=lambda r: r["c_n"])
    if len(c_ns) >= 3:
        limit = c_ns[-1]
        shifts = [(r, r["rel_a"] - limit["rel_a"]) for r in c_ns[:-1]]
        text = ", ".join(f"{shift:+.2%} at $c_n a / E^* = {r['compliance']:.0f}$" for r, shift in shifts)
        small = [r["compliance"] for r, shift in shifts if abs(shift) < 1e-3]
        lines += [f"Compliance ($c_n$ varied, $\\delta = {DELTA:g}$): against the stiffest run "
                  f"($c_n = {limit['c_n']:g}$, $c_n a / E^* = {limit['compliance']:.0f}$, taken for the Signorini "
                  f"limit) the half-width moves by "
                  f"{text}: the compliant foundation lets the body penetrate and widens the contact"
                  + (f"; below 0.1 % from $c_n a / E^* = {min(small):.0f}$ on." if small else ".") + "", ""]
    nus = sorted((r for r in rows if r["vary"] == "nu"), key=lambda r: r["nu"])
    if len(nus) >= 2:
        text = ", ".join(f"{r['rel_a']:+.2%} at $\\nu = {r['nu']:g}$ ($(1 - 2\\nu) / (1 - \\nu) = "
                         f"{(1 - 2 * r['nu']) / (1 - r['nu']):.2f}$)" for r in nus)
        shrinking = all(abs(b["rel_a"]) < abs(a["rel_a"]) for a, b in zip(nus[:-1], nus[1:], strict=True))
        lines += [f"Poisson ratio ($\\delta = {DELTA:g}$, $c_n = {C_N:g}$): $a / a_H - 1$ = {text}."]
        if shrinking:
            lines += ["The deviation shrinks as $\\nu \\to 1/2$, where the tangential surface displacement $u_x$ of the"
                      " contact zone vanishes (it is proportional to $1 - 2\\nu$ for a half-space): the compliance law "
                      "measures the penetration along the body's normal, $u \\cdot n - g_a$ with $n$ tilted by $x / R$,"
                      " so $u_x x / R$ enters it; relative to the gap $x^2 / (2 R)$ this is of order $(1 - 2\\nu) / (1 "
                      "- \\nu) \\cdot a / R$, first order in $a / R$.  Hertz's theory takes the normal vertical (small "
                      "slopes) and drops that term: part of the deviation is Hertz's small-slope assumption, the rest "
                      "(what remains as $\\nu \\to 1/2$) the finite body."]
        lines += [""]
    return lines


def convergence_report(results, settings):
    lines = ["## Energy error: curved elements against a polygon", "",
             f"Reference: the last level of the hp run ({results['reference']['ndof']} DOFs, $\\eta_h$ = "
             f"{results['eta_ref']:.2e}).  Error of a level: {ENERGY} (the discrete energy, exact for nested hp "
             f"levels of one run up to the reference's own error); check: {NORM} by point evaluation of "
             "$u_\\mathrm{ref}$ on a second run's levels.  Polygons: the error against the curved "
             "reference (the true problem, on the polygon's domain) and against the polygon's own last level "
             "(its discretisation error only).", ""]
    lines += fits_table(results)
    local = results["fit_levels"]
    if len(local) >= 4:
        half = len(local) // 2
        first = fit_algebraic([r["ndof"] for r in local[:half + 1]], [r["error_J"] for r in local[:half + 1]])[0]
        second = fit_algebraic([r["ndof"] for r in local[half:]], [r["error_J"] for r in local[half:]])[0]
        lines += [f"Curved: the algebraic slope $s$ grows along the fitted range ({first:.2f} on its first half, "
                  f"{second:.2f} on its second): faster than any fixed power of $N$, as exponential convergence "
                  "is.", ""]
    check = fit_range(results["check"], results["eta_ref"])
    if check:
        ratio = [r["error_interp"] / r["error_J"] for r in check]
        lines += [f"The two error measures agree: {NORM[:-1]} / {ENERGY[1:]} in "
                  f"[{min(ratio):.3f}, {max(ratio):.3f}] on the {len(check)} levels of the check run in the fitted "
                  "range.", ""]
    lines += polygon_floors(results)
    spikes = [r for r in results["levels"][:-1] if r["error_J"] > 0 and r["eta_h"] > 10 * r["error_J"]]
    effectivity = [r["eta_h"] / r["error_J"] for r in results["fit_levels"]]
    if spikes:
        lines += [f"$\\eta_h$ / error exceeds 10 on levels {', '.join(str(r['level']) for r in spikes)} (at most "
                  f"{max(r['eta_h'] / r['error_J'] for r in spikes):.0f}): there "
                  "$\\eta_6 = \\lVert \\sigma_n(u_h) + c_n (u_{h,n} - g_a)_+ \\rVert$, which carries $c_n$, is nearly "
                  f"all of it ($\\eta_6 / \\eta_h \\ge {min(r['eta6'] / r['eta_h'] for r in spikes):.4f}$).  While "
                  "the mesh does not resolve the contact zone ($a \\approx 0.03$ against coarse edges) the compliance "
                  "residual is of size $c_n$ times an error of the penetration: the residual estimator is not robust "
                  "in $c_n$ there"
                  + (f" (on the fitted levels $\\eta_h$ / error is {min(effectivity):.1f}-{max(effectivity):.1f})."
                     if effectivity else "."), ""]
    lines += level_tables(results)
    return lines


def fits_table(results):
    """Markdown lines: the exponential and algebraic fits of every error measure."""
    lines = []
    fits_ = results["fits"]
    rows = []
    for name, fit in fits_.items():
        if fit is None:
            continue
        (b, rms_e), (s, rms_a) = fit["exponential"], fit["algebraic"]
        better = ("none: it stagnates" if fit["fall"] < 1.5 else "exponential" if rms_e < rms_a else "algebraic")
        better += ", levels off" if fit["fall"] >= 1.5 and fit["end"] < 1.05 else ""
        rows.append([name, f"{fit['first']}-{fit['last']} ({fit['points']} levels)", f"{fit['fall']:.3g}",
                     f"{b:.4f}", f"{rms_e:.3f}", f"{s:.3f}", f"{rms_a:.3f}", better])
    lines += ["Least-squares fits of the error $e$: $\\log e = c - b N^{1/3}$ (exponential) and "
              "$\\log e = c - s \\log N$ (algebraic); rms: root mean square residual in $\\log e$; \"falls by\": "
              "first / last error of the range.  \"curved\": the energy error, \"curved_eta\": $\\eta_h$, over the "
              f"levels with $\\eta_h$ below {FIT_RANGE[0]:g} $|\\!|\\!| u_h |\\!|\\!|_h$ and above {FIT_RANGE[1]:g} "
              "$\\eta_h$ of the reference; polygons: the error "
              "against the curved reference over the same DOF range (\"levels off\": its last two values differ by "
              "less than 5 %).", "",
              markdown_table(["error", "DOFs fitted", "falls by", "$b$", "rms (exp)", "$s$", "rms (alg)", "better fit"],
                             rows), ""]
    return lines


def polygon_floors(results):
    """Markdown lines: how far each polygon's error falls, and its floor against the number of sides."""
    lines = []
    for sides, polygon in results["polygons"].items():
        floor = min(r["error_interp"] for r in polygon["records"])
        passed = [r for r in results["levels"][:-1] if 0 < r["error_J"] < floor]
        own = [r["error_own"] for r in polygon["records"] if r["error_own"] > 0]
        lines += [f"The {sides}-gon's error against the true solution gets no smaller than {floor:.2e} (up to "
                  f"{polygon['records'][-1]['ndof']} DOFs)"
                  + (f", while its error against its own last level falls to {own[-1]:.2e}: what is left is the "
                     "geometry error (the polygon is a different problem), not discretisation" if own and
                     own[-1] < floor / 3 else "")
                  + (f"; the curved elements pass {floor:.2e} at {passed[0]['ndof']} DOFs." if passed else ".")]
    floors = [(sides, min(r["error_interp"] for r in polygon["records"]))
              for sides, polygon in results["polygons"].items()]
    if len(floors) >= 2:
        (n0, f0), (n1, f1) = floors[0], floors[-1]
        order = math.log(f0 / f1) / math.log(n1 / n0)
        lines += [f"The floor falls like $n^{{-{order:.2f}}}$ in the number $n$ of sides from {n0} to {n1} sides, "
                  f"i.e. like the side length to the power {order:.2f}"
                  + (": close to the order 3/2 that straight boundary edges with the circle's data leave on the "
                     "annulus ([curved meshes](curved.md), \"Straight edges\"), where the polygon is refined with the "
                     "mesh and the error falls algebraically at that order; a fixed polygon does not converge at all."
                     if 1.2 <= order <= 2.0 else ".")]
    lines += [""] if results["polygons"] else []
    return lines


def level_tables(results):
    """Markdown lines: the levels of the reference run, the check run and every polygon's run."""
    lines = []
    lines += ["Levels of the reference run (curved):", ""]
    lines += [markdown_table(["level", "DOFs", "$N^{1/3}$", "$\\eta_h$", "error (energy)", "$\\eta_h$ / error"],
                             [[r["level"], r["ndof"], f"{r['ndof'] ** (1 / 3):.2f}", _f(r["eta_h"], ".3e"),
                               _f(r["error_J"], ".3e"), _f(r["eta_h"] / r["error_J"] if r["error_J"] else None, ".2f")]
                              for r in results["levels"][:-1]]), ""]
    lines += ["Check run (curved), errors by point evaluation of the reference:", ""]
    lines += [markdown_table(["level", "DOFs", "$\\eta_h$", "error by point evaluation", "error by the energy"],
                             [[r["level"], r["ndof"], _f(r["eta_h"], ".3e"), _f(r["error_interp"], ".3e"),
                               _f(r["error_J"], ".3e")] for r in results["check"]]), ""]
    for sides, polygon in results["polygons"].items():
        m = polygon["measures"]
        lines += [f"Polygon with {sides} sides (side {2 * R * math.sin(math.pi / (2 * sides)):.4f}, "
                  f"sagitta {R * (1 - math.cos(math.pi / (2 * sides))):.1e}); stopped: {polygon['stopped']}; last "
                  f"level: $F$ = {m['F']:.4e}, $a$ = {_f(m['a'], '.5f')} ({_f(m['rel_a'], '+.2%')} against Hertz), "
                  f"$p_0$ = {m['p0']:.4e} ({m['rel_p0']:+.1%}):", ""]
        lines += [markdown_table(["level", "DOFs", "$\\eta_h$", "error against the curved reference",
                                  "error against its own last level"],
                                 [[r["level"], r["ndof"], _f(r["eta_h"], ".3e"), _f(r["error_interp"], ".3e"),
                                   _f(r["error_own"], ".3e")] for r in polygon["records"]]), ""]
    return lines

if __name__ == "__main__":
    run_script(main)
