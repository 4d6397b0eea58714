"""Volumetric locking of every method and degree as nu -> 1/2, on a divergence-free contact solution (issue 38).

The exact solution of :func:`ngdgfric.studies.manufactured.incompressible_contact_manufactured` (E = 1000, c_n = 10;
contact and no-contact, stick and slip zones on Gamma_C) is divergence-free for every nu: its stress 2 mu eps(u) and
its data stay bounded as nu -> 1/2, so a method that does not lock converges at the same rate with about the same
error for every nu, and one that locks does not (the manufactured solution of results/stability.md, whose stresses
grow with lam, cannot show this).  Its kinks lie on the mesh lines x = 1/4, 1/2 of every mesh h = 2^-k, so the
expected rate in the energy norm is p.

For the six methods of :data:`ngdgfric.METHODS` (default penalties), p = 1 ... 4, nu in :data:`NUS` and the uniform
meshes of :data:`LEVELS`: the relative energy error |||u - u_h|||_h / |||u|||, its growth (the error at nu divided by
the error at nu = 0.3 on the same mesh) and the observed rate in h over the two finest meshes.  A (method, p) locks at
nu when the growth exceeds :data:`GROWTH` on some mesh or the rate falls below p - :data:`RATE_DROP`; the first such nu
of the grid is the threshold that :data:`ngdgfric.dg.methods.LOCKING` states and the LockingWarning uses.
Writes results/locking.md and results/locking.csv.

    python scripts/locking.py [--quick] [--workers N] [--out DIR]
"""

import math
import time
import warnings

import ngsolve as ngs
from common import command_line, in_processes, run_script, say, script_parser, write_csv

import ngdgfric as ndf
from ngdgfric.dg.methods import METHODS
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.problem import strain_of, stress
from ngdgfric.studies.manufactured import incompressible_contact_manufactured

# ============================================================================ PARAMETERS
ORDERS = (1, 2, 3, 4)
NUS = (0.3, 0.45, 0.47, 0.49, 0.497, 0.499, 0.4997, 0.4999, 0.49999)  # 0.5 - nu from 0.2 down to 1e-5
LEVELS = {1: (2, 3, 4, 5), 2: (2, 3, 4, 5), 3: (2, 3, 4), 4: (2, 3, 4)}  # h = 2^-k (P3, P4: errors to 1e-5)
GROWTH = 2.0  # locking: the error at nu more than GROWTH times that at nu = 0.3 on some mesh ...
RATE_DROP = 0.5  # ... or the rate over the two finest meshes below p - RATE_DROP
E = 1000.0
QUICK = dict(methods=("cg", "bassi"), orders=(1,), nus=(0.3, 0.4999), levels=(2, 3))
FIELDS = ["method", "order", "nu", "h", "ndof", "relative_error", "effectivity", "iterations", "seconds", "status",
          "warnings"]


def parse(argv=None):
    parser = script_parser(__doc__, "cg and Bassi, P1, nu = 0.3 and 0.4999, h = 1/4 and 1/8")
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2; 1: no pool)")
    return parser.parse_args(argv)


# ============================================================================ ONE CASE
def run_case(item):
    """All meshes of one (method, order, nu): rows of FIELDS (a failed solve is a row with its status)."""
    method, order, nu, levels = item
    problem, exact = incompressible_contact_manufactured(E=E, nu=nu)
    strain = strain_of(exact)
    rows = []
    for k in levels:
        mesh = ndf.uniform_mesh(problem, 2.0**-k)
        row = dict(method=method, order=order, nu=nu, h=2.0**-k)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            start = time.perf_counter()
            try:
                sol = ndf.solve(problem, mesh, method=method, order=order)
            except ndf.SolverError as error:
                rows.append(dict(row, status=f"failed: {str(error).splitlines()[0][:100]}"))
                continue
        seconds = time.perf_counter() - start
        norm = ngs.Integrate(ngs.InnerProduct(stress(problem, strain), strain), mesh, order=16) ** 0.5
        error = ndf.energy_norm(sol, exact)
        rows.append(dict(row, ndof=sol.ndof, relative_error=error / norm, effectivity=ndf.estimate(sol).eta_h / error,
                         iterations=sol.iterations, seconds=seconds, status="solved",
                         warnings="; ".join(sorted({type(w.message).__name__ for w in caught}))))
    return rows


# ============================================================================ MEASURES
def errors(rows, method, order, nu):
    """{h: relative error} of the solved meshes of one (method, order, nu)."""
    return {r["h"]: r["relative_error"] for r in rows
            if (r["method"], r["order"], r["nu"]) == (method, order, nu) and r["status"] == "solved"}


def finest(rows, method, order, nu, key):
    """``key`` of the finest solved mesh of one (method, order, nu) (None: none solved)."""
    solved = [r for r in rows if (r["method"], r["order"], r["nu"]) == (method, order, nu) and r["status"] == "solved"]
    return min(solved, key=lambda r: r["h"])[key] if solved else None


def growth(rows, method, order, nu):
    """(largest over the meshes, on the finest mesh) of error at nu / error at the smallest nu on the same mesh;
    None where a mesh of either is missing (a failed solve)."""
    base, errs = errors(rows, method, order, min(r["nu"] for r in rows)), errors(rows, method, order, nu)
    if not base or set(base) != set(errs):
        return None
    ratios = {h: errs[h] / base[h] for h in errs}
    return max(ratios.values()), ratios[min(ratios)]


def rate(rows, method, order, nu):
    """The observed rate in h over the two finest meshes (None: fewer than two solved)."""
    errs = errors(rows, method, order, nu)
    if len(errs) < 2:
        return None
    fine, coarse = sorted(errs)[:2]
    return math.log(errs[coarse] / errs[fine]) / math.log(coarse / fine)


def locks(rows, method, order, nu):
    """Whether (method, order) locks at nu: error growth above GROWTH on some mesh, or the finest rate below
    p - RATE_DROP, or a failed solve."""
    grown, observed = growth(rows, method, order, nu), rate(rows, method, order, nu)
    return grown is None or observed is None or grown[0] > GROWTH or observed < order - RATE_DROP


def threshold(rows, method, order):
    """The first nu of the grid from which (method, order) locks at every larger nu (None: at none)."""
    nus = sorted({r["nu"] for r in rows})
    locking = [locks(rows, method, order, nu) for nu in nus]
    first = next((i for i in range(len(nus)) if all(locking[i:])), None)
    return None if first is None else nus[first]


# ============================================================================ REPORT
def fmt(value, spec=".3g"):
    return "-" if value is None else format(value, spec)


def warning_check(rows):
    """A sentence: where ``ndf.solve`` issued its LockingWarning against where this study finds locking."""
    cases = sorted({(r["method"], r["order"], r["nu"]) for r in rows})
    warned = {c for c in cases if any("LockingWarning" in (r.get("warnings") or "") for r in rows
                                      if (r["method"], r["order"], r["nu"]) == c)}
    locking = {(m, p, nu) for m, p, nu in cases if (threshold(rows, m, p) or 1.0) <= nu}
    differ = sorted(warned ^ locking)
    return (f"`ndf.solve` issued a LockingWarning in {len(warned)} of the {len(cases)} (method, $p$, $\\nu$) cases; "
            f"this "
            f"study finds locking in {len(locking)}; they differ in "
            + (", ".join(f"{m} $P_{p}$ $\\nu = {nu:g}$" for m, p, nu in differ) if differ else "none") + ".")


def pairs(rows):
    return [(m, p) for m in dict.fromkeys(r["method"] for r in rows) for p in sorted({r["order"] for r in rows})
            if any((r["method"], r["order"]) == (m, p) for r in rows)]


def summary_rows(rows):
    """One line per (method, p): error at nu = 0.3 (finest mesh), threshold, growth and rate there and at the
    largest nu."""
    nus, lines = sorted({r["nu"] for r in rows}), []
    for method, order in pairs(rows):
        nu_lock = threshold(rows, method, order)
        lines.append([method, order, fmt(finest(rows, method, order, nus[0], "relative_error"), ".2e"),
                      fmt(rate(rows, method, order, nus[0]), ".2f"), "-" if nu_lock is None else f"{nu_lock:g}",
                      *(_growth_and_rate(rows, method, order, nu_lock) if nu_lock is not None else ("-", "-")),
                      *_growth_and_rate(rows, method, order, nus[-1])])
    return lines


def _growth_and_rate(rows, method, order, nu):
    """(largest growth over the meshes, rate), formatted."""
    return fmt((growth(rows, method, order, nu) or (None,))[0], ".2f"), fmt(rate(rows, method, order, nu), ".2f")


def nu_table(rows, measure, spec):
    """One line per (method, p), one column per nu: ``measure(rows, method, order, nu)`` formatted."""
    nus = sorted({r["nu"] for r in rows})
    return markdown_table(["method", "$p$", f"$\\nu = {nus[0]:g}$"] + [f"{nu:g}" for nu in nus[1:]],
                          [[m, p] + [fmt(measure(rows, m, p, nu), spec) for nu in nus] for m, p in pairs(rows)])


def headline(rows):
    """The page's opening: what was measured, and which methods lock from which $\\nu$ (Markdown, computed)."""
    nus = sorted({r["nu"] for r in rows})
    free, locking = [], []
    for method in dict.fromkeys(r["method"] for r in rows):
        orders = sorted({r["order"] for r in rows if r["method"] == method})
        found = {p: threshold(rows, method, p) for p in orders}
        if all(nu is None for nu in found.values()):
            free.append(method.upper())
            continue
        by_nu = {}
        for p, nu in found.items():
            if nu is not None:
                by_nu.setdefault(nu, []).append(str(p))
        locking.append(f"{method.upper()} (" + "; ".join(f"$p = {', '.join(ps)}$ from $\\nu = {nu:g}$"
                                                          for nu, ps in sorted(by_nu.items())) + ")")
    text = ("Every method and degree on a contact solution that stays smooth and divergence-free as "
            f"$\\nu \\to 1/2$, for $\\nu$ from {nus[0]:g} to {nus[-1]:g}: a method that does not lock keeps its error "
            "and its rate, one that locks does not.")
    if free:
        text += f"  {', '.join(free)} do{'es' * (len(free) == 1)} not lock on this grid"
        text += (f"; {', '.join(locking)} lock." if locking else ".")
    elif locking:
        text += f"  {', '.join(locking)} lock."
    return text


def report(rows, quick):
    nus, failed = sorted({r["nu"] for r in rows}), [r for r in rows if r["status"] != "solved"]
    meshes = ", ".join(f"$P_{p}$: $h$ = " + ", ".join(f"1/{round(1 / h)}" for h in sorted(
        {r["h"] for r in rows if r["order"] == p}, reverse=True)) for p in sorted({r["order"] for r in rows}))
    lines = [f"# Volumetric locking: where each method and degree locks{' (quick run)' * quick}", "",
             headline(rows), "",
             "The setting: the divergence-free contact solution of "
             f"`ngdgfric.studies.manufactured.incompressible_contact_manufactured` ($E = {E:g}$, $c_n = 10$; its "
             "stresses and data stay bounded as $\\nu \\to 1/2$), every method with its default penalty and the "
             f"default solver, uniform meshes ({meshes}).  Relative energy error "
             "$|\\!|\\!| u - u_h |\\!|\\!|_h / |\\!|\\!| u |\\!|\\!|$; growth: the error at $\\nu$ divided by the "
             f"error at $\\nu = {nus[0]:g}$ on the same mesh; rate: observed order in $h$ over the two finest meshes "
             "(expected: $p$, the kinks of $u$ lie on mesh lines).", "",
             f"**Locks from $\\nu$** is the first $\\nu$ of the grid from which on the growth exceeds {GROWTH:g} on "
             f"some mesh or the rate falls below $p - {RATE_DROP:g}$ (or a solve fails); `-`: not up to "
             f"$\\nu = {nus[-1]:g}$.  These are the numbers of `ngdgfric.dg.methods.LOCKING`, which `ndf.solve` warns "
             f"with (LockingWarning) and `adapt` chooses its method by.  {len(rows)} solves, {len(failed)} failed.", "",
             "## Where each method locks", "",
             markdown_table(["method", "$p$", f"error at $\\nu = {nus[0]:g}$ (finest $h$)",
                             f"rate at $\\nu = {nus[0]:g}$", "locks from $\\nu$", "growth there (max over $h$)",
                             "rate there", f"growth at $\\nu = {nus[-1]:g}$", f"rate at $\\nu = {nus[-1]:g}$"],
                            summary_rows(rows)), "",
             "## Error growth (largest over the meshes)", "",
             nu_table(rows, lambda *a: (growth(*a) or (None,))[0], ".2f"), "",
             "## Error growth on the finest mesh", "",
             nu_table(rows, lambda *a: (growth(*a) or (None, None))[1], ".2f"), "",
             "## Observed rate over the two finest meshes", "",
             nu_table(rows, rate, ".2f"), "",
             "## Relative error on the finest mesh", "",
             nu_table(rows, lambda *a: finest(*a, "relative_error"), ".2e"), "",
             "## Estimator effectivity $\\eta_h$ / error on the finest mesh", "",
             "The default estimator (`ndf.estimate`, in the units of the energy norm).  It sees the stresses, so it "
             "also shows where the stresses lock while the displacement does not.", "",
             nu_table(rows, lambda *a: finest(*a, "effectivity"), ".2f"), "",
             "## The library's warning", "",
             warning_check(rows), ""]
    if failed:
        lines += ["## Failed solves", "", markdown_table(["method", "p", "nu", "h", "status"],
                                                         [[r["method"], r["order"], r["nu"], r["h"], r["status"]]
                                                          for r in failed]), ""]
    lines += [f"Regenerate: `{command_line()}`", ""]
    return "\n".join(lines)


# ============================================================================ MAIN
def main(argv=None):
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    methods = QUICK["methods"] if args.quick else tuple(METHODS)
    orders, nus = (QUICK["orders"], QUICK["nus"]) if args.quick else (ORDERS, NUS)
    items = [(m, p, nu, QUICK["levels"] if args.quick else LEVELS[p]) for m in methods for p in orders for nu in nus]
    rows = []
    for _, case_rows in in_processes(run_case, items, args.workers):
        rows += case_rows
        last = case_rows[-1]
        say(f"{last['method']} P{last['order']} nu = {last['nu']:g}: {last['status']}, relative error "
            f"{fmt(last.get('relative_error'), '.3e')}")
    position = {item[:3]: k for k, item in enumerate(items)}
    rows.sort(key=lambda r: (position[(r["method"], r["order"], r["nu"])], -r["h"]))
    write_csv(args.out / "locking.csv", rows, FIELDS)
    write_text(args.out / "locking.md", report(rows, args.quick))
    say(f"wrote {args.out / 'locking.md'}")
    return rows


if __name__ == "__main__":
    run_script(main)
