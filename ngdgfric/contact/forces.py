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

__all__ = ["Zone", "ContactSide", "contact_sides", "constant_vectors", "LAM_TOL", "SLIP_TOL"]

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


def constant_vectors(V):
    """The coefficient vectors of the constant functions e_x, e_y in V_h (numpy arrays)."""
    vectors = []
    for e in ((1.0, 0.0), (0.0, 1.0)):
        gf = ngs.GridFunction(V)
        gf.Set(ngs.CF(e))
        vectors.append(gf.vec.FV().NumPy().copy())
    return np.array(vectors)


def contact_sides(sol, lam_tol=LAM_TOL, slip_tol=SLIP_TOL, constants=None):
    """{contact side: :class:`ContactSide`}: the contact part of :func:`ngdgfric.forces.force_balance` (no assembly;
    also for plots).  ``lam_tol``, ``slip_tol``: module docstring; ``constants``: :func:`constant_vectors` of the
    solution's space if at hand."""
    disc, contact = sol.discretization, sol.contact
    constants = constant_vectors(disc.V) if constants is None else constants
    traces, q = contact.traces, contact.gauss.q
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
