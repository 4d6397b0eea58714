r"""Normal compliance and friction on :math:`\Gamma_C`: integrands, contact forms, multiplier, Gauss points, KKT
residuals.

In 2D the tangent space of :math:`\Gamma_C` is one-dimensional: with :math:`t = (-n_y, n_x)` the multiplier of
Lemma 3.1 is :math:`\lambda_\tau t` with a scalar function :math:`\lambda_\tau`,
:math:`|\lambda_\tau t| = |\lambda_\tau|`, and

.. math::

    g(\lambda_\tau, v) = \int_{\Gamma_C} c_\tau \lambda_\tau (v \cdot t) \, ds, \qquad
    \text{(3.4)}: \ \lambda_\tau (u \cdot t) = |u \cdot t|.

For :math:`m_t > 0` the friction bound :math:`c_\tau` is replaced by :math:`c_\tau (u_n - g_a)_+^{m_t}` (1.9), so
:math:`g` depends on :math:`u` too; where that bound vanishes (no contact) :math:`u_\tau` is free and
:math:`\lambda_\tau = \operatorname{sign}(u_\tau)` is one valid multiplier.  The residual of (3.3) (``residual``)
is written once for both: its friction term carries the bound at :math:`u` (:math:`c_\tau` itself for
:math:`m_t = 0`).  The fixed point on the bound solves problems with the bound frozen (``frozen_bound``).

All contact integrals use the same :math:`(p+1)`-point Gauss rule per edge: the discrete problem (3.1)
is the one with :math:`j_\tau` and :math:`j_n` evaluated by this rule.  The multiplier :math:`\lambda_\tau` lives in
a facet space of degree :math:`p` on :math:`\Gamma_C`; a degree-:math:`p` polynomial is determined by its
:math:`p+1` Gauss values, and the Gauss-rule :math:`L^2` projection onto it is interpolation at those points, so
every pointwise relation (:math:`|\lambda_\tau| \le 1`, :math:`\lambda_\tau u_\tau = |u_\tau|`, the projection
:math:`P_{[-1,1]}`) holds exactly at the Gauss points (:func:`ngdgfric.contact_state`,
:func:`ngdgfric.kkt_residuals`).
"""

import dataclasses

import ngsolve as ngs
import numpy as np

from .problem import PerSide, coefficient, exponents, strain, stress
from .threads import threads

__all__ = ["contact_rule", "contact_measure", "normal_tangent", "penetration", "positive_power", "compliance",
           "friction_bound", "project_unit", "compliance_form", "friction_matrix",
           "frozen_bound", "residual", "residual_terms", "multiplier_space", "contact_points", "contact_boundary",
           "evaluate_on_contact",
           "ContactGauss",
           "GaussValues", "contact_state", "transitions", "kkt_residuals", "rounding_residual"]


def contact_rule(order):
    """The (p+1)-point Gauss rule on edges (exact to degree 2p+1)."""
    return {ngs.SEGM: ngs.IntegrationRule(ngs.SEGM, 2 * order + 1)}


def contact_measure(problem, mesh, order):
    """ds on Gamma_C (skeleton form, as L2 spaces need) with the contact Gauss rule."""
    return ngs.ds(skeleton=True, definedon=mesh.Boundaries(problem.where("contact")), intrules=contact_rule(order))


def normal_tangent():
    """Outward unit normal n and tangent t = (-n_y, n_x) on the boundary."""
    n = ngs.specialcf.normal(2)
    return n, ngs.CF((-n[1], n[0]))


def penetration(problem, u):
    """u_n - g_a: positive where the body penetrates the foundation (1.8)."""
    n, _ = normal_tangent()
    return u * n - coefficient(problem.g_a)


def positive_power(d, m):
    """(d)_+^m (m != 0), written IfPos(d, d^m, 0) (IfPos(d, d, 0)^m gave NaN Jacobians)."""
    return ngs.IfPos(d, d if m == 1 else d**m, 0)


def _side_by_side(exponent, law):
    """law(m) for an exponent m given as a number; on a mesh where it is given per contact side
    (:class:`ngdgfric.problem.PerSide`) the sum of law(m_s) times the indicator of side s."""
    return exponent.combine(law) if isinstance(exponent, PerSide) else law(exponent)


def compliance(problem, u):
    """Contact pressure c_n (u_n - g_a)_+^{m_n}, so that sigma_n(u) = -compliance (1.8)."""
    d = penetration(problem, u)
    return coefficient(problem.c_n) * _side_by_side(problem.m_n, lambda m: positive_power(d, m))


def friction_bound(problem, u):
    """The friction bound c_tau (u_n - g_a)_+^{m_t} of (1.9) at u; c_tau itself for the reduced law m_t = 0
    (also on the contact sides with m_t = 0 when the sides have their own m_t)."""
    if max(exponents(problem.m_t)) == 0:
        return coefficient(problem.c_tau)
    d = penetration(problem, u)
    return coefficient(problem.c_tau) * _side_by_side(problem.m_t, lambda m: positive_power(d, m) if m > 0 else 1)


def project_unit(z):
    """P_[-1,1](z), pointwise."""
    return ngs.IfPos(z - 1, 1, ngs.IfPos(-1 - z, -1, z))


def compliance_form(problem, dS, u, v):
    """j_n(u, v) = int_{Gamma_C} c_n (u_n - g_a)_+^{m_n} v_n ds (Gauss rule ``dS``), a symbolic integral."""
    n, _ = normal_tangent()
    return compliance(problem, u) * (v * n) * dS


def friction_matrix(disc, bound):
    """The matrix of g(lam_tau, v) = int_{Gamma_C} bound lam_tau (v . t) ds (trial space ``disc.Q``, test
    space V_h) for a friction bound given as a number or a CoefficientFunction: c_tau (m_t = 0), or the
    bound at a fixed u."""
    _, t = normal_tangent()
    lam_tau, v = disc.Q.TrialFunction(), disc.V_plain.TestFunction()
    g = ngs.BilinearForm(trialspace=disc.Q, testspace=disc.V_plain)
    g += coefficient(bound) * lam_tau * (v * t) * disc.dS
    with threads(disc.V.ndof):
        g.Assemble()
    return g.mat


def frozen_bound(problem, u):
    """``problem`` with the reduced law (m_t = 0) and, as its friction coefficient, the bound
    c_tau (u_n - g_a)_+^{m_t} of (1.9) at (a copy of) the GridFunction ``u``: the problem of one step of
    the fixed point (:mod:`ngdgfric.solvers.fixed_point`).  Only c_tau and m_t differ, so a discretisation of
    ``problem`` serves it too."""
    u_frozen = ngs.GridFunction(u.space)
    u_frozen.vec.data = u.vec
    return dataclasses.replace(problem, c_tau=friction_bound(problem, u_frozen), m_t=0.0)


def residual_terms(disc, u, lam_tau):
    """The terms of the residual of (3.3) at the GridFunctions (u, lam_tau) of ``disc``, vectors on V_h:

        B_h(u, v),   j_n(u, v),   g(u; lam_tau, v) = int_{Gamma_C} c_tau (u_n - g_a)_+^{m_t} lam_tau v.t ds,
        -(f, v),

    the friction term with the bound at u (:func:`friction_bound`; c_tau itself for m_t = 0), assembled
    at that bound (:func:`friction_matrix`): one code path for m_t = 0 and m_t > 0."""
    trial, test = disc.V.TnT()
    compliance_part = ngs.BilinearForm(disc.V)
    compliance_part += compliance_form(disc.problem, disc.dS, trial, test)
    terms = [disc.F.CreateVector() for _ in range(4)]
    terms[0].data = disc.A * u.vec
    compliance_part.Apply(u.vec, terms[1])
    terms[2].data = friction_matrix(disc, friction_bound(disc.problem, u)) * lam_tau.vec
    terms[3].data = -disc.F
    return terms


def residual(disc, u, lam_tau):
    """The residual of (3.3) at (u, lam_tau): the sum of :func:`residual_terms`,
    B_h(u, v) + j_n(u, v) + g(u; lam_tau, v) - (f, v), a vector on V_h."""
    terms = residual_terms(disc, u, lam_tau)
    r = terms[0]
    for term in terms[1:]:
        r.data += term
    return r


def multiplier_space(problem, mesh, order):
    """Degree-p facet space on Gamma_C for the scalar multiplier lam_tau (the vector multiplier is lam_tau t)."""
    full = ngs.FacetFESpace(mesh, order=order)
    return ngs.Compress(full, active_dofs=full.GetDofs(mesh.Boundaries(problem.where("contact"))))


def contact_points(problem, mesh, order):
    """The Gauss points of all edges of Gamma_C, mapped, in a fixed order (for evaluation)."""
    return mesh.MapToAllElements(contact_rule(order), mesh.Boundaries(problem.where("contact")))


def contact_boundary(problem, mesh, part="contact"):
    """The edges of Gamma_C (or of another boundary ``part``) in the order of :func:`contact_points` (edge k holds
    the Gauss points k q ... (k + 1) q - 1): a list of (boundary element, the element of the mesh whose edge it
    is)."""
    sides = set(problem.sides(part))
    return [(el, mesh[el.edges[0]].elements[0]) for el in mesh.Elements(ngs.BND) if el.mat in sides]


def evaluate_on_contact(cf, points, volume=True):
    """Values of ``cf`` at contact Gauss points; ``volume`` for volume (element) functions."""
    values = (ngs.BoundaryFromVolumeCF(cf) if volume else cf)(points)
    return np.asarray(values).reshape(len(points), -1).squeeze(axis=1) if cf.dim == 1 else np.asarray(values)


class ContactGauss:
    """The Gauss points of Gamma_C edge by edge, and multiplier values <-> coefficients.

    points: mapped points (for evaluation); xy: (edges, q, 2) coordinates; ends: (edges, 2, 2)
    edge end points; dofs: (edges, q) multiplier dofs of each edge; sides: the name of each edge's contact side;
    q = p + 1.
    """

    def __init__(self, problem, mesh, order, Q):
        self.points = contact_points(problem, mesh, order)
        self.q = order + 1
        self.xy = np.column_stack([np.asarray(ngs.x(self.points)).ravel(),
                                   np.asarray(ngs.y(self.points)).ravel()]).reshape(-1, self.q, 2)
        edges = [el for el, _ in contact_boundary(problem, mesh)]
        ends = [[mesh[v].point for v in el.vertices] for el in edges]
        dofs = [list(Q.GetDofNrs(el)) for el in edges]
        self.sides = [el.mat for el in edges]
        self.ends = np.asarray(ends, dtype=float).reshape(-1, 2, 2)
        self.dofs = np.asarray(dofs, dtype=np.int64).reshape(-1, self.q)
        self.Q = Q
        # Vandermonde matrices: column k holds the values of every edge's k-th basis function
        probe = ngs.GridFunction(Q)
        self.vandermonde = np.empty((len(self.dofs), self.q, self.q))
        for k in range(self.q):
            probe.vec[:] = 0.0
            probe.vec.FV().NumPy()[self.dofs[:, k]] = 1.0
            self.vandermonde[:, :, k] = self.values(probe)

    def values(self, lam_tau):
        """Values of a multiplier GridFunction at the Gauss points, shape (edges, q)."""
        return np.asarray(lam_tau(self.points)).reshape(-1, self.q)

    def set_values(self, lam_tau, values):
        """Set the multiplier GridFunction to the degree-p polynomials with these Gauss values."""
        coefficients = np.linalg.solve(self.vandermonde, np.asarray(values).reshape(-1, self.q, 1))[..., 0]
        lam_tau.vec.FV().NumPy()[self.dofs.ravel()] = coefficients.ravel()

    def snapshot(self, lam_tau):
        """The multiplier's Gauss values with the edge geometry, independent of the mesh."""
        return GaussValues(self.xy, self.ends, self.values(lam_tau))


class GaussValues:
    """A piecewise degree-p function on Gamma_C given by its values at the Gauss points of each edge."""

    def __init__(self, xy, ends, values):
        self.xy, self.ends, self.values = np.asarray(xy), np.asarray(ends), np.asarray(values)
        self.q = self.values.shape[1]

    def edge_parameters(self, xy):
        """For points xy (n, 2) on Gamma_C: the edge containing each and the parameter s in [0, 1]."""
        a, b = self.ends[:, 0], self.ends[:, 1]
        d = b - a
        s = np.einsum("nek,ek->ne", xy[:, None, :] - a[None], d) / np.sum(d * d, axis=1)
        foot = a[None] + s[..., None] * d[None]
        distance = np.linalg.norm(xy[:, None, :] - foot, axis=2) + 1e-12 * (np.abs(s - 0.5) > 0.5 + 1e-9)
        edge = np.argmin(distance, axis=1)
        return edge, np.clip(s[np.arange(len(xy)), edge], 0.0, 1.0)

    def __call__(self, xy):
        """Values at points xy (n, 2) on Gamma_C (Lagrange interpolation through each edge's Gauss nodes)."""
        xy = np.asarray(xy).reshape(-1, 2)
        edge, s = self.edge_parameters(xy)
        a = self.ends[edge, 0]
        d = self.ends[edge, 1] - a
        nodes = np.einsum("nqk,nk->nq", self.xy[edge] - a[:, None], d) / np.sum(d * d, axis=1)[:, None]
        result = np.zeros(len(xy))
        for j in range(self.q):
            basis = np.ones(len(xy))
            for m in range(self.q):
                if m != j:
                    basis *= (s - nodes[:, m]) / (nodes[:, j] - nodes[:, m])
            result += basis * self.values[edge, j]
        return result


def contact_state(sol):
    r"""The state of a solution at the contact Gauss points.

    The points are those of the discrete problem's contact rule on :math:`\Gamma_C`, :math:`p + 1` per edge, in
    the order of :meth:`ngdgfric.Discretization.contact_points`.

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve`.

    Returns
    -------
    dict of str to numpy.ndarray
        One array over the points each:

        - ``x``, ``y``: coordinates;
        - ``u_n``, ``u_tau``: normal and tangential displacement (:math:`u_\tau = u \cdot t`);
        - ``gap``: :math:`u_n - g_a`;
        - ``pressure``: :math:`c_n (u_n - g_a)_+^{m_n}`;
        - ``lam_tau``: the multiplier :math:`\lambda_\tau` (Lemma 3.1);
        - ``sigma_n``, ``sigma_tau``: normal and tangential stress of :math:`u_h`
          (:math:`\sigma_\tau = \sigma_h(u) n \cdot t`);
        - ``c_tau``: the friction coefficient;
        - ``bound``: the friction bound :math:`c_\tau (u_n - g_a)_+^{m_t}` (1.9) (:math:`c_\tau` for
          :math:`m_t = 0`).

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> state = ndf.contact_state(ndf.solve(problem, ndf.uniform_mesh(problem, 0.5)))
    >>> len(state["x"]), bool(abs(state["lam_tau"]).max() <= 1 + 1e-12)
    (4, True)
    """
    points = sol.discretization.contact_points()
    n, t = normal_tangent()
    u, problem = sol.u, sol.discretization.problem
    sigma_n_vec = stress(sol.discretization.material, strain(u)) * n
    return {
        "x": np.asarray(ngs.x(points)).ravel(),
        "y": np.asarray(ngs.y(points)).ravel(),
        "u_n": evaluate_on_contact(u * n, points),
        "u_tau": evaluate_on_contact(u * t, points),
        "gap": evaluate_on_contact(penetration(problem, u), points),
        "pressure": evaluate_on_contact(compliance(problem, u), points),
        "sigma_n": evaluate_on_contact(sigma_n_vec * n, points),
        "sigma_tau": evaluate_on_contact(sigma_n_vec * t, points),
        "lam_tau": np.asarray(sol.lam_tau(points)).ravel(),
        "c_tau": np.asarray(coefficient(problem.c_tau)(points)).ravel() * np.ones(len(points)),
        "bound": evaluate_on_contact(friction_bound(problem, u), points) * np.ones(len(points)),
    }


def transitions(sol, tol=1e-8):
    """The points of Gamma_C where the contact zone or the stick zone of a Solution ends, an (n, 2) array: midway
    between two neighbouring Gauss points of an edge where u_n - g_a changes sign, or |lam_tau| crosses 1 - ``tol``
    (where u may be singular; the adaptive loop grades its meshes towards them, :func:`ngdgfric.hp.hp_refine`)."""
    gauss = sol.discretization.gauss
    state = contact_state(sol)
    shape = gauss.xy.shape[:2]
    in_contact = (state["gap"] > 0).reshape(shape)
    sticking = (np.abs(state["lam_tau"]) < 1 - tol).reshape(shape) & in_contact
    flips = (np.diff(in_contact, axis=1) != 0) | (np.diff(sticking, axis=1) != 0)
    edge, k = np.nonzero(flips)
    return 0.5 * (gauss.xy[edge, k] + gauss.xy[edge, k + 1])


def _relative_residual(disc, u, lam_tau):
    """||:func:`residual`||_2 divided by the largest of the norms of its terms (:func:`residual_terms`: B_h(u, .),
    j_n, g, (f, .)), a scale that exists without loads too (a body pushed by a penetration only: f = 0, g = 0);
    0 if every term is zero."""
    terms = [term.FV().NumPy() for term in residual_terms(disc, u, lam_tau)]
    scale = max(float(np.linalg.norm(term)) for term in terms)
    return float(np.linalg.norm(np.sum(terms, axis=0)) / scale) if scale > 0 else 0.0


def kkt_residuals(sol):
    r"""Violations of the discrete KKT system (3.3)-(3.4) of a solution at the Gauss points of :math:`\Gamma_C`.

    All three are at round-off level at a solution.

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve`.

    Returns
    -------
    dict of str to float
        - ``lam_excess``: :math:`\max(|\lambda_\tau| - 1, 0)`;
        - ``complementarity``: :math:`\max |\lambda_\tau u_\tau - |u_\tau|| / \max |u|` (:math:`\max |u|` over
          the coefficients of :math:`u_h`);
        - ``equilibrium``: the Euclidean norm of the residual of (3.3) relative to the largest of its terms
          :math:`B_h(u_h, \cdot)`, :math:`j_n`, :math:`g` and :math:`(f, \cdot)`, the friction term with the bound
          at :math:`u_h` (``residual`` of :mod:`ngdgfric.contact`).

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> residuals = ndf.kkt_residuals(ndf.solve(problem, ndf.uniform_mesh(problem, 0.5)))
    >>> sorted(residuals)
    ['complementarity', 'equilibrium', 'lam_excess']
    >>> all(value < 1e-10 for value in residuals.values())
    True
    """
    state = contact_state(sol)
    scale = max(np.max(np.abs(sol.u.vec.FV().NumPy())), 1e-300)
    lam_tau, u_tau = state["lam_tau"], state["u_tau"]
    return {
        "lam_excess": float(max(np.max(np.abs(lam_tau), initial=0.0) - 1.0, 0.0)),
        "complementarity": float(np.max(np.abs(lam_tau * u_tau - np.abs(u_tau)), initial=0.0) / scale),
        "equilibrium": _relative_residual(sol.discretization, sol.u, sol.lam_tau),
    }


def rounding_residual(sol):
    """The equilibrium residual of :func:`kkt_residuals` for u rounded once more, u (1 +- eps) with
    fixed random signs: what round-off in u alone leaves, the floor to compare ``equilibrium`` with."""
    u = ngs.GridFunction(sol.u.space)
    signs = np.random.default_rng(0).choice([-1.0, 1.0], size=len(u.vec))
    u.vec.FV().NumPy()[:] = sol.u.vec.FV().NumPy() * (1 + np.finfo(float).eps * signs)
    return _relative_residual(sol.discretization, u, sol.lam_tau)
