r"""Contact forces of a solution of (3.3), side by side: resultants and contact, stick and slip zones.

**Contact, (1.8)-(1.9).**  On a contact side :math:`S` the foundation exerts on the body the traction
:math:`\sigma(u) n = \sigma_n n + \sigma_\tau t`, :math:`t = (-n_y, n_x)`, with
:math:`\sigma_n = -c_n (u_n - g_a)_+^{m_n}` (1.8) and, in the discrete problem (Lemma 3.1),
:math:`\sigma_\tau = -\beta \lambda_\tau`, :math:`\beta = c_\tau (u_n - g_a)_+^{m_t}` the friction bound of (1.9)
(:math:`c_\tau` itself for the reduced law :math:`m_t = 0`).  The resultants of :math:`S` are

.. math::

    N_S &= \int_S c_n (u_{hn} - g_a)_+^{m_n} \, ds
    \quad (\ge 0, \text{ a compression: it acts along } -n), \\
    T_S &= \int_S \sigma_\tau \, ds = -\int_S \beta \lambda_\tau \, ds \quad (\text{along } t), \\
    F_S &= -\int_S \left(c_n (u_{hn} - g_a)_+^{m_n} n + \beta \lambda_\tau t\right) ds \quad (\text{on the body}),

each with the contact Gauss rule of the discrete problem (:math:`p + 1` points per edge, weights
:math:`\omega_q` of ``ContactTraces`` in :mod:`ngdgfric.contact.traces`, :math:`n` and :math:`t` at the points
from its trace matrix :math:`B`), so that :math:`F_S \cdot e_i = -(j_n(u_h, e_i) + g(\lambda_\tau, e_i))` over the
edges of :math:`S`: the discrete contact forces of (3.3), not an approximation of them.  Sign conventions:
:math:`n` is the outward normal, :math:`t = (-n_y, n_x)` the direction in which the boundary runs with the body on
its left (counter-clockwise around the body); :math:`T_S > 0` pushes the body along :math:`t`.  Since
:math:`\lambda_\tau u_\tau = |u_\tau|` (3.4), the friction traction opposes the slip:
:math:`\sigma_\tau u_\tau \le 0` at every point.

**Zones.**  A property of the Gauss points is turned into lengths by the points' weights: point :math:`q` of an
edge owns the cell :math:`[c_{q-1}, c_q]` of the reference edge, :math:`c_q = w_1 + \dots + w_q` (Gauss weights on
:math:`[0, 1]`), which contains the point (the separation theorem of Chebyshev, Markov and Stieltjes for Gauss
rules) and is mapped by the element mapping (curved sides too); a zone is the union of the cells of its points,
its length the sum of their weights :math:`\omega_q`, the same measure with which (3.3) integrates the contact
terms (so :math:`N_S` is the sum over the contact zone only).  The zones of one contact side are

* contact: :math:`u_{hn} - g_a > 0` (exactly the points with a compliance force, (1.8); no tolerance needed: the
  pressure is continuous and vanishes at the zone's ends);
* slip: :math:`\beta > 0`, :math:`|\lambda_\tau| \ge 1 -` ``lam_tol`` (:math:`|\sigma_\tau|` at the bound, (1.9))
  and :math:`u_\tau \ne 0`, i.e. :math:`|u_\tau| >` ``slip_tol`` :math:`\max |u_h|` on :math:`\Gamma_C`.  Every
  solver ends with a projection onto the bound (Newton: the friction force onto
  :math:`[-\beta \omega, \beta \omega]`, :math:`\lambda_\tau = f_t / (\beta \omega)`; Uzawa and the fixed point:
  :math:`\lambda_\tau` onto :math:`[-1, 1]`), so :math:`|\lambda_\tau| = 1` to round-off where the points slip
  (:math:`1 - |\lambda_\tau| \le 1.2 \cdot 10^{-16}` measured with Newton and Uzawa on Example 6.1,
  :math:`h = 1/8`), while in a stick zone :math:`|\lambda_\tau| < 1` varies continuously (at most 0.83 there): the
  default ``lam_tol = 1e-6`` is far above round-off and counts only points within :math:`10^{-6}` of the bound as
  at it.  :math:`u_\tau` is not the criterion: sticking points have :math:`u_\tau = 0` only up to the solver's
  accuracy (Newton: :math:`3 \cdot 10^{-16} \max |u_h|`; Uzawa with the tolerance :math:`10^{-8}` of Section 6:
  :math:`2 \cdot 10^{-6} \max |u_h|`, against :math:`2.6 \cdot 10^{-3} \max |u_h|` at the least slipping point),
  so ``slip_tol`` (default ``1e-8``) only tells a point at the bound that does not move (impending slip, counted as
  stick) from one that slips;
* stick: :math:`\beta > 0` and not slip.

Friction acts where :math:`\beta > 0`: on the contact zone for :math:`m_t > 0`, but on all of :math:`\Gamma_C` for
the reduced law :math:`m_t = 0` of the paper (1.10), whose friction bound :math:`c_\tau` does not depend on
contact; stick and slip zones are parts of that region (and may lie outside the contact zone for
:math:`m_t = 0`).
"""

from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from .boundary import boundary_edges, contact_rule
from .state import contact_state

__all__ = ["Zone", "ContactSide", "contact_sides", "zone_masks", "side_of", "walk", "chains", "zone",
           "constant_vectors", "LAM_TOL", "SLIP_TOL"]

LAM_TOL = 1e-6
"""Default ``lam_tol`` of :func:`ngdgfric.forces.force_balance`: |lam_tau| >= 1 - LAM_TOL is at the friction bound."""
SLIP_TOL = 1e-8
"""Default ``slip_tol`` of :func:`ngdgfric.forces.force_balance`: |u_tau| > SLIP_TOL max |u_h| on Gamma_C is a slip."""


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
    """The contact forces and zones of one contact side (module docstring), or of one side of a contact pair
    (:mod:`ngdgfric.contact.pair_zones`).

    ``normal``: N_S; ``tangential``: T_S (along t); ``force``: F_S, the (x, y) force of the foundation (of the other
    body, on a pair's side) on the body; ``length``: the side's length (sum of its weights omega_q); ``contact``,
    ``stick``, ``slip``: :class:`Zone`.  Point data in order along the side (along t): ``points`` (indices into the
    arrays of :func:`ngdgfric.contact.contact_state`, or of the pair's entry of
    :func:`ngdgfric.contact.pair_state`), ``arc`` (arc length of each point from the side's start), ``cells``
    ((m, 2) arc length of each point's cell ends), ``cell_ends`` ((m, 2, 2) the (x, y) of those ends), ``xy``
    ((m, 2) the points), ``pressure`` (the normal traction c_n (u_n - g_a)_+^{m_n} there), ``lam_tau`` (the
    multiplier), ``in_contact``, ``sticking``, ``slipping`` (boolean arrays); ``partner``: the other side of its
    contact pair ("" on the foundation).  A side made of several separate pieces is walked piece after piece (its
    arc length then runs on across the gaps).
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
    xy: np.ndarray = field(repr=False)
    pressure: np.ndarray = field(repr=False)
    lam_tau: np.ndarray = field(repr=False)
    in_contact: np.ndarray = field(repr=False)
    sticking: np.ndarray = field(repr=False)
    slipping: np.ndarray = field(repr=False)
    partner: str = ""


def constant_vectors(V, regions=None):
    """The coefficient vectors of the constant functions e_x, e_y in V_h (numpy arrays, shape (2, ndof)); with
    ``regions`` (region names), of e_x, e_y on the elements of those regions and 0 elsewhere (one body's rigid
    translations: bodies share no vertex, so this is a function of V_h)."""
    vectors = []
    for e in ((1.0, 0.0), (0.0, 1.0)):
        gf = ngs.GridFunction(V)
        cf = ngs.CF(e)
        if regions is not None:
            cf = cf * V.mesh.MaterialCF({name: 1.0 for name in regions}, default=0.0)
        gf.Set(cf)
        vectors.append(gf.vec.FV().NumPy().copy())
    return np.array(vectors)


def contact_sides(sol, lam_tol=LAM_TOL, slip_tol=SLIP_TOL, constants=None):
    """{contact side: :class:`ContactSide`}: the contact part of :func:`ngdgfric.forces.force_balance` (no assembly;
    also for plots).  ``lam_tol``, ``slip_tol``: module docstring; ``constants``: :func:`constant_vectors` of the
    solution's space if at hand."""
    disc, contact = sol.discretization, sol.contact
    constants = constant_vectors(disc.V) if constants is None else constants
    traces, q = contact.traces, contact.gauss.q
    M, foundation = traces.M, traces.foundation  # the foundation's points first, then the pairs'
    state = contact_state(sol)
    # n, t at the points as (3.3) sees them: (B e_i)_q = n_i(x_q), (B e_i)_{M+q} = t_i(x_q)
    n = np.column_stack([traces.apply(e)[:foundation] for e in constants])
    t = np.column_stack([traces.apply(e)[M:M + foundation] for e in constants])
    omega = traces.omega[:foundation]
    f_n = omega * state["pressure"]
    f_t = omega * state["bound"] * state["lam_tau"]
    in_contact, sticking, slipping = zone_masks(state["gap"], state["bound"], state["lam_tau"], state["u_n"],
                                                state["u_tau"], lam_tol, slip_tol)
    nodes, fractions = _cells(q)
    within = (nodes - fractions[:-1]) / np.diff(fractions)  # where each point lies in its cell
    walks, cell_ends = _walks(sol.mesh, disc.problem, fractions, t)
    xy = np.column_stack([state["x"], state["y"]])
    result = {}
    for side, walked in walks.items():
        points = np.concatenate([np.arange(k * q, (k + 1) * q)[::-1 if reverse else 1] for k, reverse in walked])
        ends = np.concatenate([np.stack([e[:-1], e[1:]], axis=1) for e in
                               (cell_ends[k][::-1 if reverse else 1] for k, reverse in walked)])
        position = np.concatenate([(1 - within)[::-1] if reverse else within for _, reverse in walked])
        result[side] = side_of(
            side, points, omega[points], ends, position,
            masks=(in_contact[points], sticking[points], slipping[points]),
            normal=float(f_n[points].sum()), tangential=float(-f_t[points].sum()),
            force=-(f_n[points, None] * n[points] + f_t[points, None] * t[points]).sum(axis=0),
            xy=xy[points], pressure=state["pressure"][points], lam_tau=state["lam_tau"][points])
    return result


def zone_masks(penetration, bound, lam_tau, u_n, u_tau, lam_tol, slip_tol):
    """(in contact, sticking, slipping), boolean arrays over points (module docstring): penetration > 0; at the
    friction bound (``bound`` > 0, |lam_tau| >= 1 - ``lam_tol``) with |u_tau| > ``slip_tol`` times the largest of
    |u_n|, |u_tau| over the points; and where friction acts otherwise."""
    scale = max(float(np.max(np.abs(np.r_[u_n, u_tau]), initial=0.0)), np.finfo(float).tiny)
    friction = bound > 0
    slipping = friction & (np.abs(lam_tau) >= 1 - lam_tol) & (np.abs(u_tau) > slip_tol * scale)
    return penetration > 0, friction & ~slipping, slipping


def side_of(side, points, weights, ends, position, masks, partner="", **forces):
    """The :class:`ContactSide` of the points ``points`` of one side in walk order: ``weights`` (their omega_q),
    ``ends`` ((m, 2, 2) their cell ends), ``position`` (where each point lies in its cell, 0 to 1), ``masks``
    (in contact, sticking, slipping), ``partner``; ``forces``: the fields normal, tangential, force, xy, pressure,
    lam_tau."""
    end = np.cumsum(weights)
    start = np.r_[0.0, end[:-1]]
    in_contact, sticking, slipping = masks
    zones = {name: zone(mask, weights, ends)
             for name, mask in (("contact", in_contact), ("stick", sticking), ("slip", slipping))}
    return ContactSide(side=side, length=float(weights.sum()), **zones, points=points, arc=start + position * weights,
                       cells=np.column_stack([start, end]), cell_ends=ends, in_contact=in_contact,
                       sticking=sticking, slipping=slipping, partner=partner, **forces)


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
    (the order of :class:`ngdgfric.contact.boundary.ContactGauss`); reversed: walked from xi = 1 to xi = 0."""
    q = len(fractions) - 1
    rule = ngs.IntegrationRule([(c,) for c in fractions], [0.0] * len(fractions))
    mapped = mesh.MapToAllElements({ngs.SEGM: rule}, mesh.Boundaries(problem.where("contact")))
    cell_ends = np.column_stack([np.asarray(ngs.x(mapped)).ravel(),
                                 np.asarray(ngs.y(mapped)).ravel()]).reshape(-1, q + 1, 2)
    sides, vertices = [], []
    for k, (el, _) in enumerate(boundary_edges(problem, mesh)):
        a, b = (v.nr for v in el.vertices)
        at_a = np.asarray(mesh[el.vertices[0]].point)
        if np.linalg.norm(cell_ends[k, 0] - at_a) > np.linalg.norm(cell_ends[k, -1] - at_a):
            a, b = b, a  # (vertex at xi = 0, vertex at xi = 1)
        sides.append(el.mat)
        vertices.append((a, b))
    walks = {}
    for side in dict.fromkeys(sides):
        edges = [k for k, name in enumerate(sides) if name == side]
        forward = np.array([cell_ends[k, -1] - cell_ends[k, 0] for k in edges])
        along = np.array([t[k * q:(k + 1) * q].mean(axis=0) for k in edges])
        walks[side] = [(edges[j], reverse) for j, reverse in walk([vertices[k] for k in edges], forward, along)]
    return walks, cell_ends


def walk(vertices, forward, along):
    """The edges of one side chained along its tangent: a list of (edge number, reversed), chain after chain
    (:func:`chains`), each chain turned so that it runs along ``along``.  ``vertices``: (a, b) per edge (the vertices
    at s = 0 and s = 1); ``forward``: (edges, 2) x(1) - x(0) of each edge; ``along``: (edges, 2) the tangent t on
    each edge."""
    walked = []
    for chain in chains(vertices):
        k, reverse = chain[0]
        if (forward[k] * (-1 if reverse else 1)) @ along[k] < 0:
            chain = [(k, not reverse) for k, reverse in chain[::-1]]
        walked += chain
    return walked


def chains(edges):
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


def zone(mask, weights, ends):
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
