"""Hertz's contact of two elastic cylinders: two bodies, a contact pair and load control, hp-adaptive.

Quarter cylinders of radii R1 = 1 (below, E = 1, nu = 0.3, standing on its flat side) and R2 = 0.5 (above, E = 2,
nu = 0.2) touching at the origin; the upper one has no Dirichlet side: a uniform pressure on its flat top transmits
the force P / 2 (the quarter model of the force P per unit length), the symmetry sides x = 0 hold both bodies
horizontally and only the contact holds the upper one vertically.  The contact pair (the upper arc against the
lower), frictionless, m_n = 1, c_n = 1e5, the gap from the geometry (no formula).  P is chosen for Hertz's
half-width a = 0.02.  Hertz (Johnson, Contact Mechanics, 1985, Section 4.2): a = (4 P R / (pi E*))^(1/2),
p0 = 2 P / (pi a), 1/R = 1/R1 + 1/R2, 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
(:mod:`ngdgfric.studies.two_cylinders`).  ``ndf.adapt(problem, rtol=1e-3)`` with its defaults (hp); a from the
sign change of the penetration [u] . n - g at the pair's points, p_max the largest pressure there.  Cost:
the whole adapt run against adapt on the half-disk pressed onto the rigid plane (results/hertz.md's scene,
:func:`ngdgfric.studies.curved.hertz_problem`, delta = 0.002, c_n = 1e5) to the same rtol and the same final DOFs
(``max_ndof``), best of ``REPEAT`` runs each.  Writes results/two_cylinders.md, .csv and .png.

    python scripts/two_cylinders.py [--quick] [--out results/]
"""

import time

from common import best, command_line, run_script, say, script_parser, write_csv

import ngdgfric as ndf
from ngdgfric.files import write_text
from ngdgfric.output import figure, markdown_table, write_png
from ngdgfric.studies.curved import hertz_problem
from ngdgfric.studies.two_cylinders import measures, plot_pressure, two_cylinders

# ==============================================================================================================
# PARAMETERS
# ==============================================================================================================

FULL = dict(rtol=1e-3, repeat=3)
QUICK = dict(rtol=1e-2, repeat=1)
FIELDS = ["level", "ndof", "eta_h", "a", "a_error", "p_max", "p_error", "F", "seconds"]


def parse(argv=None):
    return script_parser(__doc__, "rtol = 1e-2, one timing run").parse_args(argv)


# ==============================================================================================================
# MAIN
# ==============================================================================================================


def cylinders_run(problem, P, rtol):
    """adapt(rtol) with defaults on the two cylinders: (Adaptation, one record per level with Hertz's measures)."""
    records = []

    def keep(level, sol, est):
        records.append(dict(level=level, ndof=sol.ndof, eta_h=est.eta_h, **measures(sol, P)))

    start = time.perf_counter()
    run = ndf.adapt(problem, rtol=rtol, keep=keep, progress=None)
    seconds = time.perf_counter() - start
    for record in records:
        record["seconds"] = seconds
    return run, records, seconds


def draw(path, sol, P):
    """The pressure along the pair against Hertz's ellipse (:func:`ngdgfric.studies.two_cylinders.plot_pressure`)."""
    fig = figure(8, 3.5)
    ax = fig.add_subplot(1, 1, 1)
    plot_pressure(ax, sol, P)
    ax.set_title("Two cylinders: the pressure along the contact pair")
    write_png(fig, path, dpi=120)


SETTING = """\
The setting: quarter cylinders of radii $R_1 = 1$ (below, $E = 1$, $\\nu = 0.3$, standing on its flat side) and
$R_2 = 0.5$ (above, $E = 2$, $\\nu = 0.2$) touching at the origin; the upper one has no Dirichlet side: a uniform
pressure on its flat top transmits the force $P / 2$ (the quarter model of the force $P$ per unit length), the
symmetry sides $x = 0$ hold both bodies horizontally and only the contact holds the upper one vertically.  The
contact pair (the upper arc against the lower), frictionless, $m_n = 1$, $c_n = 10^5$, the gap from the geometry (no
formula).  $P$ is chosen for Hertz's half-width $a = 0.02$.  Hertz (Johnson, *Contact Mechanics*, 1985, Section
4.2): $a = (4 P R / (\\pi E^*))^{1/2}$, $p_0 = 2 P / (\\pi a)$, $1/R = 1/R_1 + 1/R_2$,
$1/E^* = (1 - \\nu_1^2)/E_1 + (1 - \\nu_2^2)/E_2$ ({mod}`ngdgfric.studies.two_cylinders`).  `ndf.adapt(problem,
rtol=1e-3)` with its defaults (hp); $a$ from the sign change of the penetration $[u] \\cdot n - g$ at the pair's
points, $p_\\mathrm{max}$ the largest pressure there.  Cost: the whole adapt run against adapt on the half-disk
pressed onto the rigid plane (the scene of [the Hertz page](hertz.md), $\\delta = 0.002$, $c_n = 10^5$) to the same
rtol and the same final DOFs (`max_ndof`), best of `REPEAT` runs each."""
"""The setting of the page (Markdown)."""


def main(argv=None):
    args = parse(argv)
    settings = QUICK if args.quick else FULL
    args.out.mkdir(parents=True, exist_ok=True)
    problem, P = two_cylinders()
    say(f"two cylinders, adapt(rtol={settings['rtol']:g}), best of {settings['repeat']}")
    cylinder_seconds, (run, records, _) = best(settings["repeat"],
                                                    lambda: cylinders_run(problem, P, settings["rtol"]))
    final = records[-1]
    half = hertz_problem(0.002, 1e5)
    half_seconds, half_run = best(settings["repeat"], lambda: ndf.adapt(
        half, rtol=settings["rtol"], max_ndof=final["ndof"], progress=None))
    write_csv(args.out / "two_cylinders.csv", records, FIELDS)
    draw(args.out / "two_cylinders.png", run.solution, P)
    rows = [[r["level"], r["ndof"], f"{r['eta_h']:.3e}", f"{r['a']:.6f}", f"{100 * r['a_error']:+.3f}%",
             f"{r['p_max']:.6e}", f"{100 * r['p_error']:+.3f}%", f"{r['F']:.6e}"] for r in records]
    within = abs(final["a_error"]) < 0.01 and abs(final["p_error"]) < 0.01
    text = "\n".join([
        "# Hertz between two elastic cylinders (two bodies, a contact pair, load control)",
        "",
        "Two elastic cylinders pressed together by a prescribed force (load control: the upper body is held by the "
        "contact alone), solved by `ndf.adapt` on a contact pair and compared with Hertz's theory: the half-width "
        f"$a$ and the peak pressure come within {max(abs(final['a_error']), abs(final['p_error'])):.2%} of Hertz's, "
        f"at {cylinder_seconds / half_seconds:.2f} times the seconds of one elastic body on a rigid plane.",
        "",
        SETTING,
        "",
        "## Against Hertz",
        "",
        f"$P$ = {P:.6e} (the quarter model carries $P / 2$ = {P / 2:.6e}); Hertz: $a$ = {final['a_H']:.6f}, "
        f"$p_0$ = {final['p0_H']:.6e}; method {run.method}, stopped on {run.stopped!r} after {len(records)} levels.",
        "",
        markdown_table(["level", "DOFs", "$\\eta_h$", "$a$", "$a / a_H - 1$", "$p_\\mathrm{max}$",
                        "$p_\\mathrm{max} / p_{0,H} - 1$", "normal resultant"], rows),
        "",
        f"Both within 1 % of Hertz on the last level: {'yes' if within else 'no'}.  The compliance takes "
        f"{final['compliance_share']:.1e} of the approach in the contact zone ($p_\\mathrm{{max}} / c_n$ against "
        "$a^2 / (2 R)$).",
        "",
        "![pressure against Hertz](two_cylinders.png)",
        "",
        "## Cost",
        "",
        markdown_table(["scene", "final DOFs", "levels", "seconds (best)"], [
            ["two cylinders (pair, load control)", final["ndof"], len(records), f"{cylinder_seconds:.2f}"],
            ["half-disk on the rigid plane (the Hertz page's scene)", half_run.levels[-1]["ndof"],
             len(half_run.levels), f"{half_seconds:.2f}"]]),
        "",
        f"Ratio {cylinder_seconds / half_seconds:.2f} (the target: within 2).  Beyond the half-disk's work, each "
        "level of the two bodies pairs the sides (closest points, the pieces aligned with $\\pi$), finds the free "
        "motion of the upper body and factorises $A + \\varepsilon M_f$, and takes a few proximal steps (each a "
        "condensed contact solve; the first from the warm start takes most of the Newton iterations).",
        "",
        f"Regenerate: `{command_line()}`",
        ""])
    write_text(args.out / "two_cylinders.md", text)
    say(f"a {100 * final['a_error']:+.3f}%, p {100 * final['p_error']:+.3f}%, {cylinder_seconds:.1f} s against "
        f"{half_seconds:.1f} s")
    return dict(records=records, cylinder_seconds=cylinder_seconds, half_seconds=half_seconds)


if __name__ == "__main__":
    run_script(main)
