r"""The DG energy norm of Section 3, the norm every error of the package is measured in:

.. math::

    \|v\|_h^2 = \sum_T \int_T C \varepsilon(v) : \varepsilon(v) \, dx
    + \sum_{e \in \mathcal{E}_h^o} h_e^{-1} \|[\![v]\!]\|_{0,e}^2,

:math:`h_e = |e|`, :math:`[\![v]\!]` the symmetric tensor jump (``jump_inner`` of :mod:`ngdgfric.dg.forms`), on
:math:`\Gamma_D` the jump :math:`v` (or :math:`v - u_D` for the solution itself), on symmetry sides that of the
normal part :math:`(v \cdot n)\, n`.  :func:`~ngdgfric.energy_norm` evaluates it for a solution (against a
GridFunction or an exact solution), ``energy_norm_squared_parts`` its two parts, ``energy_matrix`` its Gram matrix
on a DG space (:math:`v^T G v = \|v\|_h^2`), all from the same densities (``_strain_energy``,
``_support_jumps``).
"""

import ngsolve as ngs
import numpy as np

from .checks import check_solution, shown
from .dg.forms import SYMMETRY_WEIGHT, edge_length, has_dirichlet_data, jump_inner, normal_part
from .meshes import facet_indicator, nested, triangle_corners
from .problem import coefficient, strain, strain_of, stress
from .transfer import interpolate

__all__ = ["energy_norm", "energy_norm_squared_parts", "energy_matrix", "difference", "problem_of", "check_derivative",
           "EXACT_ORDER"]

EXACT_ORDER = 16  # the least quadrature degree of errors against an exact solution (energy_norm)


def _strain_energy(problem, a, b):
    """C eps(a) : eps(b), the volume density of the inner product of |||.|||_h."""
    return ngs.InnerProduct(stress(problem, strain(a)), strain(b))


def _support_jumps(problem, mesh, a, b, n):
    """[a] : [b] on the supported boundary edges: the jumps a, b on Gamma_D, their normal parts on symmetry sides
    (weight :data:`~ngdgfric.dg.forms.SYMMETRY_WEIGHT`), zero elsewhere."""
    # IfPos, not indicator times jump: a NaN of a (x log x at x = 0) on an edge where it does not enter stays out
    return ngs.IfPos(facet_indicator(mesh, problem.where("dirichlet")) - 0.5, jump_inner(a, b, n), 0) + \
        SYMMETRY_WEIGHT * ngs.IfPos(facet_indicator(mesh, problem.where("symmetry")) - 0.5,
                                    jump_inner(normal_part(a, n), normal_part(b, n), n), 0)


def energy_matrix(problem, mesh, V):
    """The Gram matrix G of |||.|||_h on the DG space ``V`` (an NGSolve sparse matrix; v^T G v = |||v|||_h^2 for
    the coefficients v of a function of V with the jump v on Gamma_D, as ``energy_norm_squared_parts``)."""
    problem = problem.on(mesh)
    u, v = V.TnT()
    n, h_e = ngs.specialcf.normal(2), edge_length(mesh)
    bonus = max(2 * _order(V) + 2 - 5, 0)
    form = ngs.BilinearForm(V)
    form += _strain_energy(problem, u, v) * ngs.dx(bonus_intorder=bonus)
    form += jump_inner(u - u.Other(), v - v.Other(), n) / h_e * ngs.dx(skeleton=True, bonus_intorder=bonus)
    form += _support_jumps(problem, mesh, u, v, n) / h_e * ngs.ds(skeleton=True, bonus_intorder=bonus)
    form.Assemble()
    return form.mat


def energy_norm_squared_parts(problem, mesh, w, element_wise=False, dirichlet_value=None):
    """(sum_T |w|_T^2, sum_{e in E_h^o} h_e^-1 ||[w]||_e^2) for a DG function ``w`` (Section 3).

    With ``element_wise`` both are numpy arrays over elements (edge terms of interior edges split
    half-half between the two neighbours, Dirichlet edges to their element).  ``dirichlet_value``: [w] = w -
    dirichlet_value on Gamma_D (u_D for the jumps u_h has and the exact u has not), None: w.
    """
    bonus = max(2 * _order(w.space) + 2 - 5, 0)  # quadrature order 2p + 2 (Integrate's default is 5)
    volume = ngs.Integrate(_strain_energy(problem, w, w) * ngs.dx(bonus_intorder=bonus), mesh,
                           element_wise=element_wise)
    jumps = _jump_part(problem, mesh, w, element_wise, dirichlet_value)
    return (volume.NumPy().copy(), jumps) if element_wise else (volume, jumps)


def _jump_part(problem, mesh, w, element_wise=False, dirichlet_value=None):
    """sum_{e in E_h^o} h_e^-1 ||[w]||_e^2 for a DG function ``w``, with [w] = w - ``dirichlet_value`` on the
    Dirichlet edges (a 2-vector CoefficientFunction; None: the jump [w] = w of Section 3) and the jump of the normal
    part (w . n) n on symmetry sides; a numpy array over elements with ``element_wise`` (interior edges split
    half-half, boundary edges to their element)."""
    n = ngs.specialcf.normal(2)
    h_e = edge_length(mesh)
    jw, off = w - w.Other(), w if dirichlet_value is None else w - dirichlet_value
    boundary = ngs.dx(element_boundary=True, bonus_intorder=max(2 * _order(w.space) + 2 - 5, 0))
    interior = ngs.Integrate(0.5 * jump_inner(jw, jw, n) / h_e * boundary, mesh, element_wise=element_wise)
    dirichlet = ngs.Integrate(_support_jumps(problem, mesh, off, off, n) / h_e * boundary, mesh,
                              element_wise=element_wise)
    return interior.NumPy() + dirichlet.NumPy() if element_wise else interior + dirichlet


def difference(u, w, extra_order=2):
    """u - w as a GridFunction on u's mesh.

    ``w``: a GridFunction on the same mesh or on one that u's mesh refines (the difference lives in the larger of
    the two DG spaces, or L2 of the larger degree, exactly; ValueError where :func:`ngdgfric.meshes.nested` does
    not find u's mesh to refine w's: the jumps would be taken on the wrong edges, or w evaluated in the wrong
    element) or a CoefficientFunction (interpolated elementwise in degree p +
    extra_order).
    """
    space_u = u.space
    if isinstance(w, ngs.GridFunction):
        if not nested(w.space.mesh, space_u.mesh):
            raise ValueError(f"w is a GridFunction on a mesh ({w.space.mesh.ne} elements) that u_h's mesh "
                             f"({space_u.mesh.ne} elements) is not found to refine: some element of u_h's mesh does "
                             f"not lie in one element of w's as NGSolve's point search finds them (another mesh, a "
                             f"curved side whose refinement moved vertices onto the curve, or elements too small "
                             f"for the point search, below about 1e-5 of w's); interpolate w onto u_h's mesh, pass "
                             f"it as a CoefficientFunction, or measure against a Reference (ngdgfric.energy_error)")
        if w.space.mesh is space_u.mesh:
            target = w.space if _order(w.space) >= _order(space_u) else space_u
        else:  # w interpolated onto u's mesh (also when it is a copy: a Solution keeps its own copy of the mesh)
            target = ngs.L2(space_u.mesh, order=max(_order(w.space), _order(space_u))) ** 2
    else:
        target = ngs.L2(u.space.mesh, order=_order(space_u) + extra_order) ** 2
    e = ngs.GridFunction(target)
    interpolate(e, u)
    other = ngs.GridFunction(target)
    interpolate(other, w)
    e.vec.data -= other.vec
    return e


DERIVATIVE_SAMPLES = 64  # elements in which check_derivative compares a CoefficientFunction's derivatives
STEP = 1e-5  # the differences' step, relative to the element's size
AGREE = 1e-6  # the largest difference of the symbolic and the numerical derivative, relative to the largest of both


def check_derivative(w, mesh):
    """ValueError unless the symbolic derivative of the 2-vector CoefficientFunction ``w`` (what
    ``ngdgfric.problem.strain_of`` differentiates) is the derivative of its values: at one point inside each of up
    to :data:`DERIVATIVE_SAMPLES` elements of ``mesh``, each partial derivative agrees with the forward or the backward
    one-sided difference of second order (steps :data:`STEP` h_T; exact to about 1e-10 for smooth w, and one of the
    two is right on a kink of w through the point) to :data:`AGREE` of the largest derivative.  A CoefficientFunction
    built from a GridFunction fails: its symbolic derivative is zero."""
    corners = triangle_corners(mesh)
    chosen = corners[np.unique(np.linspace(0, len(corners) - 1, min(len(corners), DERIVATIVE_SAMPLES)).astype(int))]
    point = np.einsum("k,ekd->ed", [0.2113, 0.3277, 0.461], chosen)  # not a centroid: kinks along mesh lines miss it
    step = STEP * np.linalg.norm(chosen[:, 1] - chosen[:, 0], axis=1)[:, None]
    gradient = ngs.CF(tuple(w[i].Diff(z) for i in range(2) for z in (ngs.x, ngs.y)))
    symbolic = np.asarray(gradient(mesh(point[:, 0], point[:, 1]))).reshape(-1, 2, 2)

    def at(k, multiple):
        shifted = point + multiple * step * np.eye(2)[k]
        return np.asarray(w(mesh(shifted[:, 0], shifted[:, 1]))).reshape(-1, 2)

    worst = scale = 0.0
    for k in range(2):
        values = {m: at(k, m) for m in (-2, -1, 0, 1, 2)}
        sides = [(s * (4 * values[s] - values[2 * s] - 3 * values[0])) / (2 * step) for s in (1, -1)]
        worst = max(worst, np.max(np.minimum(*(np.abs(side - symbolic[:, :, k]) for side in sides))))
        scale = max(scale, np.abs(symbolic[:, :, k]).max(), *(np.abs(side).max() for side in sides))
    if worst > AGREE * scale:
        raise ValueError(f"w is a CoefficientFunction whose symbolic derivative is not the derivative of its values "
                         f"(they differ by {worst:.3g}, {worst / scale:.2g} of their size): one built from a "
                         f"GridFunction (symbolic differentiation sees a GridFunction as a constant)?  Pass the "
                         f"GridFunction itself, or measure against a Reference or another Solution "
                         f"(ngdgfric.energy_error)")


def _order(space):
    return space.globalorder


def problem_of(sol):
    """The problem with its data on the mesh: a Solution's discretisation's (data per part resolved), a
    :class:`Reference`'s own."""
    disc = getattr(sol, "discretization", None)
    return sol.problem if disc is None else disc.problem


def energy_norm(sol, w=None):
    r"""The DG energy norm of a solution, or of its difference to an exact solution (Section 3).

    .. math::

        \|v\|_h^2 = \sum_T \int_T C \epsilon(v) : \epsilon(v) \, dx
                    + \sum_{e \in \mathcal{E}_h^o} h_e^{-1} \|[v]\|_{0,e}^2,

    for :math:`v = u_h` or :math:`v = u_h - w`.  With a prescribed displacement :math:`u_D \ne 0`,
    :math:`\|u_h\|_h` takes :math:`[u_h] = u_h - u_D` on :math:`\Gamma_D` (the jump the solution has there;
    :math:`u_h` itself would add :math:`h^{-1} \|u_D\|^2`).

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve` (anything with ``problem``, ``mesh`` and ``u``).
    w : ngsolve.GridFunction, CoefficientFunction or None, optional
        Default ``None``: the norm of :math:`u_h`.  A GridFunction (see ``difference``), or a continuous
        CoefficientFunction of ``x, y`` (an exact solution): then :math:`\epsilon(w)` is its own derivative
        (``strain_of`` of :mod:`ngdgfric.problem`), :math:`C` is the problem's (the true material, also where a
        jump cuts elements), the volume integral uses a Gauss rule of degree :math:`\max(2 p + 4,` ``EXACT_ORDER``
        :math:`)` (a kink of :math:`w` inside an element is integrated, not interpolated), and
        :math:`[u_h - w] = [u_h]` on interior edges.

    Returns
    -------
    float
        :math:`\|u_h\|_h` or :math:`\|u_h - w\|_h`.

    Raises
    ------
    ValueError
        For a CoefficientFunction ``w`` whose symbolic derivative is not the derivative of its values (one built
        from a GridFunction, ``0.5 * sol.u``: symbolic differentiation sees a GridFunction as a constant;
        ``check_derivative``); pass the GridFunction itself.  For ``sol`` not a Solution or Reference, ``w`` not a
        displacement (a Solution: use :func:`ngdgfric.energy_error`; a number; a function with other than 2
        components), and a ``w`` or strain that is not finite where it enters (named with a point).

    See Also
    --------
    ngdgfric.energy_error : The error against a stored reference solution.

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
    >>> print(f"{ndf.energy_norm(sol):.2f}")
    23.11
    >>> print(f"{ndf.energy_norm(sol, sol.u):.2f}")
    0.00
    """
    check_solution(sol, "sol", reference=True)
    _check_w(w)
    problem = problem_of(sol)
    if w is None or isinstance(w, ngs.GridFunction):
        v = sol.u if w is None else difference(sol.u, w)
        # |||u_h|||_h takes [u_h] = u_h - u_D on Gamma_D: the jump the exact u has not
        shift = coefficient(problem.u_D) if w is None and has_dirichlet_data(problem) else None
        volume, jumps = energy_norm_squared_parts(problem, sol.mesh, v, dirichlet_value=shift)
        return (volume + jumps) ** 0.5
    problem, mesh, u = problem, sol.mesh, sol.u
    check_derivative(w, mesh)
    e = strain(u) - strain_of(w)
    order = max(2 * _order(u.space) + 4, EXACT_ORDER)
    volume = ngs.Integrate(ngs.InnerProduct(stress(problem, e), e), mesh, order=order)
    squared = volume + _jump_part(problem, mesh, u, dirichlet_value=w)
    if not np.isfinite(squared):
        _name_non_finite(problem, mesh, w, order)
    return squared**0.5


def _check_w(w):
    """ValueError naming ``w`` unless it is None, a 2-vector GridFunction or a 2-vector CoefficientFunction."""
    if w is None:
        return
    if hasattr(w, "problem") and hasattr(w, "u"):
        raise ValueError(f"w is a {type(w).__name__}, not a displacement: measure u_h against another Solution or a "
                         f"Reference with ngdgfric.energy_error(sol, w), or pass its GridFunction w.u")
    if not isinstance(w, ngs.CoefficientFunction):
        raise ValueError(f"w must be None, a GridFunction or a CoefficientFunction of x, y with 2 components (an "
                         f"exact displacement), got {shown(w)}")
    if w.dim != 2:
        kind = "GridFunction" if isinstance(w, ngs.GridFunction) else "CoefficientFunction"
        raise ValueError(f"w must be a displacement with 2 components, got a {kind} with {w.dim}")


def _name_non_finite(problem, mesh, w, order):
    """ValueError naming a point where the exact solution ``w`` or its strain is not finite: at the Gauss points of
    degree ``order`` of the elements (the volume integral) or of the Dirichlet and symmetry edges (the jumps there);
    edges of other sides, where w does not enter, are not looked at."""
    rules = [(ngs.VOL, {ngs.TRIG: ngs.IntegrationRule(ngs.TRIG, order)}, "inside the domain")]
    for part in ("dirichlet", "symmetry"):
        if problem.sides(part):
            rules.append((mesh.Boundaries(problem.where(part)), {ngs.SEGM: ngs.IntegrationRule(ngs.SEGM, order)},
                          f"on the {part} sides"))
    for where, rule, said in rules:
        points = mesh.MapToAllElements(rule, where)
        for what, cf in (("w", w), ("the strain of w", strain_of(w))):
            values = np.asarray(cf(points)).reshape(len(points), -1)
            bad = np.flatnonzero(~np.all(np.isfinite(values), axis=1))
            if bad.size:
                k = int(bad[0])
                at = (float(ngs.x(points[k])), float(ngs.y(points[k])))
                raise ValueError(f"{what} is not finite {said}: {tuple(map(float, values[k]))} at ({at[0]:.6g}, "
                                 f"{at[1]:.6g}) ({bad.size} of {len(points)} quadrature points); give an exact "
                                 f"solution with finite values there")
    raise ValueError("the error of u_h against w is not finite, though w and its strain are finite at the quadrature "
                     "points: the material or the mesh?")
