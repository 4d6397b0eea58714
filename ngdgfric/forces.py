"""Forces on the body as the discrete problem (3.3) sees them: contact resultants and zones, support reactions.

**Contact, (1.8)-(1.9).**  On a contact side S the foundation exerts on the body the traction
sigma(u) n = sigma_n n + sigma_tau t, t = (-n_y, n_x), with sigma_n = -c_n (u_n - g_a)_+^{m_n} (1.8) and, in the
discrete problem (Lemma 3.1), sigma_tau = -beta lam_tau, beta = c_tau (u_n - g_a)_+^{m_t} the friction bound of
(1.9) (c_tau itself for the reduced law m_t = 0).  The resultants of S are

    normal       N_S = int_S c_n (u_hn - g_a)_+^{m_n} ds              (>= 0, a compression: it acts along -n)
    tangential   T_S = int_S sigma_tau ds = -int_S beta lam_tau ds     (along t)
    vector       F_S = -int_S (c_n (u_hn - g_a)_+^{m_n} n + beta lam_tau t) ds     (on the body)

each with the contact Gauss rule of the discrete problem (p + 1 points per edge, weights omega_q of
:class:`ngdgfric.solvers.traces.ContactTraces`, n and t at the points from its trace matrix B), so that
F_S . e_i = -(j_n(u_h, e_i) + g(lam_tau, e_i)) over the edges of S: the discrete contact forces of (3.3), not an
approximation of them.  Sign conventions: n is the outward normal, t = (-n_y, n_x) the direction in which the
boundary runs with the body on its left (counter-clockwise around the body); T_S > 0 pushes the body along t.
Since lam_tau u_tau = |u_tau| (3.4), the friction traction opposes the slip: sigma_tau u_tau <= 0 at every point.

**Zones.**  A property of the Gauss points is turned into lengths by the points' weights: point q of an edge
owns the cell [c_{q-1}, c_q] of the reference edge, c_q = w_1 + ... + w_q (Gauss weights on [0, 1]), which
contains the point (the separation theorem of Chebyshev, Markov and Stieltjes for Gauss rules) and is mapped by
the element mapping (curved sides too); a zone is the union of the cells of its points, its length the sum of
their weights omega_q, the same measure with which (3.3) integrates the contact terms (so N_S is the sum over
the contact zone only).  The zones of one contact side are

* contact: u_hn - g_a > 0 (exactly the points with a compliance force, (1.8); no tolerance needed: the pressure
  is continuous and vanishes at the zone's ends);
* slip: beta > 0, |lam_tau| >= 1 - ``lam_tol`` (|sigma_tau| at the bound, (1.9)) and u_tau != 0, i.e.
  |u_tau| > ``slip_tol`` max |u_h| on Gamma_C.  Every solver ends with a projection onto the bound (Newton: the
  friction force onto [-beta omega, beta omega], lam_tau = f_t / (beta omega); Uzawa and the fixed point: lam_tau
  onto [-1, 1]), so |lam_tau| = 1 to round-off where the points slip (1 - |lam_tau| <= 1.2e-16 measured with
  Newton and Uzawa on Example 6.1, h = 1/8), while in a stick zone |lam_tau| < 1 varies continuously (at most 0.83
  there): the default lam_tol = 1e-6 is far above round-off and counts only points within 1e-6 of the bound as
  at it.  u_tau is not the criterion: sticking points have u_tau = 0 only up to the solver's accuracy (Newton:
  3e-16 max |u_h|; Uzawa with the tolerance 1e-8 of Section 6: 2e-6 max |u_h|, against 2.6e-3 max |u_h| at the
  least slipping point), so ``slip_tol`` (default 1e-8) only tells a point at the bound that does not move
  (impending slip, counted as stick) from one that slips;
* stick: beta > 0 and not slip.

Friction acts where beta > 0: on the contact zone for m_t > 0, but on all of Gamma_C for the reduced law
m_t = 0 of the paper (1.10), whose friction bound c_tau does not depend on contact; stick and slip zones are
parts of that region (and may lie outside the contact zone for m_t = 0).

**Reactions.**  For v = e_i, a constant, eps(e_i) = 0 and [e_i] = 0 on interior edges, so (3.3) keeps only
boundary terms:

    sum_{S supported} b_S(u_h, e_i) + j_n(u_h, e_i) + g(lam_tau, e_i) = (f, e_i) + int_{Gamma_F} g . e_i ds,

b_S the part of B_h(u_h, e_i), minus the part of the right-hand side that u_D carries, on the edges of the
Dirichlet or symmetry side S (:func:`ngdgfric.dg.forms.dg_terms`, :func:`ngdgfric.dg.forms.load_terms`):
-e_i . sigma_h(u_h) n + w eta p^2 / h_e [u_h - u_D] : [e_i] ds, with only normal parts (u . n) n and the weight
w = :data:`~ngdgfric.dg.forms.SYMMETRY_WEIGHT` on symmetry sides, plus for Bassi, Brezzi and LDG the lifting terms
of its edges, eta sum_{e in S} (C r_e[u_h - u_D], r_e[e_i]) and sum_{e in S} (C r_0[u_h - u_D], r_e[e_i])
(:mod:`ngdgfric.dg.liftings`).  The reaction of S, the force the support exerts on the body, is R_S = -b_S(u_h, e_i)
(the DG flux: int_S sigma_h(u_h) n ds minus the penalty), so that

    sum_S R_S + F_f + F_g + sum_C F_C = 0,      F_f = (f, e_i) (body force, (1.5)),  F_g = int_{Gamma_F} g ds (1.7),

to round-off at a solution of (3.3) (:attr:`ForceBalance.residual`).  Every term is assembled with the
integrands and quadrature of the discrete problem.
"""

from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from .contact import contact_rule, contact_state
from .dg.forms import dirichlet_load_terms, has_dirichlet_data, support_terms
from .dg.liftings import edge_colours, lifting_matrices, lifting_space
from .problem import coefficient, pattern
from .threads import threads

__all__ = ["Zone", "ContactSide", "Reaction", "ForceBalance", "force_balance", "contact_sides", "LAM_TOL", "SLIP_TOL"]

LAM_TOL = 1e-6
"""Default ``lam_tol`` of :func:`force_balance`: |lam_tau| >= 1 - LAM_TOL is at the friction bound."""
SLIP_TOL = 1e-8
"""Default ``slip_tol`` of :func:`force_balance`: |u_tau| > SLIP_TOL max |u_h| on Gamma_C is a slip."""


@dataclass(frozen=True)
class Zone:
    """A part of a contact side: the union of the Gauss cells of its points (module docstring).

    ``length``: the sum of the weights omega_q of its points; ``pieces``: the runs of consecutive cells, each a
    (k, 2) array of the cell ends in order along t (on curved sides a polyline through every cell end).
    """

    length: float
    pieces: tuple

    @property
    def start(self):
        """The first point of the zone along the side (along t), None for an empty zone."""
        return tuple(self.pieces[0][0]) if self.pieces else None

    @property
    def end(self):
        """The last point of the zone along the side, None for an empty zone."""
        return tuple(self.pieces[-1][-1]) if self.pieces else None

    @property
    def bounds(self):
        """(x0, y0, x1, y1): the coordinate range of the zone, None for an empty zone."""
        if not self.pieces:
            return None
        points = np.concatenate(self.pieces)
        return (*points.min(axis=0).tolist(), *points.max(axis=0).tolist())


@dataclass(frozen=True)
class ContactSide:
    """The contact forces and zones of one contact side (module docstring).

    ``normal``: N_S; ``tangential``: T_S (along t); ``force``: F_S, the (x, y) force of the foundation on the
    body; ``length``: the side's length (sum of its weights omega_q); ``contact``, ``stick``, ``slip``:
    :class:`Zone`.  Point data in order along the side (along t): ``points`` (indices into the arrays of
    :func:`ngdgfric.contact.contact_state`), ``arc`` (arc length of each point from the side's start),
    ``cells`` ((m, 2) arc length of each point's cell ends), ``cell_ends`` ((m, 2, 2) the (x, y) of those ends),
    ``in_contact``, ``sticking``, ``slipping`` (boolean arrays).  A side made of several separate pieces is walked
    piece after piece (its arc length then runs on across the gaps).
    """

    side: str
    normal: float
    tangential: float
    force: np.ndarray
    length: float
    contact: Zone
    stick: Zone
    slip: Zone
    points: np.ndarray = field(repr=False)
    arc: np.ndarray = field(repr=False)
    cells: np.ndarray = field(repr=False)
    cell_ends: np.ndarray = field(repr=False)
    in_contact: np.ndarray = field(repr=False)
    sticking: np.ndarray = field(repr=False)
    slipping: np.ndarray = field(repr=False)


@dataclass(frozen=True)
class Reaction:
    """The reaction R_S, the (x, y) force that the support of side ``side`` (``part``: "dirichlet" or
    "symmetry") exerts on the body (module docstring)."""

    side: str
    part: str
    force: np.ndarray


@dataclass(frozen=True)
class ForceBalance:
    """The forces on the body of a solution of (3.3) (module docstring); every vector an (x, y) array.

    ``contact``: {contact side: :class:`ContactSide`}; ``reactions``: {Dirichlet or symmetry side:
    :class:`Reaction`}; ``traction``: {traction side: int_S g ds}; ``body``: (f, e_i), the body force.
    """

    contact: dict
    reactions: dict
    traction: dict
    body: np.ndarray

    def vectors(self):
        """Every force on the body as (kind, side, vector): reactions, contact, traction, body force."""
        return ([(r.part, side, r.force) for side, r in self.reactions.items()]
                + [("contact", side, c.force) for side, c in self.contact.items()]
                + [("traction", side, g) for side, g in self.traction.items()] + [("body", "", self.body)])

    @property
    def residual(self):
        """sum of reactions + body force + traction + contact forces: zero to round-off (global equilibrium)."""
        return np.sum([vector for _, _, vector in self.vectors()], axis=0)

    @property
    def scale(self):
        """The largest force of :meth:`vectors` (Euclidean norm), to judge :attr:`residual` by."""
        return max(float(np.linalg.norm(vector)) for _, _, vector in self.vectors())

    @property
    def relative_residual(self):
        """|residual| / scale (0 if every force vanishes)."""
        scale = self.scale
        return float(np.linalg.norm(self.residual)) / scale if scale > 0 else 0.0

    def rows(self):
        """One dict per force for a CSV file: kind, side, force_x, force_y, and for contact sides normal,
        tangential, the side's length and for each zone its length, number of pieces and first and last point."""
        rows = []
        for kind, side, vector in self.vectors():
            row = dict(kind=kind, side=side, force_x=float(vector[0]), force_y=float(vector[1]))
            if kind == "contact":
                c = self.contact[side]
                row.update(normal=c.normal, tangential=c.tangential, length=c.length)
                for name in ("contact", "stick", "slip"):
                    zone = getattr(c, name)
                    start, end = zone.start or (np.nan, np.nan), zone.end or (np.nan, np.nan)
                    row.update({f"{name}_length": zone.length, f"{name}_pieces": len(zone.pieces),
                                f"{name}_start_x": start[0], f"{name}_start_y": start[1],
                                f"{name}_end_x": end[0], f"{name}_end_y": end[1]})
            rows.append(row)
        residual = self.residual
        rows.append(dict(kind="residual", side="", force_x=float(residual[0]), force_y=float(residual[1])))
        return rows

    def summary(self):
        """A few lines for a terminal: per side the forces and zones, then the equilibrium residual."""
        lines = []
        for side, r in self.reactions.items():
            lines.append(f"{r.part} {side}: reaction ({r.force[0]:.6e}, {r.force[1]:.6e})")
        for side, c in self.contact.items():
            lines.append(f"contact {side}: normal {c.normal:.6e}, tangential {c.tangential:.6e}, "
                         f"force ({c.force[0]:.6e}, {c.force[1]:.6e})")
            lines += [f"  {name + ' zone':12s} {_zone_text(getattr(c, name), c.length)}"
                      for name in ("contact", "stick", "slip")]
        for side, g in self.traction.items():
            lines.append(f"traction {side}: load ({g[0]:.6e}, {g[1]:.6e})")
        lines.append(f"body force: load ({self.body[0]:.6e}, {self.body[1]:.6e})")
        residual = self.residual
        lines.append(f"equilibrium: sum of forces ({residual[0]:.3e}, {residual[1]:.3e}), "
                     f"{self.relative_residual:.1e} of the largest")
        return lines


def _zone_text(zone, length):
    """A zone for a terminal: its length (of the side's ``length``) and its pieces (at most three listed)."""
    if not zone.pieces:
        return f"0 of {length:.4g}"
    ends = [f"{_point_text(piece[0])} to {_point_text(piece[-1])}" for piece in zone.pieces]
    text = f"{zone.length:.4g} of {length:.4g}"
    if len(ends) == 1:
        return f"{text}: {ends[0]}"
    if len(ends) <= 3:
        return f"{text} in {len(ends)} pieces: " + ", ".join(ends)
    return f"{text} in {len(ends)} pieces from {ends[0].split(' to ')[0]} to {ends[-1].split(' to ')[1]}"


def _point_text(xy):
    x, y = np.round(xy, 12) + 0.0  # no 1e-16 or -0 for a point on an axis
    return f"({x:.4g}, {y:.4g})"


def force_balance(sol, lam_tol=LAM_TOL, slip_tol=SLIP_TOL):
    """The forces on the body of a :class:`~ngdgfric.solution.Solution`: a :class:`ForceBalance`.

    Contact resultants and zones per contact side, reactions per Dirichlet and symmetry side, the loads
    (module docstring).  ``lam_tol``: |lam_tau| >= 1 - lam_tol is at the friction bound; ``slip_tol``: a point
    at the bound slips where |u_tau| > slip_tol max |u_h| on Gamma_C (module docstring for both).
    """
    disc = sol.discretization
    constants = _constants(disc.V)
    with threads(disc.V.ndof):
        contact = _contact_sides(sol, constants, lam_tol, slip_tol)
        reactions = _reactions(disc, sol.u, constants)
        traction, body = _loads(disc, constants)
    return ForceBalance(contact, reactions, traction, body)


def contact_sides(sol, lam_tol=LAM_TOL, slip_tol=SLIP_TOL):
    """The contact part of :func:`force_balance` alone: {contact side: :class:`ContactSide`} (no assembly; for
    plots)."""
    return _contact_sides(sol, _constants(sol.discretization.V), lam_tol, slip_tol)


def _constants(V):
    """The coefficient vectors of the constant functions e_x, e_y in V_h (numpy arrays)."""
    vectors = []
    for e in ((1.0, 0.0), (0.0, 1.0)):
        gf = ngs.GridFunction(V)
        gf.Set(ngs.CF(e))
        vectors.append(gf.vec.FV().NumPy().copy())
    return np.array(vectors)


def _found(problem, mesh, part):
    """The sides of a boundary part that the mesh has."""
    return [side for side in problem.sides(part) if side in mesh.GetBoundaries()]


# ---------------------------------------------------------------------------------------------------------------
# contact


def _contact_sides(sol, constants, lam_tol, slip_tol):
    disc = sol.discretization
    traces, q = disc.traces, disc.gauss.q
    M = traces.M
    state = contact_state(sol)
    # n, t at the points as (3.3) sees them: (B e_i)_q = n_i(x_q), (B e_i)_{M+q} = t_i(x_q)
    n = np.column_stack([traces.apply(e)[:M] for e in constants])
    t = np.column_stack([traces.apply(e)[M:] for e in constants])
    f_n = traces.omega * state["pressure"]
    f_t = traces.omega * state["bound"] * state["lam_tau"]
    scale = max(float(np.max(np.abs(np.r_[state["u_n"], state["u_tau"]]), initial=0.0)), np.finfo(float).tiny)
    in_contact = state["gap"] > 0
    friction = state["bound"] > 0
    slipping = friction & (np.abs(state["lam_tau"]) >= 1 - lam_tol) & (np.abs(state["u_tau"]) > slip_tol * scale)
    sticking = friction & ~slipping
    nodes, fractions = _cells(q)
    within = (nodes - fractions[:-1]) / np.diff(fractions)  # where each point lies in its cell
    walks, cell_ends = _walks(sol.mesh, disc.problem, fractions, t)
    result = {}
    for side, walk in walks.items():
        points = np.concatenate([np.arange(k * q, (k + 1) * q)[::-1 if reverse else 1] for k, reverse in walk])
        ends = np.concatenate([np.stack([e[:-1], e[1:]], axis=1) for e in
                               (cell_ends[k][::-1 if reverse else 1] for k, reverse in walk)])
        position = np.concatenate([(1 - within)[::-1] if reverse else within for _, reverse in walk])
        weights = traces.omega[points]
        end = np.cumsum(weights)
        start = np.r_[0.0, end[:-1]]
        zones = {name: _zone(mask[points], weights, ends)
                 for name, mask in (("contact", in_contact), ("stick", sticking), ("slip", slipping))}
        result[side] = ContactSide(
            side=side, normal=float(f_n[points].sum()), tangential=float(-f_t[points].sum()),
            force=-(f_n[points, None] * n[points] + f_t[points, None] * t[points]).sum(axis=0),
            length=float(weights.sum()), **zones, points=points, arc=start + position * weights,
            cells=np.column_stack([start, end]), cell_ends=ends, in_contact=in_contact[points],
            sticking=sticking[points], slipping=slipping[points])
    return result


def _cells(q):
    """The nodes xi_1 < ... < xi_q of the contact Gauss rule on [0, 1] and its cell ends 0 = c_0 < c_1 < ... <
    c_q = 1, c_k = w_1 + ... + w_k."""
    rule = contact_rule(q - 1)[ngs.SEGM]
    nodes = np.array([point[0] for point in rule.points])
    if np.any(np.diff(nodes) <= 0):
        raise RuntimeError("the contact Gauss points are not in increasing order on the reference edge")
    return nodes, np.r_[0.0, np.cumsum(rule.weights)]


def _walks(mesh, problem, fractions, t):
    """({contact side: its edges chained along t, a list of (edge number, reversed)}, the cell ends of every
    contact edge mapped, (edges, q + 1, 2) in reference order).  Edge k holds the Gauss points k q ... (k + 1) q - 1
    (the order of :class:`ngdgfric.contact.ContactGauss`); reversed: walked from xi = 1 to xi = 0."""
    q = len(fractions) - 1
    rule = ngs.IntegrationRule([(c,) for c in fractions], [0.0] * len(fractions))
    mapped = mesh.MapToAllElements({ngs.SEGM: rule}, mesh.Boundaries(problem.where("contact")))
    cell_ends = np.column_stack([np.asarray(ngs.x(mapped)).ravel(),
                                 np.asarray(ngs.y(mapped)).ravel()]).reshape(-1, q + 1, 2)
    sides, vertices = [], []
    for el in mesh.Elements(ngs.BND):
        if el.mat in problem.sides("contact"):
            k = len(sides)
            a, b = (v.nr for v in el.vertices)
            at_a = np.asarray(mesh[el.vertices[0]].point)
            if np.linalg.norm(cell_ends[k, 0] - at_a) > np.linalg.norm(cell_ends[k, -1] - at_a):
                a, b = b, a  # (vertex at xi = 0, vertex at xi = 1)
            sides.append(el.mat)
            vertices.append((a, b))
    walks = {}
    for side in dict.fromkeys(sides):
        edges = [k for k, name in enumerate(sides) if name == side]
        walk = []
        for chain in _chains([vertices[k] for k in edges]):
            chain = [(edges[j], reverse) for j, reverse in chain]
            k, reverse = chain[0]
            forward = (cell_ends[k, -1] - cell_ends[k, 0]) * (-1 if reverse else 1)
            if forward @ t[k * q:(k + 1) * q].mean(axis=0) < 0:
                chain = [(k, not reverse) for k, reverse in chain[::-1]]
            walk += chain
        walks[side] = walk
    return walks, cell_ends


def _chains(edges):
    """The edges (vertex pairs (a, b)) as chains: lists of (edge number, reversed) with consecutive edges
    sharing a vertex, each chain from one end to the other (or around a closed loop)."""
    touching = {}
    for k, (a, b) in enumerate(edges):
        touching.setdefault(a, []).append(k)
        touching.setdefault(b, []).append(k)
    used, chains = set(), []
    ends = [v for v, ks in touching.items() if len(ks) == 1]
    starts = ends + [v for v in touching if v not in ends]  # open chains from an end, then closed loops
    for v in starts:
        while any(k not in used for k in touching[v]):
            chain, at = [], v
            while True:
                free = [k for k in touching[at] if k not in used]
                if not free:
                    break
                k = free[0]
                used.add(k)
                a, b = edges[k]
                reverse = at != a
                chain.append((k, reverse))
                at = a if reverse else b
            chains.append(chain)
    return chains


def _zone(mask, weights, ends):
    """The :class:`Zone` of the points ``mask`` of one side (in walk order); ``ends``: their cell ends, (m, 2, 2)."""
    pieces, current, previous = [], None, None
    for (a, b), inside in zip(ends, mask, strict=True):
        if inside:
            if current is not None and np.linalg.norm(a - previous) <= 1e-9 * np.linalg.norm(b - a):
                current.append(b)
            else:
                current = [a, b]
                pieces.append(current)
        else:
            current = None
        previous = b
    if len(pieces) > 1 and np.linalg.norm(pieces[-1][-1] - pieces[0][0]) <= 1e-9 * np.linalg.norm(
            pieces[0][1] - pieces[0][0]):  # around a closed side: the walk's last piece goes on into its first
        pieces = [pieces[-1] + pieces[0][1:]] + pieces[1:-1]
    return Zone(float(weights[mask].sum()), tuple(np.array(piece) for piece in pieces))


# ---------------------------------------------------------------------------------------------------------------
# reactions and loads


def _reactions(disc, u, constants):
    """{side: :class:`Reaction`} of the Dirichlet and symmetry sides on the mesh."""
    problem, mesh = disc.problem, disc.mesh
    lifted = _lifting_parts(disc, u, constants)
    reactions = {}
    for part in ("dirichlet", "symmetry"):
        for side in _found(problem, mesh, part):
            b = _support_form(disc, part, side)
            applied = disc.F.CreateVector()
            b.Apply(u.vec, applied)
            value = applied.FV().NumPy().copy()
            if part == "dirichlet" and has_dirichlet_data(problem):
                value -= _dirichlet_load(disc, side)
            reactions[side] = Reaction(side, part, -(constants @ value + lifted.get(side, 0.0)))
    return reactions


def _support_form(disc, part, side):
    """The terms of B_h on the edges of one Dirichlet or symmetry side (:func:`ngdgfric.dg.forms.support_terms`), as
    a bilinear form on V_h that is applied, not assembled."""
    u, v = disc.V.TnT()
    consistency, penalised = support_terms(disc.problem, disc.material, disc.mesh, u, v, disc.method, disc.penalty,
                                           disc.p, disc.h_penalty, part, sides=[side])
    form = ngs.BilinearForm(disc.V, nonassemble=True)
    for term in consistency + ([penalised] if penalised is not None else []):
        form += term
    return form


def _dirichlet_load(disc, side):
    """The part of the load vector that u_D carries on one Dirichlet side
    (:func:`ngdgfric.dg.forms.dirichlet_load_terms`)."""
    form = ngs.LinearForm(disc.V)
    for term in dirichlet_load_terms(disc.problem, disc.material, disc.mesh, disc.V.TestFunction(), disc.method,
                                     disc.penalty, disc.p, disc.h_penalty, sides=[side]):
        form += term
    form.Assemble()
    return form.vec.FV().NumPy().copy()


def _lifting_parts(disc, u, constants):
    """{side: the lifting terms of B_h(u_h, e_i) - (u_D part) on the edges of the side, an (x, y) array}.

    The liftings of the edge colours (:func:`ngdgfric.dg.liftings.lifting_matrices`): r_c[e_i] = R_c e_i lives on
    the elements with a Dirichlet or symmetry edge of colour c, and no element has two edges of one colour, so
    its part on the elements of the side's edges of colour c is sum_{e in S, e in c} r_e[e_i].  Then
    eta sum_{e in S} (C r_e[u - u_D], r_e[e_i]) = eta sum_c (R_c u - r_c)^T P (R_c e_i restricted to those
    elements) and likewise with R u - r (the global lifting r_0) for (C r_0[u - u_D], r_e[e_i])."""
    method, problem, mesh = disc.method, disc.problem, disc.mesh
    if method.penalty != "lift" and not method.global_lift:
        return {}
    R, P, r = lifting_matrices(problem, disc.material, mesh, disc.V, disc.order, local=True,
                               total=method.global_lift)
    colours = edge_colours(problem, mesh)
    space = lifting_space(mesh, disc.order)
    supported = set(_found(problem, mesh, "dirichlet") + _found(problem, mesh, "symmetry"))
    boundary_edges = [(el.mat, el.edges[0].nr, mesh[el.edges[0]].elements[0].nr)
                      for el in mesh.Elements(ngs.BND) if el.mat in supported]

    def apply(matrix, vector):
        x = matrix.CreateRowVector()
        x.FV().NumPy()[:] = vector
        y = matrix.CreateColVector()
        y.data = matrix * x
        return y

    def lifted(k):  # P (R_k u - r_k) as a numpy array
        y = apply(R[k], u.vec.FV().NumPy())
        if r[k] is not None:
            y.data -= r[k]
        z = P.CreateColVector()
        z.data = P * y
        return z.FV().NumPy().copy()

    global_part = lifted(len(R) - 1) if method.global_lift else None
    parts = {side: np.zeros(2) for side in supported}
    for c, colour in enumerate(colours):
        tests = np.array([apply(R[c], e).FV().NumPy() for e in constants])  # R_c e_i, shape (2, dim Sigma_h)
        local_part = lifted(c) if method.penalty == "lift" else None
        for side in supported:
            elements = {element for name, facet, element in boundary_edges if name == side and colour.facets[facet]}
            if not elements:
                continue
            dofs = np.concatenate([list(space.GetDofNrs(ngs.ElementId(ngs.VOL, nr))) for nr in sorted(elements)])
            if local_part is not None:
                parts[side] += disc.penalty.boundary * tests[:, dofs] @ local_part[dofs]
            if global_part is not None:
                parts[side] += tests[:, dofs] @ global_part[dofs]
    return parts


def _loads(disc, constants):
    """({traction side: int_S g ds}, (f, e_i)): the load vector's terms (:func:`ngdgfric.dg.forms.load_terms`) at
    v = e_i."""
    problem, mesh = disc.problem, disc.mesh
    v = disc.V.TestFunction()
    body = ngs.LinearForm(disc.V)
    body += coefficient(problem.f) * v * ngs.dx
    body.Assemble()
    traction = {}
    for side in _found(problem, mesh, "traction"):
        form = ngs.LinearForm(disc.V)
        form += coefficient(problem.g) * v * ngs.ds(skeleton=True, definedon=mesh.Boundaries(pattern([side])))
        form.Assemble()
        traction[side] = constants @ form.vec.FV().NumPy()
    return traction, constants @ body.vec.FV().NumPy()
