"""Reference solutions of Examples 6.1 and 6.2 for true errors (hp-adaptive SIPG).

Not in the paper, which has no exact solutions: the references behind every true error of our Tables 6.1/6.2
(scripts/uniform_convergence.py) and of the accuracy studies.

Runs the hp-adaptive loop (SIPG, p from 2 up to ``--max-order``, Doerfler theta = 0.3, from uniform h = 1/2, no
geometric layers: every setting explicit, so that adapt's defaults, which changed, leave it as it is) until
eta_h <= ``--tol`` or ``--max-ndof``, and stores the last solution in results/reference_<example>.npz
(:mod:`ngdgfric.reference`) with its eta_h.  results/reference.md reports the distance of the
last levels to it: they fall geometrically, and the reference's own error is estimated as the
last of them times their last ratio.

    python scripts/reference.py [--example 6.1 6.2] [--quick]
"""

import shutil
import tempfile
import time
from pathlib import Path

from common import command_line, run_script, say, script_parser

import ngdgfric as ndf
from ngdgfric.examples import EXAMPLES
from ngdgfric.files import atomic_path, write_text
from ngdgfric.output import markdown_table


def parse(argv=None):
    parser = script_parser(__doc__, "a coarse reference (smoke test)", example="many")
    parser.add_argument("--tol", type=float, default=0.02, help="stop at eta_h <= tol (default 0.02)")
    parser.add_argument("--max-ndof", type=int, default=150_000)
    parser.add_argument("--max-order", type=int, default=8)
    return parser.parse_args(argv)


def make_reference(problem, path, tol, max_ndof, max_order, max_levels=80):
    """hp-adapt, keeping every level's solution; save the last to ``path``.  Returns the level
    records, each with ``distance`` = |||u_ref - u_level|||."""
    with tempfile.TemporaryDirectory() as folder:
        files = []

        def keep(level, sol, est):
            files.append(Path(folder) / f"level_{level}.npz")
            ndf.save_reference(sol, files[-1], eta_h=est.eta_h,
                               description=f"hp-adaptive SIPG, level {level}, {sol.ndof} dofs, eta_h = {est.eta_h:.4e}")

        start = time.perf_counter()
        records = ndf.adapt(problem, method="sipg", order=2, hp=True, max_order=max_order, tol=tol, layers=0,
                            max_ndof=max_ndof, max_levels=max_levels, variant="paper", theta=0.3, keep=keep,
                            progress=say).levels
        seconds = time.perf_counter() - start
        with atomic_path(path) as temporary:
            shutil.copyfile(files[-1], temporary)
        reference = ndf.load_reference(path, problem)
        for record, file in zip(records[:-1], files[:-1], strict=True):
            if record["ndof"] >= records[-1]["ndof"] / 8:
                record["distance"] = ndf.energy_error(ndf.load_reference(file, problem), reference)
    return records, seconds


def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    tol, max_ndof = (2.0, 5000) if args.quick else (args.tol, args.max_ndof)
    lines = ["# Reference solutions", "",
             "The solutions the true errors of the paper's examples are measured against: hp-adaptive runs far past",
             "the errors studied elsewhere, each with its own error estimated from how its last levels approach it",
             "(about $3 \\cdot 10^{-5}$ in the energy norm).", "",
             "hp-adaptive SIPG ($\\eta = 30\\mu$, $p$ from 2 up to the maximum, $\\theta = 0.3$, Melenk-Wohlmuth hp",
             "decision), stored as `reference_<example>.npz` and loaded by `ngdgfric.load_reference`.  True errors on",
             "the other pages are $|\\!|\\!| u_\\mathrm{ref} - u_h |\\!|\\!|_h$ by `ngdgfric.energy_error`.",
             "Below: the distance of the last levels to the reference; the reference's own error is estimated as",
             "the last distance times the last ratio of consecutive distances (geometric decay).", ""]
    results = {}
    for example in args.example:
        say(f"Example {example}: hp reference")
        path = args.out / f"reference_{example.replace('.', '_')}.npz"
        records, seconds = make_reference(EXAMPLES[example](), path, tol, max_ndof, args.max_order)
        results[example] = records
        last = records[-1]
        distances = [r["distance"] for r in records if "distance" in r]
        own = distances[-1] ** 2 / distances[-2] if len(distances) > 1 else float("nan")
        lines += [f"## Example {example}", "",
                  f"`{path.name}`: {last['ndof']} DOFs, $p = {last['p_min']}, \\dots, {last['p_max']}$, {len(records)} "
                  f"levels, $\\eta_h$ = {last['eta_h']:.3e} (the estimator of Section 4 as printed, not in the units "
                  f"of the energy norm), {seconds:.0f} s; estimated error {own:.1e} (from the distances below).", "",
                  markdown_table(["level", "DOFs", "$\\eta_h$", "distance to the reference"],
                                 [[r["level"], r["ndof"], f"{r['eta_h']:.3e}", f"{r['distance']:.3e}"]
                                  for r in records if "distance" in r]), ""]
    lines += [f"Regenerate: `{command_line()}`", ""]
    write_text(args.out / "reference.md", "\n".join(lines))
    say("\n".join(lines))
    return results


if __name__ == "__main__":
    run_script(main)
