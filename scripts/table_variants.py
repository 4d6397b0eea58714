"""Why do our Table 6.1/6.2 numbers differ from the paper's?  Try the plausible variants.

For SIPG, P1, on the paper's meshes h = 2^-1 ... 2^-5, compute the table's error under
variations of (a) the norm (energy of Section 3, relative energy, broken H1 seminorm, L2),
(b) the comparison (consecutive solutions as in Section 6, or a fine reference at h = 2^-7),
(c) the diagonal direction of the uniform mesh, (d) the reading of the traction g on Gamma_F,
(e) the penalty (eta = 30 mu, or eta = 30), and report for each the ratio ours/paper and the
rate differences.  Writes results/table_investigation.md and .csv.

    python scripts/table_variants.py [--quick]
"""

import argparse
import dataclasses
import math
from pathlib import Path

import ngsolve as ngs
from common import EXAMPLES, RESULTS, command_line, markdown_table, say, write_csv

import ngdgfric as ndf
from ngdgfric.paper import TABLES
from ngdgfric.studies import consecutive_differences, difference_norms, rates

NORMS = ("energy", "relative", "h1", "l2")


def traction_variants(example):
    """The literal traction of the paper and the plausible alternative reading."""
    base = EXAMPLES[example]()
    if example == "6.1":
        # g_x = 200 (5 - y) only on the left side, g_y = -190 only on the top
        on_left = ngs.IfPos(0.5 - ngs.x, 1.0, 0.0)
        other = ngs.CF((200 * (5 - ngs.y) * on_left, -190.0 * (1 - on_left)))
        return {"g literal": base, "g split by side": dataclasses.replace(base, g=other)}
    # equal and opposite compression of both vertical sides
    sign = ngs.IfPos(0.5 - ngs.x, 1.0, -1.0)
    return {"g literal": base, "g compressive": dataclasses.replace(base, g=ngs.CF((880 * sign, 0.0)))}


def solve_levels(problem, levels, diagonal="sw-ne", eta=None):
    out = []
    for k in levels:
        mesh = ndf.uniform_mesh(problem, 2.0**-k, diagonal=diagonal)
        out.append(ndf.solve(problem, mesh, eta=eta, tol=1e-10))
    return out


def variant_rows(example, name, solutions, reference, paper):
    hs = [s.mesh_h for s in solutions[:-1]]
    rows = []
    diffs = {"consecutive": consecutive_differences(solutions)}
    if reference is not None:
        diffs["reference"] = [difference_norms(s, reference) for s in solutions[:-1]]
    for comparison, values in diffs.items():
        for norm in NORMS:
            errors = [d[norm] for d in values]
            observed = rates(errors, hs)
            ratio = [e / p for e, p in zip(errors, paper["error"], strict=False)]
            rate_diff = [o - p for o, p in zip(observed[1:], paper["rate"][1:], strict=False)]
            rows.append(dict(example=example, variant=name, comparison=comparison, norm=norm,
                             errors=" ".join(f"{e:.3e}" for e in errors),
                             rates=" ".join(f"{r:.3f}" for r in observed[1:]),
                             ratio_min=min(ratio), ratio_max=max(ratio),
                             max_rate_diff_last3=max(abs(d) for d in rate_diff[-3:])))
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    levels = (1, 2, 3) if args.quick else (1, 2, 3, 4, 5, 6)
    ref_level = 4 if args.quick else 7
    rows = []
    for example in ("6.1", "6.2"):
        paper = TABLES[example]["sipg"]
        for gname, problem in traction_variants(example).items():
            variants = [("baseline", dict())] if gname != "g literal" else [
                ("baseline", dict()), ("diagonal nw-se", dict(diagonal="nw-se")),
                ("eta = 30 (not 30 mu)", dict(eta=30.0))]
            for vname, kw in variants:
                name = f"{gname}, {vname}"
                say(f"Example {example}: {name}")
                try:
                    sols = solve_levels(problem, levels, **kw)
                except ndf.SolverError as err:
                    say(f"  failed: {err}")
                    rows.append(dict(example=example, variant=name, comparison="-", norm="-",
                                     errors=f"solver failed: {err}", rates="-", ratio_min=math.nan,
                                     ratio_max=math.nan, max_rate_diff_last3=math.nan))
                    continue
                for s, k in zip(sols, levels, strict=True):
                    s.mesh_h = 2.0**-k
                reference = None
                if vname == "baseline":
                    reference = solve_levels(problem, (ref_level,), **kw)[0]
                rows += variant_rows(example, name, sols, reference, paper)
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(args.out / "table_investigation.csv", rows)
    (args.out / "table_investigation.md").write_text(report(rows))
    say(f"wrote {args.out / 'table_investigation.md'}")
    return rows


def findings(rows):
    """Sentences with the numbers: which variant comes closest to the paper, and how close."""
    lines = []
    for example in ("6.1", "6.2"):
        ok = [r for r in rows if r["example"] == example and not math.isnan(r["ratio_min"])]
        closest = min(ok, key=lambda r: abs(math.log(r["ratio_min"])) + abs(math.log(r["ratio_max"])))
        within = [r for r in ok if 0.9 <= r["ratio_min"] and r["ratio_max"] <= 1.1]
        base = next(r for r in ok if r["variant"] == "g literal, baseline" and r["comparison"] == "consecutive"
                    and r["norm"] == "energy")
        lines += [
            f"- Example {example}: the paper's measure (energy norm, consecutive solutions) gives ours/paper = "
            f"{base['ratio_min']:.3g} - {base['ratio_max']:.3g}, rates within {base['max_rate_diff_last3']:.3f} "
            f"of the paper's on the finest three rows.",
            f"- Example {example}: closest variant in size: {closest['variant']}, {closest['comparison']}, "
            f"{closest['norm']} norm (ours/paper {closest['ratio_min']:.3g} - {closest['ratio_max']:.3g}); "
            + (f"{len(within)} variant(s) agree within 10% in every row." if within else
               "no variant agrees with the paper within 10% in every row."),
        ]
    return lines


def report(rows):
    header = ["example", "variant", "comparison", "norm", "errors h=2^-1..", "rates", "ours/paper",
              "max |rate - paper| (last 3)"]
    table = [[r["example"], r["variant"], r["comparison"], r["norm"], r["errors"], r["rates"],
              f"{r['ratio_min']:.3g} - {r['ratio_max']:.3g}", f"{r['max_rate_diff_last3']:.3f}"] for r in rows]
    return "\n".join([
        "# Variants of the Table 6.1/6.2 error measure (SIPG, P1)", "",
        f"Regenerate: `{command_line()}`", "",
        "Paper: errors and rates of Tables 6.1, 6.2 (SIPG columns).  'consecutive': |u_h - u_{h/2}| as in "
        "Section 6; 'reference': |u_h - u_ref| with u_ref on h = 2^-7.  Norms: 'energy' = |||.|||_h of "
        "Section 3, 'relative' = energy / |||u_{fine}|||_h, 'h1' = broken H1 seminorm, 'l2' = L2 norm.", "",
        "## Findings (computed from the table below)", "", *findings(rows), "",
        markdown_table(header, table), ""])


if __name__ == "__main__":
    main()
