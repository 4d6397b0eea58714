"""Which sparse direct solver: speed, Schur complements, what the install needs (issue 12, item 2).

The contact solver condenses the DG system onto the contact Gauss points (W = B A^-1 B^T,
:mod:`ngdgfric.solvers.condensation`), so it needs either a sparse factorisation that returns a Schur
complement, or 2M back-substitutions.  For the matrices A of Example 6.1 (SIPG symmetric, NIPG
nonsymmetric, 1e5-4e5 DOFs) this script times, best of ``--repeat`` runs in one process:

* NGSolve's own direct solvers: sparsecholesky (symmetric), umfpack; and NGSolve's PARDISO
  interface (present when the ``mkl`` wheel is installed);
* scipy's SuperLU (``scipy.sparse.linalg.splu``) and ``pypardiso``, if installed;
* MKL PARDISO with the Schur complement of the trace block of [[A, B^T], [B, 0]]
  (:class:`ngdgfric.solvers.pardiso.SchurFactorization`), as the contact solver uses it;
* the same W from back-substitutions with NGSolve's fastest factorisation (the path without mkl),
  timed on 64 columns and scaled to 2M;

and records which packages are importable, their installed size, and what MUMPS bindings on PyPI
need.  Writes results/linear_solvers.md and .csv.

    python benchmarks/bench_linear_solvers.py [--quick] [--repeat 3]
"""

import importlib
import importlib.metadata
import re
import sys
import time
from pathlib import Path

import numpy as np

import ngdgfric as ndf
from ngdgfric.contact import Contact
from ngdgfric.files import write_text
from ngdgfric.output import markdown_table
from ngdgfric.solvers import pardiso
from ngdgfric.solvers.condensation import augmented_matrix
from ngdgfric.threads import threads

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))  # scripts/common.py, shared
from common import command_line, run_script, say, script_parser, write_csv  # noqa: E402

CASES = [("sipg", 1, 7), ("sipg", 2, 7), ("nipg", 1, 7), ("nipg", 2, 6)]
QUICK = [("sipg", 1, 4), ("nipg", 1, 4)]
PACKAGES = ["ngsolve", "mkl", "intel-openmp", "tbb", "scipy", "pypardiso", "python-mumps", "mumpspy"]


def parse(argv=None):
    parser = script_parser(__doc__, "two small matrices, one run")
    parser.add_argument("--repeat", type=int, default=2)
    return parser.parse_args(argv)


def best_of(repeat, run):
    """min over ``repeat`` runs of run() -> dict of times (key by key)."""
    results = [run() for _ in range(repeat)]
    return {key: min(r[key] for r in results) for key in results[0]}


def ngsolve_inverse(disc, kind):
    def run():
        x = disc.F.CreateVector()
        with threads(disc.V.ndof):
            start = time.perf_counter()
            inverse = disc.A.Inverse(inverse=kind)
            factor = time.perf_counter() - start
            start = time.perf_counter()
            x.data = inverse * disc.F
            solve = time.perf_counter() - start
        del inverse
        return dict(factor=factor, solve=solve)
    return run


def scipy_superlu(disc):
    import scipy.sparse
    import scipy.sparse.linalg
    values, cols, rowptr = disc.A.CSR()
    A = scipy.sparse.csc_matrix(scipy.sparse.csr_matrix((np.array(values), np.array(cols), np.array(rowptr)),
                                                        shape=(disc.A.height, disc.A.width)))
    b = disc.F.FV().NumPy().copy()

    def run():
        start = time.perf_counter()
        lu = scipy.sparse.linalg.splu(A)
        factor = time.perf_counter() - start
        start = time.perf_counter()
        lu.solve(b)
        return dict(factor=factor, solve=time.perf_counter() - start)
    return run


def pypardiso_solver(disc):
    import pypardiso
    import scipy.sparse
    values, cols, rowptr = disc.A.CSR()
    A = scipy.sparse.csr_matrix((np.array(values), np.array(cols), np.array(rowptr)), shape=(disc.A.height,) * 2)
    b = disc.F.FV().NumPy().copy()

    def run():
        solver = pypardiso.PyPardisoSolver()
        start = time.perf_counter()
        solver.factorize(A)
        factor = time.perf_counter() - start
        start = time.perf_counter()
        solver.solve(A, b)
        solve = time.perf_counter() - start
        solver.free_memory(everything=True)
        return dict(factor=factor, solve=solve)
    return run


def pardiso_schur(disc):
    traces = Contact(disc).traces
    K = augmented_matrix(disc.A, traces, disc.symmetric)
    F = disc.F.FV().NumPy().copy()

    def run():
        start = time.perf_counter()
        factorization = pardiso.SchurFactorization(*K, 2 * traces.M, disc.symmetric)
        factor = time.perf_counter() - start
        start = time.perf_counter()
        factorization.solve_eliminated(F, np.zeros(2 * traces.M))
        solve = time.perf_counter() - start
        factorization.release()
        return dict(factor=factor, solve=solve)
    return run


def delassus_by_backsubstitution(disc, kind, columns=64):
    """W from back-substitutions: factorisation + 2M solves, timed on ``columns`` of them."""
    import ngsolve as ngs
    traces = Contact(disc).traces

    def run():
        with threads(disc.V.ndof):
            start = time.perf_counter()
            inverse = disc.A.Inverse(inverse=kind)
            factor = time.perf_counter() - start
            rhs, out = ngs.MultiVector(disc.F, columns), ngs.MultiVector(disc.F, columns)
            for k in range(columns):
                unit = np.zeros(2 * traces.M)
                unit[k] = 1.0
                rhs[k].FV().NumPy()[:] = traces.apply_transpose(unit)
            start = time.perf_counter()
            out[:] = inverse * rhs
            per_column = (time.perf_counter() - start) / columns
        del inverse
        return dict(factor=factor + per_column * 2 * traces.M, solve=per_column)
    return run


def installed(package):
    """(version, installed megabytes) of a distribution, or None."""
    try:
        dist = importlib.metadata.distribution(package)
    except importlib.metadata.PackageNotFoundError:
        return None
    size = 0
    for file in dist.files or []:
        path = Path(dist.locate_file(file))
        if path.is_file():
            size += path.stat().st_size
    return dist.version, size / 2**20


def importable(module):
    """'yes' or the error raised by importing ``module``."""
    try:
        importlib.import_module(module)
        return "yes"
    except Exception as error:  # ImportError, or numpy ABI errors raised as other types
        return f"no: {type(error).__name__}: {str(error).splitlines()[0][:120]}"


def main(argv=None):
    args = parse(argv)
    cases, repeat = (QUICK, 1) if args.quick else (CASES, args.repeat)
    problem = ndf.example_6_1()
    have_scipy = importable("scipy") == "yes"
    have_pypardiso = have_scipy and importable("pypardiso") == "yes"
    rows = []
    for method, order, k in cases:
        mesh = ndf.uniform_mesh(problem, 2.0**-k)
        disc = ndf.Discretization(problem, mesh, method=method, order=order)
        contact = ndf.contact.Contact(disc)
        symmetric = disc.symmetric
        fastest = "sparsecholesky" if symmetric else "umfpack"
        solvers = [(f"NGSolve {fastest}", ngsolve_inverse(disc, fastest))]
        if symmetric:
            solvers.append(("NGSolve umfpack", ngsolve_inverse(disc, "umfpack")))
        if pardiso.available():
            solvers.append(("NGSolve pardiso (mkl)", ngsolve_inverse(disc, "pardiso")))
        if have_scipy:
            solvers.append(("scipy SuperLU", scipy_superlu(disc)))
        if have_pypardiso:
            solvers.append(("pypardiso", pypardiso_solver(disc)))
        if pardiso.available():
            solvers.append(("PARDISO + Schur complement (ngdgfric)", pardiso_schur(disc)))
        solvers.append((f"W by back-substitution ({fastest})", delassus_by_backsubstitution(disc, fastest)))
        floor = None
        for name, run in solvers:
            times = best_of(repeat, run)
            floor = floor or times["factor"] + times["solve"]
            row = dict(method=method, order=order, h=f"2^-{k}", ndof=disc.V.ndof, symmetric=symmetric,
                       contact_unknowns=2 * contact.traces.M, solver=name, factor=times["factor"], solve=times["solve"],
                       schur=name.startswith("PARDISO + Schur") or name.startswith("W by"),
                       ratio=(times["factor"] + times["solve"]) / floor)
            rows.append(row)
            say(f"{method} P{order} h = 2^-{k} ({disc.V.ndof} dofs): {name}: factor {times['factor']:.3f} s, "
                f"solve {times['solve']:.4f} s, {row['ratio']:.2f} x NGSolve's fastest")
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(args.out / "linear_solvers.csv", rows)
    packages = {name: installed(name) for name in PACKAGES}
    imports = {"scipy": importable("scipy"), "pypardiso": importable("pypardiso"), "mumps (python-mumps)":
               importable("mumps"), "mumpspy": importable("mumpspy")}
    write_text(args.out / "linear_solvers.md", report(rows, packages, imports))
    return rows


def report(rows, packages, imports):
    def summary(kind, name):
        subset = [r for r in rows if r["solver"].startswith(name) and r["symmetric"] == (kind == "symmetric")]
        return ", ".join(f"{r['ratio']:.2f} ({r['method']} $P_{r['order']}$, {r['ndof']} DOFs)" for r in subset) or "-"

    lines = ["# Sparse direct solvers for the contact solver", "",
             "Which sparse direct solvers that install with pip can factorise the matrices of the contact solver, "
             "at what cost against NGSolve's own, and which of them give the Schur complement on the contact "
             "unknowns the contact solver needs.", "",
             "Matrices $A$ of Example 6.1 (uniform meshes, $\\eta = 30\\mu$).  Times: best of the runs in one "
             "process, 2 cores; 'ratio' is factorisation and one solve over NGSolve's fastest (sparsecholesky for the "
             "symmetric SIPG matrix, umfpack for NIPG).  'Schur' rows also give the Delassus operator $W$ of the "
             "$2M$ contact unknowns (`contact unknowns`); the back-substitution row is the path without mkl "
             "(64 columns timed, scaled to $2M$).", "",
             "## Summary (computed)", "",
             "- PARDISO factorisation with the Schur complement (what the contact solver needs), relative to "
             f"NGSolve's fastest plain factorisation and solve: symmetric {summary('symmetric', 'PARDISO + Schur')}; "
             f"nonsymmetric {summary('nonsymmetric', 'PARDISO + Schur')}.",
             f"- The same $W$ by back-substitutions: symmetric {summary('symmetric', 'W by')}; nonsymmetric "
             f"{summary('nonsymmetric', 'W by')}.",
             f"- NGSolve's PARDISO interface (plain): symmetric {summary('symmetric', 'NGSolve pardiso')}; "
             f"nonsymmetric {summary('nonsymmetric', 'NGSolve pardiso')}.",
             f"- scipy SuperLU: symmetric {summary('symmetric', 'scipy')}; "
             f"nonsymmetric {summary('nonsymmetric', 'scipy')}.",
             "", markdown_table(["method", "$p$", "$h$", "DOFs", "contact unknowns", "solver", "factorisation s",
                                 "solve s", "ratio", "Schur / $W$"],
                                [[r["method"], r["order"], re.sub(r"2\^-(\d+)", r"$2^{-\1}$", str(r["h"])), r["ndof"],
                                  r["contact_unknowns"], r["solver"],
                                  f"{r['factor']:.3f}", f"{r['solve']:.4f}", f"{r['ratio']:.2f}",
                                  "yes" if r["schur"] else "no"] for r in rows]), "",
             "## What each needs (measured in this environment)", "",
             markdown_table(["package", "version", "installed MB"],
                            [[name, *(("-", "not installed") if info is None else (info[0], f"{info[1]:.0f}"))]
                             for name, info in packages.items()]), "",
             markdown_table(["import", "works"], [[name, text] for name, text in imports.items()]), "",
             "- NGSolve's solvers (sparsecholesky, umfpack) come with the ngsolve wheel; no Schur complement.",
             "- MKL PARDISO comes with the `mkl` wheel (x86_64 Linux and Windows; it pulls intel-openmp, tbb and "
             "umf); NGSolve's wheel finds it at run time, and `ngdgfric.solvers.pardiso` calls its Schur-complement "
             "mode through ctypes.  pypardiso wraps the same library without the Schur complement.",
             "- scipy's SuperLU: no Schur complement, and not a dependency of ngdgfric.",
             "- MUMPS (Schur complement via ICNTL(19)): on PyPI only python-mumps 0.0.2 has a wheel, built "
             "against NumPy 1.x (it does not import with the NumPy 2 that ngsolve uses; see the import table); "
             "python-mumps 0.0.3/0.0.4 are source distributions that need a MUMPS library to build, and mumpspy "
             "loads a system libdmumps through ctypes and needs mpi4py: neither installs with pip alone.", "",
             f"Regenerate: `{command_line()}` (run alone: timings on a busy machine are meaningless).", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    run_script(main)
