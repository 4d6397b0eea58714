"""Normal compliance and friction on Gamma_C: integrands, multiplier space, Gauss points.

In 2D the tangent space of Gamma_C is one-dimensional: with t = (-n_y, n_x) the multiplier of
Lemma 3.1 is lam_tau = l t with a scalar l, |lam_tau| = |l|, and

    g(lam_tau, v) = int_{Gamma_C} c_tau l (v . t) ds,     (3.4):  l (u . t) = |u . t|.

All contact integrals use the same (p+1)-point Gauss rule per edge: the discrete problem (3.1)
is the one with j_tau and j_n evaluated by this rule.  The multiplier l lives in a facet space
of degree p on Gamma_C; a degree-p polynomial is determined by its p+1 Gauss values, and the
Gauss-rule L2 projection onto it is interpolation at those points, so every pointwise relation
(|l| <= 1, l u_tau = |u_tau|, the projection P_[-1,1]) holds exactly at the Gauss points.
"""

import ngsolve as ngs
import numpy as np

__all__ = ["contact_rule", "contact_measure", "normal_tangent", "penetration", "compliance",
           "project_unit", "multiplier_space", "contact_points", "evaluate_on_contact"]


def contact_rule(order):
    """The (p+1)-point Gauss rule on edges (exact to degree 2p+1)."""
    return {ngs.SEGM: ngs.IntegrationRule(ngs.SEGM, 2 * order + 1)}


def contact_measure(problem, mesh, order):
    """ds on Gamma_C (skeleton form, as L2 spaces need) with the contact Gauss rule."""
    return ngs.ds(skeleton=True, definedon=mesh.Boundaries(problem.contact), intrules=contact_rule(order))


def normal_tangent():
    """Outward unit normal n and tangent t = (-n_y, n_x) on the boundary."""
    n = ngs.specialcf.normal(2)
    return n, ngs.CF((-n[1], n[0]))


def _cf(value):
    return value if isinstance(value, ngs.CoefficientFunction) else ngs.CF(value)


def penetration(problem, u):
    """u_n - g_a: positive where the body penetrates the foundation (1.8)."""
    n, _ = normal_tangent()
    return u * n - _cf(problem.g_a)


def compliance(problem, u):
    """Contact pressure c_n (u_n - g_a)_+^{m_n}, so that sigma_n(u) = -compliance (1.8)."""
    d = penetration(problem, u)
    power = d if problem.m_n == 1 else d ** problem.m_n
    return _cf(problem.c_n) * ngs.IfPos(d, power, 0)


def project_unit(z):
    """P_[-1,1](z), pointwise."""
    return ngs.IfPos(z - 1, 1, ngs.IfPos(-1 - z, -1, z))


def multiplier_space(problem, mesh, order):
    """Degree-p facet space on Gamma_C for the scalar multiplier l (lam_tau = l t)."""
    full = ngs.FacetFESpace(mesh, order=order)
    return ngs.Compress(full, active_dofs=full.GetDofs(mesh.Boundaries(problem.contact)))


def contact_points(problem, mesh, order):
    """The Gauss points of all edges of Gamma_C, mapped, in a fixed order (for evaluation)."""
    return mesh.MapToAllElements(contact_rule(order), mesh.Boundaries(problem.contact))


def evaluate_on_contact(cf, points, volume=True):
    """Values of ``cf`` at contact Gauss points; ``volume`` for volume (element) functions."""
    values = (ngs.BoundaryFromVolumeCF(cf) if volume else cf)(points)
    return np.asarray(values).reshape(len(points), -1).squeeze(axis=1) if cf.dim == 1 else np.asarray(values)
