"""The cases of the default solver's robustness: one case, its verdict, and the case lists.

Every case is one ``ndf.solve(problem, mesh, method=..., order=...)`` with the default solver
(:mod:`ngdgfric.solvers.newton`).  A case passes iff the solve raises nothing and the solution satisfies
the discrete KKT system (3.3)-(3.4) of Lemma 3.1 at round-off (``ndf.kkt_residuals``):

    lam_excess = max(|l| - 1, 0) <= 1e-14,     complementarity <= 1e-12,
    equilibrium <= 10 max(rounding, 1e-14),

where ``rounding`` is the equilibrium residual of u rounded once more, u (1 +- eps) (what
round-off alone leaves; ``ngdgfric.contact.rounding_residual``), and, for m_t = 0 and
at most ``UZAWA_MAX_NDOF`` unknowns, where the paper's Uzawa iteration (Section 6; the full sparse
system, an independent solver) converges with solver_tol = 1e-11, the two solutions agree:
max|u_newton - u_uzawa| / max|u_uzawa| <= 1e-7.  Uzawa failing (slow convergence; stopped after
a time budget of wall time, which maxit = 20000 would often exceed by far) is recorded, not
counted against the case.  A SolverError is no failure when plain semismooth Newton from
``EXISTENCE_STARTS`` random starting forces finds no solution of the same condensed problem either
("no solution found").

Cases: a fixed list of named hard cases (``named_cases``: the failures reported before the solver's rewrite,
the extremes of tests/test_newton.py, and nine cases of the bimaterial strip: E = 1e3 / 1e5 on
its halves with the penetration-dependent friction bound, m_t = 1, 2, on uniform, Netgen and hp-adapted
meshes) and cases drawn by ``draw_case`` over: the five DG methods; p = 1, 2, 3 (a few p = 4); m_n in
{1, 1.5, 2, 3}; m_t in {0, 0.5, 1, 2} (mostly 0); c_n in {0, 1e-6, ..., 1e10}; c_tau in {0, 1e-3, ...,
1e9}; nu in {0, ..., 0.4999}; initial penetration, gap and spatially varying g_a; spatially varying E,
c_n, c_tau; problems: Examples 6.1 and 6.2 (``dataclasses.replace``), the manufactured contact solution
at E = 1, 1e3, 1e6 (data scaled with E), the manufactured solution with the friction bound
c_tau (u_n - g_a)_+^{m_t} (m_t = 1, 2), an L-shaped block, and a square with two adjacent contact sides
(an element with two contact edges); meshes: uniform h = 1/4, 1/8, 1/16 (1/32 in named cases), Netgen,
h-adapted and hp-adapted (variable order per element) by ``ndf.adapt`` on the family's base problem.
``random_cases`` draws them with numpy's ``default_rng(SEED)`` for the report of
scripts/solver_robustness.py; tests/test_solver_robustness.py draws them with hypothesis (the property
test) and runs the named and the quick cases.
"""

import collections
import dataclasses
import functools
import itertools
import math
import time
import warnings

import ngsolve as ngs
import numpy as np

import ngdgfric as ndf
from ngdgfric.contact import rounding_residual
from ngdgfric.dg.dofs import dg_ndof
from ngdgfric.dg.methods import METHODS
from ngdgfric.examples import EXAMPLES
from ngdgfric.solvers.condensation import Condensation
from ngdgfric.solvers.reduced import ReducedContact
from ngdgfric.solvers.uzawa import REPORT_EVERY
from ngdgfric.studies import max_rel_diff
from ngdgfric.studies.manufactured import contact_manufactured, friction_manufactured
from ngdgfric.studies.scenes import strip

# ============================================================================ PARAMETERS
SEED = 20261112
COUNT = 200  # drawn cases (plus the named ones)
UZAWA_MAX_NDOF = 6000
UZAWA_OPTIONS = dict(solver="uzawa", solver_tol=1e-11, maxit=20000)
UZAWA_SECONDS, QUICK_UZAWA_SECONDS = 30.0, 3.0  # time budget of one Uzawa run (12 ms per iteration seen)
LAM_EXCESS_TOL, COMPLEMENTARITY_TOL, EQUILIBRIUM_FACTOR, ROUNDING_FLOOR = 1e-14, 1e-12, 10.0, 1e-14
AGREEMENT_TOL, UZAWA_LIMITED = 1e-7, 1e-5
EXISTENCE_STARTS = 500  # random starts of the search for a solution after a SolverError

METHOD_NAMES = list(METHODS)
NU = [0.0, 0.3, 0.45, 0.49, 0.499, 0.4999]
C_N = [0.0, 1e-6, 1.0, 1e2, 1e4, 1e6, 1e8, 1e10]
C_TAU = [0.0, 1e-3, 1.0, 450.0, 1e4, 1e6, 1e9]
M_N = [1.0, 1.5, 2.0, 3.0]
M_T = [0.5, 1.0, 2.0]  # drawn in a minority of the cases; m_t = 0 otherwise
E_SCALES = [1.0, 1e3, 1e6]  # the manufactured solutions, data scaled with E
ORDERS, ORDER_WEIGHTS = [1, 2, 3, 4], [0.35, 0.35, 0.25, 0.05]
FAMILIES = ["6.1", "6.2", "manufactured", "friction", "L-shape", "corner"]
FAMILY_WEIGHTS = [0.25, 0.2, 0.2, 0.1, 0.1, 0.15]
MESHES, MESH_WEIGHTS = ["uniform", "netgen", "h-adapted", "hp-adapted"], [0.5, 0.2, 0.15, 0.15]
ADAPT_LEVELS = [6, 8, 10]
G_A_DRAWN = ["-0.01", "0.02", "0.01*x"]  # initial penetration, a gap, a varying gap

L_SHAPE = ndf.Polygon(((0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)),
                      ("contact", "traction", "traction", "traction", "dirichlet", "traction"))
CORNER = ndf.Polygon.rectangle(0, 0, 1, 1, bottom="contact", right="contact", top="dirichlet", left="traction")


def l_shape():
    """An L-shaped block on a foundation (the L_SHAPE file of tests/test_cli.py), held at the top of its leg."""
    return ndf.ContactProblem(E=1000.0, nu=0.3, f=(0.0, -10 * ngs.sin(math.pi * ngs.x / 2)), g=(0.0, 0.0),
                              c_n=1e4, m_n=1.5, g_a=0.001 * (ngs.x - 1) ** 2, c_tau=20.0, geometry=L_SHAPE,
                              name="L-shape")


def corner():
    """Example 6.2's data on the unit square with contact at the bottom and on the right."""
    return dataclasses.replace(ndf.example_6_2(), geometry=CORNER, name="corner")


BASES = {**EXAMPLES, "L-shape": l_shape, "corner": corner}
G_A = {"0.05": lambda: 0.05, "0": lambda: 0.0, "-0.01": lambda: -0.01, "0.02": lambda: 0.02,
       "0.01*x": lambda: 0.01 * ngs.x, "0.001*(x-1)^2": lambda: 0.001 * (ngs.x - 1) ** 2}
BASE_G_A = {"6.1": "0.05", "6.2": "0", "L-shape": "0.001*(x-1)^2", "corner": "0"}

# ============================================================================ THE CASES
def case(id, family, method, order, mesh, size, name="", nu=None, E=None, c_n=None, m_n=None, c_tau=None, m_t=0.0,
         g_a=None, E_varies=False, c_n_varies=False, c_tau_varies=False):
    """One case as plain data (reproducible from its row).  ``size``: h (uniform), maxh (netgen) or the
    number of adaptive levels; None data: the family's base values."""
    if family in BASES:
        base = BASES[family]()
        nu = base.nu if nu is None else nu
        E = base.E if E is None else E
        c_n = base.c_n if c_n is None else c_n
        m_n = base.m_n if m_n is None else m_n
        c_tau = base.c_tau if c_tau is None else c_tau
        g_a = BASE_G_A[family] if g_a is None else g_a
    elif family == "manufactured":  # contact_manufactured: m_n = 1, m_t = 0, c_tau and g_a its own
        m_n, c_tau, g_a = 1.0, None, "manufactured"
    elif family == "strip":  # scenes.strip: E = E / 100 E on its halves, g_a = 0
        nu, E = 0.3 if nu is None else nu, 1e3 if E is None else E
        c_n, m_n, c_tau, g_a = (1e6 if c_n is None else c_n), (2.0 if m_n is None else m_n), \
            (10.0 if c_tau is None else c_tau), "0"
    else:  # friction_manufactured: m_n = 1, g_a its own
        m_n, g_a = 1.0, "manufactured"
    return dict(id=id, name=name, family=family, method=method, order=order, mesh=mesh, size=size, nu=float(nu),
                E=float(E), E_varies=bool(E_varies), c_n=float(c_n), c_n_varies=bool(c_n_varies and c_n > 0),
                m_n=float(m_n), c_tau=None if c_tau is None else float(c_tau),
                c_tau_varies=bool(c_tau_varies and c_tau), m_t=float(m_t), g_a=g_a, g_a_kind=g_a_kind(g_a))


def named_cases():
    """The failures reported before the solver's rewrite and the extremes of tests/test_newton.py."""
    cases = []
    for nu in (0.499, 0.4999):
        for h in (1 / 8, 1 / 16, 1 / 32):
            cases.append(case(f"N{len(cases) + 1:02d}", "6.1", "sipg", 1, "uniform", h, nu=nu,
                              name=f"failed before the rewrite: Example 6.1, nu = {nu}"))
    for method, h in (("nipg", 1 / 8), ("sipg", 1 / 16)):
        cases.append(case(f"N{len(cases) + 1:02d}", "manufactured", method, 2, "uniform", h, nu=0.3, E=1000.0,
                          c_n=1e4, name="failed before the rewrite: manufactured, E = 1000, c_n = 1e4"))
    more = [
        dict(family="6.1", m_n=2.0, c_n=1e5, g_a="-0.01", name="initial penetration, m_n = 2"),
        dict(family="6.1", c_n=1e10, g_a="-0.01", name="stiff compliance, initial penetration"),
        dict(family="6.1", c_n=0.0, g_a="-0.01", name="no compliance"),
        dict(family="6.1", method="nipg", c_n=1e10, c_tau=1e9, name="stiff compliance, everything sticks"),
        dict(family="6.1", E=2000.0, E_varies=True, name="E = 2000 + 500 x"),
        dict(family="6.1", order=2, m_t=0.5, name="m_t = 1/2: the bound's derivative is unbounded"),
        dict(family="6.1", method="ldg", nu=0.4999, c_n=1e8, order=3, name="LDG P3, nearly incompressible"),
        dict(family="6.2", method="brezzi", c_tau=1e-3, name="tiny friction"),
        dict(family="corner", size=1 / 4, name="element with two contact edges (W singular)"),
        dict(family="corner", method="nipg", order=2, c_n=1e8, m_n=3.0, name="two contact sides, stiff"),
        dict(family="L-shape", mesh="netgen", size=0.3, name="L-shaped block (tests/test_cli.py)"),
        dict(family="L-shape", method="bassi", order=2, mesh="hp-adapted", size=8, order_kind="hp",
             name="L-shaped block, hp-adapted"),
        dict(family="manufactured", method="brezzi", order=3, E=1e6, c_n=1e9, nu=0.49, size=1 / 16,
             name="manufactured, E = 1e6, c_n = 1e9"),
        dict(family="friction", method="nipg", order=2, E=1.0, c_n=0.01, c_tau=0.1, m_t=2.0, size=1 / 16,
             name="friction bound m_t = 2, E = 1"),
        dict(family="friction", method="sipg", order=1, E=1e3, c_n=10.0, c_tau=1e6, m_t=1.0,
             name="friction bound m_t = 1, huge c_tau"),
        *strip_cases(),
    ]
    for spec in more:
        spec = dict(spec)
        family, method = spec.pop("family"), spec.pop("method", "sipg")
        order, mesh, size = spec.pop("order", 1), spec.pop("mesh", "uniform"), spec.pop("size", 1 / 8)
        if spec.pop("order_kind", None) == "hp":
            order = "hp"
        if family in ("manufactured", "friction"):
            spec.setdefault("nu", 0.3)
        cases.append(case(f"N{len(cases) + 1:02d}", family, method, order, mesh, size, **spec))
    return cases


def strip_cases():
    """Varying E with m_t > 0: the bimaterial strip of ngdgfric.studies.scenes.strip (E = 1e3 / 1e5,
    c_n = 1e6, m_n = 2, c_tau = 10, m_t = 1, where the default solver's inner solves used to fail), on
    several meshes, methods and orders, and variations of its contrast, compliance and bound."""
    base = dict(family="strip", m_t=1.0, order=2, size=1 / 2)
    return [dict(base, name="bimaterial strip, m_t = 1 (where the inner solves failed)"),
            dict(base, size=1 / 4, name="bimaterial strip, m_t = 1, h = 1/4"),
            dict(base, method="nipg", name="bimaterial strip, NIPG"),
            dict(base, method="bassi", order=3, mesh="netgen", size=0.4, name="bimaterial strip, Netgen, P3"),
            dict(base, method="ldg", order=1, size=1 / 8, name="bimaterial strip, LDG P1"),
            dict(base, method="brezzi", m_t=2.0, name="bimaterial strip, m_t = 2"),
            dict(base, c_n=1e8, m_n=1.0, c_tau=100.0, name="bimaterial strip, stiffer, larger bound"),
            dict(base, E=1.0, c_n=1e3, c_tau=0.01, name="bimaterial strip, E = 1 / 100"),
            dict(base, mesh="hp-adapted", size=8, order_kind="hp", name="bimaterial strip, hp-adapted")]


def draw_case(id, method, pick, coin):
    """A case drawn over the ranges of the module docstring: ``pick(values, weights=None)`` chooses one of
    ``values``, ``coin(p)`` is True with probability ``p`` (numpy's generator in ``random_cases``,
    hypothesis in the property test)."""
    family = pick(FAMILIES, FAMILY_WEIGHTS)
    order = pick(ORDERS, ORDER_WEIGHTS)
    mesh = "netgen" if family == "L-shape" and coin(0.6) else pick(MESHES, MESH_WEIGHTS)
    if family == "L-shape" and mesh == "uniform":
        mesh = pick(["netgen", "h-adapted", "hp-adapted"])
    if mesh == "uniform":
        size = pick([1 / 4, 1 / 8] if order == 4 else [1 / 4, 1 / 8, 1 / 16])
    elif mesh == "netgen":
        size = 0.3 if family == "L-shape" else pick([0.3, 0.15] if order == 4 else [0.3, 0.15, 0.1])
    else:
        size = pick(ADAPT_LEVELS)
    if mesh == "hp-adapted":
        order = "hp"
    spec = dict(id=id, family=family, method=method, order=order, mesh=mesh, size=size)
    if family == "manufactured":
        E = pick(E_SCALES)
        spec.update(E=E, nu=pick(NU[1:]),  # the construction needs nu > 0.04 (c_tau >= 0)
                    c_n=10 * E / 1000 * pick([0.1, 1.0, 1e2, 1e3, 1e5]))
    elif family == "friction":
        E = pick(E_SCALES)
        spec.update(E=E, nu=pick(NU), m_t=pick([1.0, 2.0]), c_n=10 * E / 1000 * pick([1.0, 1e2, 1e4]),
                    c_tau=E / 1000 * pick([0.0, 1e-3, 1.0, 100.0, 1e4]))
    else:
        base = BASES[family]()
        spec.update(nu=base.nu if coin(0.3) else pick(NU), E=base.E, E_varies=coin(0.2),
                    c_n=base.c_n if coin(0.2) else pick(C_N), c_n_varies=coin(0.2),
                    m_n=base.m_n if coin(0.4) else pick(M_N), c_tau=base.c_tau if coin(0.2) else pick(C_TAU),
                    c_tau_varies=coin(0.2), m_t=0.0 if coin(0.85) else pick(M_T),
                    g_a=BASE_G_A[family] if coin(0.4) else pick(G_A_DRAWN))
    return case(**spec)


def random_cases(count=COUNT, seed=SEED):
    """``count`` cases R001, ... drawn with numpy's default_rng(seed), the methods in turn."""
    rng = np.random.default_rng(seed)

    def pick(values, weights=None):
        return values[int(rng.choice(len(values), p=weights))]

    def coin(p):
        return rng.random() < p

    return [draw_case(f"R{i + 1:03d}", METHOD_NAMES[i % len(METHOD_NAMES)], pick, coin) for i in range(count)]


def quick_cases():
    """Eight small cases for the smoke test (a few seconds)."""
    return [
        case("Q1", "6.1", "sipg", 1, "uniform", 1 / 4, nu=0.499),
        case("Q2", "6.2", "nipg", 2, "uniform", 1 / 4, c_n=1e8, g_a="-0.01"),
        case("Q3", "manufactured", "bassi", 1, "uniform", 1 / 4, E=1.0, nu=0.3, c_n=0.01),
        case("Q4", "friction", "brezzi", 1, "uniform", 1 / 4, E=1e3, nu=0.3, c_n=10.0, c_tau=100.0, m_t=1.0),
        case("Q5", "L-shape", "ldg", 1, "netgen", 0.5, m_n=2.0, c_tau_varies=True),
        case("Q6", "corner", "sipg", 1, "uniform", 1 / 4, E_varies=True),
        case("Q7", "6.1", "sipg", "hp", "hp-adapted", 4, c_n=1e4, c_n_varies=True),
        case("Q8", "6.2", "ldg", 2, "netgen", 0.5, m_t=1.0, g_a="0.01*x"),
    ]


# ============================================================================ PROBLEMS AND MESHES
def build_problem(spec):
    """The ContactProblem of a case."""
    family, E = spec["family"], spec["E"]
    if family == "manufactured":
        return contact_manufactured(E=E, nu=spec["nu"], c_n=spec["c_n"], K=50 * E / 1000)[0]
    if family == "friction":
        return friction_manufactured(m_t=int(spec["m_t"]), E=E, nu=spec["nu"], c_n=spec["c_n"], c_tau=spec["c_tau"],
                                     K=50 * E / 1000)[0]
    if family == "strip":
        return dataclasses.replace(strip(E0=E, E1=100 * E, c_n=spec["c_n"], m_n=spec["m_n"], c_tau=spec["c_tau"],
                                         m_t=spec["m_t"], pressure=0.1 * E).problem, nu=spec["nu"])
    x = ngs.x
    return dataclasses.replace(BASES[family](), nu=spec["nu"], E=E * (1 + x / 4) if spec["E_varies"] else E,
                               c_n=spec["c_n"] * (1 + x) if spec["c_n_varies"] else spec["c_n"], m_n=spec["m_n"],
                               c_tau=spec["c_tau"] * 2 * x if spec["c_tau_varies"] else spec["c_tau"],
                               m_t=spec["m_t"], g_a=G_A[spec["g_a"]]())


def adapt_base(family):
    """The problem whose adaptive loop makes the adapted meshes of a family (same geometry and labels)."""
    if family == "manufactured":
        return contact_manufactured()[0]
    if family == "friction":
        return friction_manufactured(m_t=1)[0]
    if family == "strip":
        return strip().problem
    return BASES[family]()


@functools.lru_cache(maxsize=None)
def adapted_mesh(family, hp, levels):
    """(mesh, orders) of the last level of ``ndf.adapt`` on the family's base problem (computed once per
    process).  hp: order 2 up to 5 from the default initial mesh; h: P1 from h = 1/4 (Netgen maxh = 0.3
    for the L-shape).  The mesh is copied at each level: adapt refines its mesh in place."""
    problem, kept = adapt_base(family), {}

    def keep(level, sol, est):
        kept.update(mesh=ngs.Mesh(sol.mesh.ngmesh.Copy()), orders=sol.discretization.orders.copy())

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ndf.PenaltyWarning)
        if hp:
            ndf.adapt(problem, hp=True, order=2, max_order=5, max_levels=levels, rtol=0, variant="paper", theta=0.3,
                      progress=None, keep=keep)
        else:
            start = ndf.uniform_mesh(problem, 1 / 4) if problem.geometry.is_rectangle else ndf.netgen_mesh(problem, 0.3)
            ndf.adapt(problem, mesh=start, order=1, hp=False, max_levels=levels, rtol=0, variant="paper", theta=0.3,
                      progress=None, keep=keep)
    return kept["mesh"], kept["orders"].astype(np.int64)


def build_mesh(spec, problem):
    """(mesh, order) of a case: order is p, or the per-element orders of an hp-adapted mesh."""
    if spec["mesh"] == "uniform":
        return ndf.uniform_mesh(problem, spec["size"]), spec["order"]
    if spec["mesh"] == "netgen":
        return ndf.netgen_mesh(problem, spec["size"]), spec["order"]
    hp = spec["mesh"] == "hp-adapted"
    mesh, orders = adapted_mesh(spec["family"], hp, spec["size"])
    return mesh, orders if hp else spec["order"]


# ============================================================================ ONE CASE
def existence_search(problem, mesh, method, order, starts=EXISTENCE_STARTS):
    """After the solver raised: look for a solution of the condensed problem (the same W, w0 and laws)
    by plain semismooth Newton (no globalisation, at most 40 steps) from ``starts`` random forces of
    scales 1e-3 ... 1e9.  Returns the first start that converged (the solver missed a solution: the
    case fails), or None (no solution found: the solver's error is the right answer as far as we know)."""
    disc = ndf.Discretization(problem, mesh, method=method, order=order)
    contact = ndf.contact.Contact(disc)
    traces = contact.traces
    condensation = Condensation(disc.A, disc.F, traces, disc.symmetric)
    reduced = ReducedContact.condensed(condensation, traces, disc.symmetric)
    rng = np.random.default_rng(0)
    for start in range(starts):
        f = rng.standard_normal(2 * reduced.M) * 10 ** rng.uniform(-3, 9)
        for _ in range(40):
            state = reduced.evaluate(f)
            if reduced.converged(state, 1e-12):
                return start
            f = f + reduced.newton_direction(state)
            if not np.all(np.isfinite(f)):
                break
    return None


class OverBudget(Exception):
    """Uzawa ran longer than its time budget (raised from its progress callback)."""

    def __init__(self, message, iteration):
        super().__init__(message)
        self.iteration = iteration


def time_budget(seconds):
    """A progress callback for Uzawa (called every ``uzawa.REPORT_EVERY`` iterations) that stops it after
    ``seconds``."""
    start, calls = time.perf_counter(), itertools.count(1)

    def check(message):
        iteration = next(calls) * REPORT_EVERY
        elapsed = time.perf_counter() - start
        if elapsed > seconds:
            raise OverBudget(f"stopped after {elapsed:.1f} s (time budget {seconds:g} s) at {message}", iteration)

    return check


def _message(error):
    return f"{type(error).__name__}: {error}".replace("\n", " ").replace("|", "/")


def run_case(spec, uzawa_seconds=UZAWA_SECONDS):
    """Solve one case with Newton (and Uzawa where it applies, unless ``uzawa_seconds`` is 0); returns its row."""
    row = dict(spec, status="fail", message="", uzawa_status="not run")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            problem = build_problem(spec)
            mesh, order = build_mesh(spec, problem)
            orders = np.full(mesh.ne, order) if np.ndim(order) == 0 else order
            row.update(elements=mesh.ne, p_min=int(orders.min()), p_max=int(orders.max()),
                       ndof=dg_ndof(orders))  # dim V_h, also when the solve fails
            start = time.perf_counter()
            sol = ndf.solve(problem, mesh, method=spec["method"], order=order)
            row.update(seconds=time.perf_counter() - start, status="solved", ndof=sol.ndof,
                       iterations=sol.iterations, contact_points=sol.info["contact_points"],
                       penetrating=sol.info["penetrating"], stick=sol.info["stick"],
                       steps=", ".join(f"{k}: {n}" for k, n in collections.Counter(sol.info["steps"]).items()))
            row.update(ndf.kkt_residuals(sol))
            row["rounding"] = rounding_residual(sol)
            row["equilibrium_ratio"] = row["equilibrium"] / max(row["rounding"], ROUNDING_FLOOR)
        except Exception as error:  # noqa: BLE001 -- every error is a result of the study
            row["message"] = _message(error)
            if isinstance(error, ndf.SolverError):
                found = existence_search(problem, mesh, spec["method"], order)
                row["existence"] = (f"a solution exists (plain Newton from random start {found})" if found is not None
                                    else f"no solution found from {EXISTENCE_STARTS} random starts")
                if found is None:
                    row["status"] = "no solution found"
        if uzawa_seconds > 0 and row["status"] == "solved" and spec["m_t"] == 0 and sol.ndof <= UZAWA_MAX_NDOF:
            start = time.perf_counter()
            try:
                uzawa = ndf.solve(problem, mesh, method=spec["method"], order=order, **UZAWA_OPTIONS,
                                  progress=time_budget(uzawa_seconds))
                uzawa_kkt = ndf.kkt_residuals(uzawa)
                row.update(uzawa_status="converged", uzawa_iterations=uzawa.iterations,
                           uzawa_difference=max_rel_diff(sol, uzawa),
                           uzawa_complementarity=uzawa_kkt["complementarity"],
                           uzawa_equilibrium=uzawa_kkt["equilibrium"])
            except OverBudget as error:
                row.update(uzawa_status="stopped", uzawa_iterations=error.iteration, uzawa_message=str(error))
            except ndf.SolverError as error:
                row.update(uzawa_status="failed", uzawa_iterations=len(error.history), uzawa_message=_message(error))
            except Exception as error:  # noqa: BLE001 -- anything but a SolverError is reported as an error
                row.update(uzawa_status="error", uzawa_message=_message(error))
            row["uzawa_seconds"] = time.perf_counter() - start
    row["warnings"] = "; ".join(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))
    row["reasons"] = "; ".join(verdict(row))
    row["passed"] = not row["reasons"] and row["status"] == "solved"
    return row


def verdict(row):
    """The pass criteria of the module docstring that ``row`` violates (empty: passed)."""
    if row["status"] == "no solution found":
        return []
    if row["status"] != "solved" or row.get("rounding") is None:
        return [row["message"] or "not solved"]
    reasons = []
    if not row["lam_excess"] <= LAM_EXCESS_TOL:
        reasons.append(f"lam_excess {row['lam_excess']:.2e} > {LAM_EXCESS_TOL:g}")
    if not row["complementarity"] <= COMPLEMENTARITY_TOL:
        reasons.append(f"complementarity {row['complementarity']:.2e} > {COMPLEMENTARITY_TOL:g}")
    if not row["equilibrium_ratio"] <= EQUILIBRIUM_FACTOR:
        reasons.append(f"equilibrium {row['equilibrium']:.2e} > {EQUILIBRIUM_FACTOR:g} x max(rounding "
                       f"{row['rounding']:.2e}, {ROUNDING_FLOOR:g})")
    if row["uzawa_status"] == "converged" and not row["uzawa_difference"] <= AGREEMENT_TOL:
        reasons.append(f"differs from Uzawa by {row['uzawa_difference']:.2e} > {AGREEMENT_TOL:g}")
    return reasons


def g_a_kind(text):
    if text == "manufactured" or "x" in text:
        return "varying"
    value = float(text)
    return "penetration" if value < 0 else "gap" if value > 0 else "zero"
