r"""The DG bilinear forms :math:`B_h^{(1..5)}` of Section 3 and the load functional, as one construction.

All five methods share the volume term and the consistency terms

.. math::

    B_h(u, v) = (\sigma_h(u), \varepsilon_h(v)) - s \langle [\![u]\!], \{\!\{\sigma_h(v)\}\!\} \rangle
    - \langle [\![v]\!], \{\!\{\sigma_h(u)\}\!\} \rangle + \text{stabilisation},

with :math:`s = +1` except NIPG (:math:`s = -1`), and differ only in the stabilisation: the edge penalty
:math:`\eta\, p^2 / h_e\, [\![u]\!] : [\![v]\!]` or the local liftings
:math:`\sum_e \eta\, (C r_e([\![u]\!]), r_e([\![v]\!]))` (:mod:`ngdgfric.dg.liftings`), and the global lifting
:math:`(C r_0([\![u]\!]), r_0([\![v]\!]))`; the rows are :data:`ngdgfric.METHODS`.  The material enters every
term from the element's own side (``Material`` of :mod:`ngdgfric.dg.material`): the averages
:math:`\{\!\{\sigma\}\!\}` are weighted by the stiffness of the two neighbours and the penalty is an
``EdgeCoefficient`` (harmonic means across material jumps).

Jumps are the symmetric tensor jumps of Section 2.1,
:math:`[\![v]\!] = \operatorname{sym}(v^+ \otimes n^+ + v^- \otimes n^-)`, on interior edges and
:math:`[\![v]\!] = \operatorname{sym}((v - u_D) \otimes n)` on Dirichlet edges
(:math:`\mathcal{E}_h^o = \mathcal{E}_h^i \cup \mathcal{E}_h^D`; the paper has :math:`u_D = 0`; a prescribed
displacement moves its part to the right-hand side, ``load_terms``), and
:math:`[\![v]\!] = \operatorname{sym}((v \cdot n)\, n \otimes n)` on symmetry sides (:math:`u \cdot n = 0`,
tangential part free); the averages are :math:`\{\!\{\sigma\}\!\} = (\sigma^+ + \sigma^-)/2` and
:math:`\{\!\{\sigma\}\!\} = \sigma` on the boundary.  For :math:`p = 1` the edge penalty is the paper's
:math:`\eta\, h_e^{-1}`; for :math:`p > 1` it carries the usual factor :math:`p_e^2`, which keeps the coercivity
threshold of :math:`\eta` independent of :math:`h` and :math:`p` up to a constant.  With a variable order per
element (hp), :math:`p_e = \max(p_{T^+}, p_{T^-})` on interior edges (the inverse trace inequality of the
higher-order neighbour decides coercivity) and :math:`p_e = p_T` on boundary edges.

The length in the penalty (``penalty_length``) is :math:`h_e = \min(|e|, 2 h_{T^+}, 2 h_{T^-})`, with
:math:`h_T = 2 |T| / |e|` the height of :math:`T` over :math:`e`: the paper's :math:`|e|` on the meshes of
Section 6 and the neighbours' heights on thin triangles.  The inverse trace inequality
:math:`\|v\|_e^2 \le \frac{(p+1)(p+2)}{2} \frac{|e|}{|T|} \|v\|_T^2` (Warburton & Hesthaven 2003) scales with
:math:`1 / h_T`, so :math:`\eta p^2 / |e|` is too weak on the long edges of a thin triangle (:math:`B_h` loses
coercivity; ``tests/test_forms.py``).  With :math:`A, B` the angles of :math:`T` at the ends of :math:`e`,
:math:`2 h_T = 2 |e| / (\cot A + \cot B)`, so :math:`h_e = |e|` wherever :math:`\cot A + \cot B \le 2`: on the
structured meshes of Section 6 (the diagonals, :math:`2 h_T = |e|`, are the edges on which the SIPG thresholds of
:mod:`ngdgfric.dg.methods` were measured; the legs have :math:`2 h_T = 2 |e|`) and on equilateral triangles.

The builders of the terms (``dg_terms``, ``support_terms``, ``load_terms``, ``dirichlet_load_terms``, and
``lifting_terms`` of :mod:`ngdgfric.dg.liftings`) read the data of one mesh, the material, the method, :math:`\eta`,
:math:`p` and :math:`h_e`, from one ``FormsContext``, which ``Discretization`` builds once per mesh.
"""

from dataclasses import dataclass

import ngsolve as ngs

from ..problem import coefficient, is_number, pattern, strain, stress
from .material import EdgeCoefficient

__all__ = ["FormsContext", "edge_length", "penalty_length", "element_areas", "edge_penalty", "edge_order",
           "dg_terms", "load_terms", "jump_inner", "normal_part", "has_dirichlet_data", "support_terms",
           "dirichlet_load_terms", "SYMMETRY_WEIGHT"]


@dataclass(frozen=True, eq=False)
class FormsContext:
    r"""The data every builder of :math:`B_h` (Section 3) and of the load functional of (3.1) reads, on one mesh.

    The builders (``dg_terms``, ``support_terms``, ``load_terms``, ``dirichlet_load_terms`` and ``lifting_terms``
    of :mod:`ngdgfric.dg.liftings`) take it as their first argument, followed only by what is their own: the trial
    and test functions, a boundary part and its sides, the space of the liftings.  ``Discretization`` builds one
    per mesh (its attribute ``forms``) from its own attributes of the same names, so its matrix, its load vector
    and the terms that :mod:`ngdgfric.forces` takes apart are built from the same data.  A context is read, never
    changed: a variant (another penalty length, say) is ``dataclasses.replace(context, h_penalty=...)``.  Two
    contexts are equal only if they are the same object (``eq=False``: the fields are NGSolve objects).

    ``problem``: the ``ContactProblem`` with its data made CoefficientFunctions on ``mesh``
    (``ContactProblem.on``): the volume force :math:`f` and the traction :math:`g` of the load functional, the
    prescribed displacement :math:`u_D` on :math:`\Gamma_D` and the sides of each boundary part (``where``,
    ``sides``).

    ``mesh``: the ``ngsolve.Mesh`` of :math:`V_h`.

    ``material``: the ``Material`` of :mod:`ngdgfric.dg.material`: the Lame parameters of the element integrated
    over (``own``) and of its neighbour across an interior edge (``neighbour``), and the stiffness-weighted
    average :math:`\{\!\{\sigma\}\!\}` (``average``).

    ``method``: the method's row of :data:`ngdgfric.METHODS` (a ``Method``): the sign :math:`s` of the
    consistency term (``symmetry``), the stabilisation (``penalty``: ``"edge"`` for
    :math:`\eta\, p_e^2 / h_e\, [\![u]\!] : [\![v]\!]`, ``"lift"`` for
    :math:`\eta \sum_e (C r_e([\![u]\!]), r_e([\![v]\!]))`), the global lifting :math:`(C r_0, r_0)`
    (``global_lift``) and whether :math:`V_h` is continuous (``conforming``: no terms on interior edges).

    ``penalty``: :math:`\eta` as an ``EdgeCoefficient`` of :mod:`ngdgfric.dg.material` (``penalty`` of
    :mod:`ngdgfric.dg.methods`), ``interior`` on interior edges and ``boundary`` on boundary edges: a given
    :math:`\eta` on every edge, or the method's default, for the edge penalty on a varying material the harmonic
    mean of the two neighbours' defaults on interior edges; the lifting methods' :math:`\eta` is
    ``penalty.boundary``.

    ``p``: the degree in the edge penalty, the number :math:`p` or the degrees :math:`p_T` as a piecewise constant
    GridFunction (variable order; ``edge_order`` makes :math:`p_e = \max(p_{T^+}, p_{T^-})` of it on interior
    edges).

    ``h_penalty``: the length :math:`h_e` of the edge penalty as an ``EdgeCoefficient``, ``penalty_length``
    (:math:`\min(|e|, 2 h_{T^+}, 2 h_{T^-})`, module docstring) unless a caller replaces it.
    """

    problem: object
    mesh: object
    material: object
    method: object
    penalty: object
    p: object
    h_penalty: object


def jump_inner(a, b, n):
    """[a]:[b] for symmetric tensor jumps [a] = sym(a (x) n), [b] = sym(b (x) n) with |n| = 1.

    sym(a (x) n) : sym(b (x) n) = (a.b + (a.n)(b.n)) / 2; ``a``, ``b`` are the vector jumps
    v+ - v- (interior edges, n = n+) or v (Dirichlet edges).
    """
    return 0.5 * (a * b + (a * n) * (b * n))


def element_areas(mesh):
    """|T| of every element as an order-0 L2 GridFunction."""
    area = ngs.GridFunction(ngs.L2(mesh, order=0))
    area.vec.FV().NumPy()[:] = ngs.Integrate(ngs.CF(1) * ngs.dx, mesh, element_wise=True).NumPy()
    return area


def edge_length(mesh, area=None):
    """CoefficientFunction equal to h_e = |e| on every edge of a straight-sided triangle mesh.

    On a facet, NGSolve's ``specialcf.mesh_size`` is |det J_T| / |e| = 2 |T| / |e|, so
    |e| = 2 |T| / mesh_size with the element area |T| (``area``: :func:`element_areas`).
    """
    return 2 * (element_areas(mesh) if area is None else area) / ngs.specialcf.mesh_size


def _smaller(a, b):
    return ngs.IfPos(a - b, b, a)


def penalty_length(mesh):
    """The ``EdgeCoefficient`` h_e = min(|e|, 2 h_T+, 2 h_T-) of the penalty (module
    docstring); on boundary edges min(|e|, 2 h_T).  ``specialcf.mesh_size`` on a facet is the height h_T of
    the element integrated over; the neighbour's is 2 |T-| / |e|.  Compiled (``Compile()``: one fused
    expression): uncompiled, the two IfPos made SIPG's skeleton assembly twice as slow (0.21 s against
    0.11 s for |e| at 49k DOFs, P1), compiled 0.13 s."""
    area = element_areas(mesh)
    length = edge_length(mesh, area)
    own = _smaller(length, 2 * ngs.specialcf.mesh_size)
    return EdgeCoefficient(_smaller(own, 4 * area.Other() / length).Compile(), own.Compile(),
                           "min(|e|, 2 h_T+, 2 h_T-)")


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


def dg_terms(context, u, v):
    """The integrals of B_h(u, v) for the edge-penalty part of ``context.method`` (Section 3).

    Returns a list of symbolic integrals (one integrator each: NGSolve assembles separate
    skeleton integrators several times faster than their sum).  Lifting terms are added by the
    caller from :mod:`ngdgfric.dg.liftings`.  ``context``: the :class:`FormsContext` (data, material, method, eta,
    p and h_e); ``u``, ``v`` are trial and test functions (or any vector proxies) of a DG space with
    ``dgjumps=True`` (or of H^1 for the conforming baseline: no terms on interior edges).

    On the symmetry sides the boundary terms act on the normal component only (Nitsche's method for
    u . n = 0 with a free tangential component): [u] = sym((u . n) n (x) n), {sigma(v)} . [u] = (u . n)
    (sigma(v) n . n), and [u]:[v] = (u . n)(v . n).
    """
    problem, material, mesh, method = context.problem, context.material, context.mesh, context.method
    s = method.symmetry
    n = ngs.specialcf.normal(2)
    interior = ngs.dx(skeleton=True)
    ju, jv = u - u.Other(), v - v.Other()
    own, other = material.own, material.neighbour
    avg_sn = lambda w: material.average(stress(own, strain(w)) * n, stress(other, strain(w.Other())) * n)  # noqa: E731
    terms = [ngs.InnerProduct(stress(own, strain(u)), strain(v)) * ngs.dx]
    if not method.conforming:  # continuous u, v: every term on interior edges vanishes
        terms += [-s * ju * avg_sn(v) * interior, -jv * avg_sn(u) * interior]
    found = set(mesh.GetBoundaries())
    parts = [support_terms(context, u, v, part)
             for part in ("dirichlet", "symmetry") if part == "dirichlet" or found & set(problem.sides(part))]
    terms += [term for consistency, _ in parts for term in consistency]
    if method.penalty == "edge":
        if not method.conforming:
            weight = edge_penalty(context.penalty.interior, edge_order(context.p), context.h_penalty.interior)
            terms.append(weight * jump_inner(ju, jv, n) * interior)
        terms += [penalised for _, penalised in parts]
    return terms


def support_terms(context, u, v, part, sides=None):
    """The terms of B_h(u, v) on the edges of a supported part ("dirichlet" or "symmetry"; ``sides``: only these
    of its sides) as (consistency terms, penalty term or None), with the data of ``context``
    (:class:`FormsContext`): with the parts of u, v the part's jumps see, u, v on Gamma_D, (u . n) n, (v . n) n on
    symmetry sides (there with the penalty weight SYMMETRY_WEIGHT)."""
    method = context.method
    n = ngs.specialcf.normal(2)
    s, own = method.symmetry, context.material.own
    pu, pv, weight = (u, v, 1.0) if part == "dirichlet" else (normal_part(u, n), normal_part(v, n), SYMMETRY_WEIGHT)
    boundary = ngs.ds(skeleton=True, definedon=context.mesh.Boundaries(context.problem.where(part) if sides is None
                                                                        else pattern(sides)))
    consistency = [-s * pu * (stress(own, strain(v)) * n) * boundary, -pv * (stress(own, strain(u)) * n) * boundary]
    if method.penalty != "edge":
        return consistency, None
    eta_e = edge_penalty(context.penalty.boundary, context.p, context.h_penalty.boundary)
    return consistency, weight * eta_e * jump_inner(pu, pv, n) * boundary


# the weight of a symmetry side's jump terms in the penalty and the energy norm: half of an interior edge's
# in the body mirrored at that side (its jump u - (mirror image of u) is 2 (u . n) n, jump_inner of it 4 times
# that of (u . n) n, and the edge belongs to two halves), so that half a symmetric scene is exactly the
# restriction of the whole (tests/test_scenes.py); the consistency terms and the liftings need no weight
SYMMETRY_WEIGHT = 2.0


def normal_part(w, n):
    """(w . n) n: what a symmetry side's jump sees of w."""
    return (w * n) * n


def has_dirichlet_data(problem):
    """Whether u_D is not the constant zero (then B_h's boundary terms put u_D on the right-hand side)."""
    value = problem.u_D
    return not (isinstance(value, (tuple, list)) and all(is_number(c) and c == 0 for c in value))


def load_terms(context, v):
    """The right-hand side of (3.1) with the data of ``context`` (:class:`FormsContext`): (f, v) of (1.4), the
    traction g on Gamma_F, and, for a prescribed displacement u_D on Gamma_D, the part of B_h's Dirichlet terms that
    u_D carries (B_h with [u] = u - u_D on Gamma_D): -s <u_D, sigma_h(v) n> + eta p^2 / h_e [u_D]:[v] (the lifting
    terms' part comes from :func:`ngdgfric.dg.liftings.lifting_terms`)."""
    problem, mesh = context.problem, context.mesh
    f, g = coefficient(problem.f), coefficient(problem.g)
    terms = [f * v * ngs.dx]
    if any(name in mesh.GetBoundaries() for name in problem.sides("traction")):
        terms.append(g * v * ngs.ds(skeleton=True, definedon=mesh.Boundaries(problem.where("traction"))))
    if has_dirichlet_data(problem):
        terms += dirichlet_load_terms(context, v)
    return terms


def dirichlet_load_terms(context, v, sides=None):
    """The part of B_h's Dirichlet terms that u_D carries to the right-hand side, on Gamma_D (``sides``: only these
    of its sides), with the data of ``context`` (:class:`FormsContext`): -s <u_D, sigma_h(v) n> + eta p^2 / h_e
    [u_D]:[v] (edge-penalty methods)."""
    method = context.method
    n = ngs.specialcf.normal(2)
    u_D = coefficient(context.problem.u_D)
    boundary = ngs.ds(skeleton=True, definedon=context.mesh.Boundaries(
        context.problem.where("dirichlet") if sides is None else pattern(sides)))
    terms = [-method.symmetry * u_D * (stress(context.material.own, strain(v)) * n) * boundary]
    if method.penalty == "edge":
        eta_e = edge_penalty(context.penalty.boundary, context.p, context.h_penalty.boundary)
        terms.append(eta_e * jump_inner(u_D, v, n) * boundary)
    return terms
