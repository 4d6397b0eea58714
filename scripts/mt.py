"""Beyond the paper: the friction bound c_tau (u_n - g_a)_+^{m_t} with m_t > 0, Example 6.1.

Porwal & Tanvi analyse the reduced law m_t = 0 and leave m_t > 0, where (1.4) is a
quasi-variational inequality, to future work (Section 7).  Example 6.1 (SIPG, P1, eta = 30 mu)
with m_t = 0, 1, 2:

1. contact, stick and slip zones along Gamma_C on a uniform mesh;
2. the fully coupled semismooth Newton (``solver="newton"``) against the fixed point on the
   friction bound (``solver="fixed_point"``) for c_tau = 450 s, s = 1/2 ... 16: iterations,
   times, and where the fixed point fails;
3. the adaptive loop of Section 6 (Doerfler theta = 0.3) for each m_t, estimator eta_4 with the
   bound at u_h.

Writes results/mt.md and results/mt.png.

    python scripts/mt.py [--quick]
"""

import dataclasses
import time

import matplotlib
import numpy as np
from common import command_line, run_script, save_figure, say, script_parser

import ngdgfric as ndf
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.studies import max_rel_diff, slope

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

M_T = (0.0, 1.0, 2.0)


def parse(argv=None):
    parser = script_parser(__doc__, "coarse meshes, few cases and levels (smoke test)")
    return parser.parse_args(argv)


def problem_with(m_t, scale=1.0):
    """Example 6.1 with friction exponent m_t and friction coefficient c_tau = 450 scale."""
    base = ndf.example_6_1()
    return dataclasses.replace(base, m_t=m_t, c_tau=base.c_tau * scale)


def intervals(x, mask):
    """The runs of ``mask`` along the sorted points x as (start, end) pairs, cut halfway between points."""
    cuts = np.concatenate([[0.0], 0.5 * (x[1:] + x[:-1]), [1.0]])
    runs, start = [], None
    for i, inside in enumerate(mask):
        if inside and start is None:
            start = cuts[i]
        if not inside and start is not None:
            runs.append((start, cuts[i]))
            start = None
    if start is not None:
        runs.append((start, cuts[-1]))
    return runs


def zones(sol):
    """Contact, stick and slip along Gamma_C at the contact Gauss points, sorted by x."""
    state = ndf.contact_state(sol)
    order = np.argsort(state["x"])
    state = {k: v[order] for k, v in state.items()}
    contact = state["gap"] > 0
    slip = np.abs(state["u_tau"]) > 1e-8 * np.max(np.abs(sol.u.vec.FV().NumPy()))
    return state, dict(contact=contact, stick=contact & ~slip, slip=contact & slip, free=~contact)


def describe(runs):
    return ", ".join(f"({a:.3f}, {b:.3f})" for a, b in runs) or "-"


def zone_study(h):
    rows, states = [], {}
    for m_t in M_T:
        problem = problem_with(m_t)
        sol = ndf.solve(problem, ndf.uniform_mesh(problem, h))
        state, parts = zones(sol)
        states[m_t] = state
        rows.append(dict(m_t=m_t, ndof=sol.ndof, iterations=sol.iterations,
                         max_penetration=float(np.max(state["gap"])), max_bound=float(np.max(state["bound"])),
                         **{name: describe(intervals(state["x"], mask)) for name, mask in parts.items()},
                         kkt=max(ndf.kkt_residuals(sol).values())))
        say(f"zones m_t = {m_t:g}: stick {rows[-1]['stick']}, slip {rows[-1]['slip']}, "
            f"no contact {rows[-1]['free']}")
    return rows, states


def contraction(history):
    """Geometric mean of the ratios of consecutive fixed-point changes (after the first step)."""
    ratios = np.asarray(history[2:]) / np.asarray(history[1:-1])
    return float(np.exp(np.mean(np.log(ratios)))) if len(ratios) else float("nan")


def timed_solve(problem, mesh, solver):
    start = time.perf_counter()
    try:
        return ndf.solve(problem, mesh, solver=solver), time.perf_counter() - start, None
    except ndf.SolverError as error:
        return None, time.perf_counter() - start, error


def solver_study(cases):
    """Coupled Newton and fixed point on each (m_t, scale, h) case."""
    rows = []
    for m_t, scale, h in cases:
        problem = problem_with(m_t, scale)
        mesh = ndf.uniform_mesh(problem, h)
        newton, newton_seconds, newton_error = timed_solve(problem, mesh, "newton")
        fixed, fixed_seconds, fixed_error = timed_solve(problem, mesh, "fixed_point")
        row = dict(m_t=m_t, c_tau=problem.c_tau, h=h, ndof=6 * mesh.ne,  # P1
                   newton=f"{newton.iterations} ({newton.info['factorizations']})" if newton else "failed",
                   newton_seconds=newton_seconds, fixed=None, fixed_seconds=fixed_seconds,
                   difference=None)
        if fixed is not None:
            row["fixed"] = (f"{fixed.iterations} ({sum(fixed.info['inner_iterations'])}, "
                            f"{fixed.info['factorizations']})")
            row["contraction"] = contraction(fixed.history)
            if newton is not None:
                row["difference"] = max_rel_diff(fixed, newton)
        else:
            row["contraction"] = contraction(fixed_error.history) if len(fixed_error.history) > 2 else float("nan")
            row["fixed"] = ("failed: inner solve" if "inner" in str(fixed_error) else
                            f"failed after {len(fixed_error.history)}")
        if newton_error is not None:
            say(f"  Newton failed: {newton_error}")
        rows.append(row)
        say(f"solvers m_t = {m_t:g}, c_tau = {problem.c_tau:g}, h = {h:g}: Newton {row['newton']} "
            f"{newton_seconds:.2f} s, fixed point {row['fixed']} {fixed_seconds:.2f} s, "
            f"contraction factor {row['contraction']:.2f}")
    return rows


def adaptive_study(levels, max_ndof):
    curves = {}
    for m_t in M_T:
        say(f"adaptive m_t = {m_t:g}")
        curves[m_t] = ndf.adapt(problem_with(m_t), method="sipg", order=1, hp=False, theta=0.3, max_levels=levels,
                                max_ndof=max_ndof, rtol=0,
                                variant="paper", progress=None).levels
        last = curves[m_t][-1]
        say(f"  {len(curves[m_t])} levels, {last['ndof']} dofs, eta_h = {last['eta_h']:.4e}")
    return curves


def plot(states, curves, path):
    fig, axes = plt.subplots(2, 2, figsize=(10, 7.5))
    (pen, bound), (tangential, adaptive) = axes
    for i, (m_t, state) in enumerate(states.items()):
        color, label = f"C{i}", f"m_t = {m_t:g}"
        pen.plot(state["x"], state["gap"], color=color, label=label)
        bound.plot(state["x"], state["bound"], color=color, label=f"{label}: bound")
        bound.plot(state["x"], np.abs(state["sigma_tau"]), ":", color=color, label=f"{label}: |sigma_tau|")
        tangential.plot(state["x"], state["u_tau"], color=color, label=label)
        records = curves[m_t]
        adaptive.loglog([r["ndof"] for r in records], [r["eta_h"] for r in records], "o-", ms=3, color=color,
                        label=label)
    pen.axhline(0, color="k", lw=0.5)
    pen.set_title(r"penetration $u_n - g_a$ on $\Gamma_C$ (contact where > 0)")
    bound.set_title(r"friction bound $c_\tau (u_n - g_a)_+^{m_t}$ and $|\sigma_\tau(u_h)|$")
    tangential.set_title(r"tangential displacement $u_\tau$ (stick where 0)")
    for ax in (pen, bound, tangential):
        ax.set_xlabel("x")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    first = next(iter(curves.values()))
    n = np.array([first[0]["ndof"], first[-1]["ndof"]], dtype=float)
    adaptive.loglog(n, first[0]["eta_h"] * (n / n[0]) ** -0.5, "k:", label="slope -1/2")
    adaptive.set_title(r"adaptive: estimator $\eta_h$")
    adaptive.set_xlabel("degrees of freedom")
    adaptive.grid(True, which="both", alpha=0.3)
    adaptive.legend(fontsize=7)
    fig.suptitle(r"Example 6.1 with the friction bound $c_\tau (u_n - g_a)_+^{m_t}$")
    save_figure(fig, path, dpi=120)


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.quick:
        zone_h, cases, levels, max_ndof = 1 / 8, [(1.0, 1.0, 1 / 8), (1.0, 4.0, 1 / 8)], 4, 10**4
    else:
        scales = (0.5, 1.0, 2.0, 3.0, 4.0, 8.0, 16.0)
        zone_h, levels, max_ndof = 1 / 64, 40, 10**5
        cases = [(0.0, 1.0, 1 / 16)] + [(m_t, s, 1 / 16) for m_t in (1.0, 2.0) for s in scales]
        cases += [(m_t, 1.0, h) for m_t in (1.0, 2.0) for h in (1 / 32, 1 / 64)]
    zone_rows, states = zone_study(zone_h)
    solver_rows = solver_study(cases)
    curves = adaptive_study(levels, max_ndof)
    plot(states, curves, args.out / "mt.png")
    write_text(args.out / "mt.md", report(zone_h, zone_rows, solver_rows, curves))
    say(f"wrote {args.out / 'mt.md'}")
    return dict(zones=zone_rows, solvers=solver_rows, adaptive=curves)


def report(zone_h, zone_rows, solver_rows, curves):
    zone_table = markdown_table(
        ["$m_t$", "DOFs", "Newton iterations", "max. penetration", "max. bound", "stick", "slip", "no contact",
         "max. KKT residual"],
        [[f"{r['m_t']:g}", r["ndof"], r["iterations"], f"{r['max_penetration']:.4f}", f"{r['max_bound']:.1f}",
          r["stick"], r["slip"], r["free"], f"{r['kkt']:.1e}"] for r in zone_rows])
    solver_table = markdown_table(
        ["$m_t$", "$c_\\tau$", "$h$", "DOFs", "Newton iterations (factorisations)", "Newton seconds",
         "fixed point iterations (inner Newton iterations, factorisations)", "fixed point seconds",
         "contraction factor", "max. relative difference"],
        [[f"{r['m_t']:g}", f"{r['c_tau']:g}", f"1/{round(1 / r['h'])}", r["ndof"], r["newton"],
          f"{r['newton_seconds']:.2f}", r["fixed"], f"{r['fixed_seconds']:.2f}",
          "-" if np.isnan(r["contraction"]) else f"{r['contraction']:.2f}",
          "-" if r["difference"] is None else f"{r['difference']:.1e}"] for r in solver_rows])
    slopes = {m_t: slope([r["ndof"] for r in records[-10:]], [r["eta_h"] for r in records[-10:]])
              for m_t, records in curves.items()}
    adaptive_table = markdown_table(
        ["$m_t$", "levels", "final DOFs", "final $\\eta_h$", "$\\eta_4$ (final)", "slope (last 10)",
         "Newton iterations per level"],
        [[f"{m_t:g}", len(records), records[-1]["ndof"], f"{records[-1]['eta_h']:.4e}",
          f"{records[-1]['eta4']:.3e}", f"{slopes[m_t]:.3f}",
          f"{min(r['iterations'] for r in records)}-{max(r['iterations'] for r in records)}"]
         for m_t, records in curves.items()])
    findings = mt_findings(zone_rows, solver_rows)
    return "\n".join([
        "# A friction bound that grows with the penetration (Example 6.1)", "",
        "Beyond the paper: Example 6.1 with a friction bound $c_\\tau (u_n - g_a)_+^{m_t}$ that grows with the "
        "penetration, solved by the coupled semismooth Newton method and by a fixed point on the bound, and "
        "adaptively.  It shows where stick and slip lie for each $m_t$, how much cheaper the coupled Newton "
        "method is, and that the adaptive loop keeps its optimal rate.", "",
        "The paper analyses the reduced law $m_t = 0$ and leaves $m_t > 0$ to future work (Section 7).  With "
        "$j_\\tau(u, v) = \\int c_\\tau (u_n - g_a)_+^{m_t} \\lvert v_\\tau \\rvert \\, ds$, problem (1.4) is a "
        "quasi-variational inequality: the friction bound is zero where there is no contact and grows with the "
        "penetration.  Example 6.1 ($c_\\tau = 450$ unless stated), SIPG, $P_1$, $\\eta = 30\\mu$, default "
        "tolerances (Newton: relative KKT residual $10^{-13}$; fixed point: change $10^{-8}$ in the relative max "
        "norm).", "",
        "![zones and adaptivity](mt.png)", "",
        f"## Contact, stick and slip along $\\Gamma_C$ (uniform $h = 1/{round(1 / zone_h)}$)", "",
        "Zones are runs of contact Gauss points ($x$ intervals): contact where $u_n - g_a > 0$, slip where "
        "$\\lvert u_\\tau \\rvert > 10^{-8} \\max \\lvert u_h \\rvert$.  The KKT residual is the largest of "
        "$\\lvert l \\rvert - 1$, the complementarity $l u_\\tau = \\lvert u_\\tau \\rvert$ and the equilibrium (3.3) "
        "with the bound at $u_h$.", "",
        zone_table, "",
        "## Coupled semismooth Newton against the fixed point on the friction bound", "",
        "Newton: `ndf.solve(problem, mesh)` (the bound is linearised in $u_n$ inside the Newton system).  "
        "Fixed point: `ndf.solve(problem, mesh, solver=\"fixed_point\")`, each outer iteration a reduced-law "
        "solve (inner semismooth Newton, warm-started) with the bound frozen at the previous iterate.  The "
        "contraction factor is the geometric mean ratio of consecutive fixed-point changes.", "",
        solver_table, "",
        "## Adaptive convergence", "",
        "`ndf.adapt` with Dörfler $\\theta = 0.3$, estimator of Section 4 with $\\eta_4 = \\lVert \\sigma_\\tau(u_h) + "
        "c_\\tau (u_{h,n} - g_a)_+^{m_t} \\lambda_\\tau \\rVert$ (bound at $u_h$); optimal slope $-1/2$.", "",
        adaptive_table, "",
        "## Findings", "",
        *findings,
        "- The fixed point's contraction factor grows roughly in proportion to $c_\\tau$ (and to $m_t$ times the "
        "penetration to the power $m_t - 1$): the outer map is a contraction only while the bound varies slowly "
        "with $u_n$ compared with the stiffness of the body.  Beyond that it stalls (its changes stop decreasing).  "
        "Times are wall-clock on two cores; the factorisation counts are the robust measure: the coupled Newton "
        "factorises once (the condensation onto $\\Gamma_C$), the fixed point once per outer iteration (each inner "
        "solve condenses its own frozen-bound problem).", "",
        f"Regenerate: `{command_line()}`", ""])



def mt_findings(zone_rows, solver_rows):
    """Markdown bullets: the two solvers for m_t > 0 compared, and the friction bounds and stick zones."""
    coupled = [r for r in solver_rows if r["m_t"] > 0]
    speedups = [r["fixed_seconds"] / r["newton_seconds"] for r in coupled if r["difference"] is not None]
    failed = ", ".join(f"$m_t = {r['m_t']:g}$ with $c_\\tau = {r['c_tau']:g}$" for r in coupled
                       if r["fixed"].startswith("failed"))
    newton_failed = [r for r in coupled if r["newton"] == "failed"]
    findings = [
        f"- The coupled Newton failed in {len(newton_failed)} of {len(coupled)} cases with $m_t > 0$; its "
        f"iterations (factorisations): {', '.join(sorted({r['newton'] for r in coupled}))}.",
        f"- Where both converged, the fixed point took {min(speedups):.1f}-{max(speedups):.1f} times as long "
        "as the coupled Newton." if speedups else "- The fixed point never converged.",
        f"- The fixed point failed for {failed}." if failed else "- The fixed point converged in every case.",
        "- Largest friction bound on $\\Gamma_C$: " + ", ".join(f"{r['max_bound']:.1f} ($m_t = {r['m_t']:g}$)"
                                                                for r in zone_rows)
        + ".  The penetrations stay below 1, so $(u_n - g_a)_+^{m_t}$ weakens the friction; stick zones: "
        + ", ".join(f"{r['stick']} ($m_t = {r['m_t']:g}$)" for r in zone_rows) + ".",
    ]
    return findings


if __name__ == "__main__":
    run_script(main)
