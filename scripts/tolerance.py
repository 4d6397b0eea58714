"""What adapt(problem, tol=t) delivers: the true energy error of its answer against t.

For Examples 6.1 and 6.2 and t = 1e-1, 1e-2, 1e-3: ``ndf.adapt(problem, tol=t)`` with its defaults
(the method adapt chooses, cg here; hp from p = 4 up to 8, Doerfler theta = 0.8, geometric layers, the
estimator in energy units), then
the true error |||u - u_h|||_h of the returned solution against the hp reference solutions of
results/reference.md (estimated error 3e-5).  Writes results/tolerance.md and .csv.

    python scripts/tolerance.py [--quick] [--out DIR]
"""

import argparse
import time
from pathlib import Path

from common import RESULTS, command_line, run_script, say, write_csv

import ngdgfric as ndf
from ngdgfric.examples import EXAMPLES
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table

TOLERANCES = (1e-1, 1e-2, 1e-3)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="t = 1, Example 6.2 only (smoke test)")
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    cases = [("6.2", 1.0)] if args.quick else [(e, t) for e in EXAMPLES for t in TOLERANCES]
    rows = []
    for example, tol in cases:
        problem = EXAMPLES[example]()
        reference = ndf.load_reference(RESULTS / f"reference_{example.replace('.', '_')}.npz", problem)
        start = time.perf_counter()
        run = ndf.adapt(problem, tol=tol, progress=None)
        seconds = time.perf_counter() - start
        error = ndf.energy_error(run.solution, reference)
        last = run.levels[-1]
        rows.append(dict(example=example, tol=tol, stopped=run.stopped, levels=len(run.levels), ndof=last["ndof"],
                         p_max=last["p_max"], eta_h=run.estimate.eta_h, error=error, error_over_tol=error / tol,
                         effectivity=run.estimate.eta_h / error, seconds=seconds))
        say(f"Example {example}, tol {tol:g}: {run.stopped} after {len(run.levels)} levels, {last['ndof']} DOFs, "
            f"eta_h {run.estimate.eta_h:.3e}, true error {error:.3e} = {error / tol:.2f} tol, {seconds:.1f} s")
    write_csv(args.out / "tolerance.csv", rows)
    write_text(args.out / "tolerance.md", report(rows))
    say(f"wrote {args.out / 'tolerance.md'}")
    return rows


def report(rows):
    table = [[r["example"], f"{r['tol']:g}", r["stopped"], r["levels"], r["ndof"], r["p_max"], f"{r['eta_h']:.3e}",
              f"{r['error']:.3e}", f"{r['error_over_tol']:.2f}", f"{r['effectivity']:.2f}", f"{r['seconds']:.1f}"]
             for r in rows]
    ratios = [r["error_over_tol"] for r in rows]
    return "\n".join([
        "# adapt(problem, tol=t): the true error of the answer", "",
        f"Regenerate: `{command_line()}`", "",
        "Defaults of `ndf.adapt`: the method it chooses (the conforming baseline cg on both examples), hp from p = 4 "
        "up to 8, Doerfler theta = 0.8, geometric layers towards the singular points, the estimator in energy "
        "units (`ndf.estimate`), stop as soon as eta_h <= t.  True error |||u - u_h|||_h of the returned solution "
        "against the hp reference solutions (results/reference.md, estimated error 3e-5).  Seconds: the whole "
        "loop, 2-core machine.", "",
        f"- true error / t = {min(ratios):.2f} - {max(ratios):.2f} over {len(rows)} runs "
        f"({'all' if all(0.1 <= q <= 1 for q in ratios) else 'not all'} within [1/10, 1]).", "",
        markdown_table(["example", "t", "stopped", "levels", "DOFs", "p_max", "eta_h", "true error", "error / t",
                        "eta_h / error", "s"], table), ""])


if __name__ == "__main__":
    run_script(main)
