"""The DG energy norm |||.|||_h of Section 3 and element-wise integrals on the skeleton."""

import ngsolve as ngs

from .forms import edge_length, jump_inner
from .meshes import facet_indicator
from .problem import strain, stress

__all__ = ["energy_norm", "energy_norm_squared_parts", "difference"]


def energy_norm_squared_parts(problem, mesh, w, element_wise=False):
    """(sum_T |w|_T^2, sum_{e in E_h^o} h_e^-1 ||[w]||_e^2) for a DG function ``w`` (Section 3).

    With ``element_wise`` both are numpy arrays over elements (edge terms of interior edges split
    half-half between the two neighbours, Dirichlet edges to their element).
    """
    n = ngs.specialcf.normal(2)
    h_e = edge_length(mesh)
    on_dirichlet = facet_indicator(mesh, problem.dirichlet)
    jw = w - w.Other()
    bonus = max(2 * _order(w.space) + 2 - 5, 0)  # quadrature order 2p + 2 (Integrate's default is 5)
    boundary = ngs.dx(element_boundary=True, bonus_intorder=bonus)
    volume = ngs.Integrate(ngs.InnerProduct(stress(problem, strain(w)), strain(w)) * ngs.dx(bonus_intorder=bonus),
                           mesh, element_wise=element_wise)
    interior = ngs.Integrate(0.5 * jump_inner(jw, jw, n) / h_e * boundary, mesh, element_wise=element_wise)
    dirichlet = ngs.Integrate(on_dirichlet * jump_inner(w, w, n) / h_e * boundary, mesh, element_wise=element_wise)
    if element_wise:
        return volume.NumPy().copy(), interior.NumPy() + dirichlet.NumPy()
    return volume, interior + dirichlet


def difference(u, w, extra_order=2):
    """u - w as a GridFunction on u's mesh.

    ``w``: a GridFunction on the same mesh (the difference lives in the larger of the two DG
    spaces, exactly) or a CoefficientFunction (interpolated elementwise in degree p + extra_order).
    """
    space_u = u.space
    if isinstance(w, ngs.GridFunction):
        target = w.space if _order(w.space) >= _order(space_u) else space_u
    else:
        target = ngs.L2(u.space.mesh, order=_order(space_u) + extra_order) ** 2
    e = ngs.GridFunction(target)
    e.Set(u)
    other = ngs.GridFunction(target)
    other.Set(w)
    e.vec.data -= other.vec
    return e


def _order(space):
    return space.globalorder


def energy_norm(sol, w=None):
    """|||u_h|||_h of a Solution, or |||u_h - w|||_h (see :func:`difference` for ``w``).

    |||v|||_h^2 = sum_T int_T C eps(v):eps(v) dx + sum_{e in E_h^o} h_e^-1 ||[v]||_{0,e}^2
    (Section 3).
    """
    v = sol.u if w is None else difference(sol.u, w)
    volume, jumps = energy_norm_squared_parts(sol.problem, sol.mesh, v)
    return (volume + jumps) ** 0.5
