"""The DG bilinear forms B_h^(1..5) of Section 3 and the load functional, as one construction.

All five methods share the volume term and the consistency terms

    B_h(u, v) = (sigma_h(u), eps_h(v)) - s <[u], {sigma_h(v)}> - <[v], {sigma_h(u)}> + stabilisation,

with s = +1 except NIPG (s = -1), and differ only in the stabilisation:

    method   s    penalty on E_h^o                             global lifting
    sipg    +1    eta p^2 / h_e [u]:[v]                         -
    nipg    -1    eta p^2 / h_e [u]:[v]                         -
    bassi   +1    sum_e eta (C r_e[u], r_e[v])                 -
    brezzi  +1    sum_e eta (C r_e[u], r_e[v])                 (C r_0[u], r_0[v])
    ldg     +1    eta p^2 / h_e [u]:[v]                         (C r_0[u], r_0[v])

Jumps are the symmetric tensor jumps of Section 2.1, [v] = sym(v+ (x) n+ + v- (x) n-), on
interior edges and [v] = sym(v (x) n) on Dirichlet edges (E_h^o = E_h^i u E_h^D); the
averages are {sigma} = (sigma+ + sigma-)/2 and {sigma} = sigma on the boundary.  For p = 1 the
edge penalty is the paper's eta h_e^-1; for p > 1 it carries the usual factor p_e^2, which keeps
the coercivity threshold of eta independent of h and p up to a constant.  With a variable order
per element (hp), p_e = max(p_T+, p_T-) on interior edges (the inverse trace inequality of the
higher-order neighbour decides coercivity) and p_e = p_T on boundary edges.
"""

import warnings
from dataclasses import dataclass

import ngsolve as ngs

from .problem import strain, stress

__all__ = ["Method", "METHODS", "get_method", "default_eta", "edge_length",
           "edge_penalty", "edge_order", "jump_penalty", "dg_terms", "load_terms", "jump_inner", "PenaltyWarning",
           "coercivity_threshold", "check_penalty", "SIPG_THRESHOLD"]


@dataclass(frozen=True)
class Method:
    """One row of the table in the module docstring."""

    name: str
    symmetry: int        # s in -s <[u], {sigma(v)}>
    penalty: str         # "edge": eta p^2/h_e [u]:[v];  "lift": sum_e eta (C r_e[u], r_e[v])
    global_lift: bool    # adds (C r_0[u], r_0[v])
    reference: str


METHODS = {
    "sipg": Method("sipg", +1, "edge", False, "B_h^(1), SIPG"),
    "nipg": Method("nipg", -1, "edge", False, "B_h^(2), NIPG"),
    "bassi": Method("bassi", +1, "lift", False, "B_h^(3), Bassi et al."),
    "brezzi": Method("brezzi", +1, "lift", True, "B_h^(4), Brezzi et al."),
    "ldg": Method("ldg", +1, "edge", True, "B_h^(5), LDG"),
}


def get_method(name):
    """The :class:`Method` called ``name`` (case-insensitive); ValueError for an unknown name."""
    key = str(name).lower()
    if key not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {name!r}")
    return METHODS[key]


def default_eta(problem, method, order=1):
    """Default penalty: eta = 30 mu for the edge-penalty methods (Section 6).

    For SIPG it is raised to 1.5 times the measured coercivity threshold of
    :func:`coercivity_threshold` where 30 mu is not above it (nearly incompressible materials: the
    threshold grows like 2 mu + lam); both examples of the paper keep 30 mu.  For the lifting
    penalties eta is dimensionless (it multiplies (C r_e, r_e)): 6 for Bassi et al. (twice the
    coercivity threshold 3, the number of edges of a triangle), 1 for Brezzi et al. (any eta > 0
    is stable, the global lifting term adds stability).
    """
    if method.penalty == "lift":
        return 6.0 if not method.global_lift else 1.0
    threshold = coercivity_threshold(problem, method, order)
    if isinstance(threshold, (int, float)) and 30 * problem.mu <= threshold:  # E a CoefficientFunction: 30 mu
        return 1.5 * threshold
    return 30 * problem.mu


def jump_penalty(problem, method, eta, order, h_e):
    """The weight of ||[u]||_e^2 in the estimator term eta_3 and in coercivity checks.

    Edge-penalty methods: their eta p^2 / h_e.  Lifting methods: (C r_e, r_e) ~ 2 mu / h_e ||[u]||^2,
    so eta multiplies 2 mu p^2 / h_e.  ``order`` as in :func:`edge_penalty`.
    """
    if method.penalty == "lift":
        return edge_penalty(2 * problem.mu * eta, order, h_e)
    return edge_penalty(eta, order, h_e)


class PenaltyWarning(UserWarning):
    """The penalty parameter is at or below the method's coercivity threshold."""


SIPG_THRESHOLD = {1: 4.0, 2: 2.2, 3: 1.75, 4: 1.55}
"""Smallest coercive SIPG penalty as eta / (2 mu + lam), per order (p > 4: the p = 4 value).

Measured by ``scripts/stability.py`` (results/stability.md): the smallest eigenvalue of
B_h(v, v) / |||v|||_h^2 changes sign at eta / (2 mu + lam) = 3.3-4.0 (p = 1), 1.85-2.15 (p = 2),
1.5-1.74 (p = 3), 1.35-1.52 (p = 4) for nu = 0 ... 0.49 on the structured meshes of Examples
6.1 and 6.2, independently of h; the table takes the largest, rounded up."""


def coercivity_threshold(problem, method, order):
    """The smallest stable eta of ``method`` for degree ``order`` (None: any eta > 0 is stable).

    SIPG: :data:`SIPG_THRESHOLD` times 2 mu + lam (measured; the theory gives only "large
    enough").  Bassi et al.: eta > 3, the number of edges of a triangle (Arnold, Brezzi,
    Cockburn, Marini 2002, for liftings into a space containing eps_h(V_h)); sufficient, the
    measured threshold is lower.  NIPG, Brezzi et al., LDG: any eta > 0.
    """
    if method.name == "bassi":
        return 3.0
    if method.name == "sipg":
        return SIPG_THRESHOLD[min(int(order), max(SIPG_THRESHOLD))] * (2 * problem.mu + problem.lam)
    return None


def check_penalty(problem, method, eta, order, action="warn"):
    """Warn (``action="warn"``), raise ValueError (``"raise"``) or do nothing (``"ignore"``) when
    eta is at or below :func:`coercivity_threshold`."""
    if action not in ("warn", "raise", "ignore"):
        raise ValueError(f"penalty_check must be 'warn', 'raise' or 'ignore', got {action!r}")
    threshold = coercivity_threshold(problem, method, order)
    if action == "ignore" or threshold is None or not isinstance(eta, (int, float)) or eta > threshold:
        return
    message = (f"eta = {eta:g} is at or below the coercivity threshold {threshold:g} of {method.name} "
               f"for order {order}: B_h may not be coercive and the solution may be meaningless")
    if action == "raise":
        raise ValueError(message)
    warnings.warn(message, PenaltyWarning, stacklevel=3)


def jump_inner(a, b, n):
    """[a]:[b] for symmetric tensor jumps [a] = sym(a (x) n), [b] = sym(b (x) n) with |n| = 1.

    sym(a (x) n) : sym(b (x) n) = (a.b + (a.n)(b.n)) / 2; ``a``, ``b`` are the vector jumps
    v+ - v- (interior edges, n = n+) or v (Dirichlet edges).
    """
    return 0.5 * (a * b + (a * n) * (b * n))


def edge_length(mesh):
    """CoefficientFunction equal to h_e = |e| on every edge of a straight-sided triangle mesh.

    On a facet, NGSolve's ``specialcf.mesh_size`` is |det J_T| / |e| = 2 |T| / |e|, so
    |e| = 2 |T| / mesh_size with the element area |T| stored in an order-0 L2 GridFunction.
    """
    area = ngs.GridFunction(ngs.L2(mesh, order=0))
    area.vec.FV().NumPy()[:] = ngs.Integrate(ngs.CF(1) * ngs.dx, mesh, element_wise=True).NumPy()
    return 2 * area / ngs.specialcf.mesh_size


def edge_penalty(eta, order, h_e):
    """The edge penalty weight eta p^2 / h_e (eta / h_e for p = 1, Section 3).

    ``order``: p (a number) or a CoefficientFunction p_e (see :func:`edge_order`).
    """
    return eta * order * order / h_e


def edge_order(order):
    """p_e on interior edges: ``order`` itself if it is a number, max(p_T+, p_T-) for an element
    order CoefficientFunction (a piecewise constant GridFunction)."""
    if not isinstance(order, ngs.CoefficientFunction):
        return order
    return ngs.IfPos(order - order.Other(), order, order.Other())


def _stress_normal(problem, w, n):
    return stress(problem, strain(w)) * n


def dg_terms(problem, mesh, u, v, method, eta, order, h_e=None):
    """The integrals of B_h(u, v) for the edge-penalty part of ``method`` (Section 3).

    Returns a list of symbolic integrals (one integrator each: NGSolve assembles separate
    skeleton integrators several times faster than their sum).  Lifting terms are added by the
    caller from :mod:`ngdgfric.liftings`.  ``u``, ``v`` are trial and test functions (or any
    vector proxies) of a DG space with ``dgjumps=True``; ``order``: p, or the element order
    GridFunction of a variable-order space.
    """
    s = method.symmetry
    n = ngs.specialcf.normal(2)
    dirichlet = mesh.Boundaries(problem.dirichlet)
    interior = ngs.dx(skeleton=True)
    boundary = ngs.ds(skeleton=True, definedon=dirichlet)
    ju, jv = u - u.Other(), v - v.Other()
    avg_sn = lambda w: 0.5 * (_stress_normal(problem, w, n) + _stress_normal(problem, w.Other(), n))  # noqa: E731
    terms = [
        ngs.InnerProduct(stress(problem, strain(u)), strain(v)) * ngs.dx,
        -s * ju * avg_sn(v) * interior,
        -jv * avg_sn(u) * interior,
        -s * u * _stress_normal(problem, v, n) * boundary,
        -v * _stress_normal(problem, u, n) * boundary,
    ]
    if method.penalty == "edge":
        if h_e is None:
            h_e = edge_length(mesh)
        terms += [edge_penalty(eta, edge_order(order), h_e) * jump_inner(ju, jv, n) * interior,
                  edge_penalty(eta, order, h_e) * jump_inner(u, v, n) * boundary]
    return terms


def load_terms(problem, mesh, v):
    """(f, v) of (1.4): body force on Omega and traction g on Gamma_F."""
    f = ngs.CF(tuple(problem.f)) if not isinstance(problem.f, ngs.CoefficientFunction) else problem.f
    g = ngs.CF(tuple(problem.g)) if not isinstance(problem.g, ngs.CoefficientFunction) else problem.g
    terms = [f * v * ngs.dx]
    if problem.traction in mesh.GetBoundaries():
        terms.append(g * v * ngs.ds(skeleton=True, definedon=mesh.Boundaries(problem.traction)))
    return terms
