r"""Forces on the body as the discrete problem (3.3) sees them: support reactions, loads and their balance.

The contact forces are in :mod:`ngdgfric.contact.forces` (resultants and zones per contact side, (1.8)-(1.9));
:func:`ngdgfric.force_balance` collects all of them in a :class:`~ngdgfric.ForceBalance`.

**Reactions.**  For :math:`v = e_i`, a constant, :math:`\epsilon(e_i) = 0` and :math:`[e_i] = 0` on interior edges,
so (3.3) keeps only boundary terms:

.. math::

    \sum_{S \text{ supported}} b_S(u_h, e_i) + j_n(u_h, e_i) + g(\lambda_\tau, e_i)
    = (f, e_i) + \int_{\Gamma_F} g \cdot e_i \, ds,

:math:`b_S` the part of :math:`B_h(u_h, e_i)`, minus the part of the right-hand side that :math:`u_D` carries, on
the edges of the Dirichlet or symmetry side :math:`S` (``dg_terms`` and ``load_terms`` of
:mod:`ngdgfric.dg.forms`), integrated over the edges:

.. math::

    -e_i \cdot \sigma_h(u_h) n + w \eta p^2 / h_e [u_h - u_D] : [e_i],

with only normal parts :math:`(u \cdot n) n` and the weight :math:`w` = ``SYMMETRY_WEIGHT`` of
:mod:`ngdgfric.dg.forms` on symmetry sides, plus for Bassi, Brezzi and LDG the lifting terms of its edges,
:math:`\eta \sum_{e \in S} (C r_e([u_h - u_D]), r_e([e_i]))` and
:math:`\sum_{e \in S} (C r_0([u_h - u_D]), r_e([e_i]))` (:mod:`ngdgfric.dg.liftings`).  The reaction of
:math:`S`, the force the support exerts on the body, is :math:`R_S = -b_S(u_h, e_i)` (the DG flux:
:math:`\int_S \sigma_h(u_h) n \, ds` minus the penalty), so that

.. math::

    \sum_S R_S + F_f + F_g + \sum_C F_C = 0, \qquad
    F_f = (f, e_i) \text{ (body force, (1.5))}, \qquad F_g = \int_{\Gamma_F} g \, ds \text{ (1.7)},

to round-off at a solution of (3.3) (:attr:`ngdgfric.ForceBalance.residual`).  Every term is assembled with the
integrands and quadrature of the discrete problem.

**Several bodies** (a :class:`~ngdgfric.Domain` whose regions form bodies that touch along contact pairs,
:class:`~ngdgfric.ContactPair`).  No DG term couples two bodies, so (3.3) at :math:`v = e_i^b`, the constant
:math:`e_i` on body :math:`b` and 0 elsewhere, is the balance of body :math:`b` alone: the reactions of its
supports, its loads (:math:`(f, e_i^b)` and the tractions of its sides), the foundation's contact forces on its
contact sides and the pairs' forces on its pair sides (:mod:`ngdgfric.contact.pair_zones`: measured on each side
of a pair through that side's traces) add up to zero (``bodies`` of :class:`~ngdgfric.ForceBalance`).  A pair's force on
one side and on the other are equal and opposite to round-off (:meth:`ngdgfric.ForceBalance.pair_resultants`).
"""

from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from .contact.forces import LAM_TOL, SLIP_TOL, constant_vectors, contact_sides
from .contact.pair_zones import pair_sides
from .dg.forms import dirichlet_load_terms, has_dirichlet_data, support_terms
from .dg.liftings import liftings
from .meshes import facet_indicator
from .problem import coefficient, pattern
from .threads import threads

__all__ = ["Reaction", "ForceBalance", "force_balance"]


@dataclass(frozen=True)
class Reaction:
    """The reaction :math:`R_S`, the (x, y) force that the support of side ``side`` (``part``: "dirichlet" or
    "symmetry") exerts on the body (module docstring)."""

    side: str
    part: str
    force: np.ndarray


@dataclass(frozen=True)
class ForceBalance:
    r"""The forces on the body of a solution of (3.3), side by side; every vector an (x, y) array.

    Made by :func:`ngdgfric.force_balance`; the terms and their balance: module docstring of
    :mod:`ngdgfric.forces`.

    Parameters
    ----------
    contact : dict
        ``{contact side: ContactSide}``: per contact side the normal and tangential resultants :math:`N_S`,
        :math:`T_S` (``normal``, ``tangential``), the force of the foundation on the body :math:`F_S`
        (``force``), the side's ``length`` and its ``contact``, ``stick`` and ``slip`` zones
        (``ContactSide`` and ``Zone`` of :mod:`ngdgfric.contact.forces`).
    reactions : dict
        ``{Dirichlet or symmetry side: Reaction}``: the reaction :math:`R_S` of each support (its ``force``;
        ``part`` says ``"dirichlet"`` or ``"symmetry"``).
    traction : dict
        ``{traction side: vector}``: the load :math:`\int_S g \, ds` of each traction side.
    body : numpy.ndarray
        :math:`(f, e_i)`, the body force.
    pairs : dict
        ``{side of a contact pair: ContactSide}``: for each pair its side, then its other side (``partner``), with
        the force of the other body on the side's body (``force``), the pair's ``normal`` and ``tangential``
        resultants, the pressure along the side (``arc``, ``xy``, ``pressure``) and the zones
        (:mod:`ngdgfric.contact.pair_zones`).  Empty without pairs.
    bodies : tuple
        With several bodies, one :class:`~ngdgfric.ForceBalance` per body (``geometry.bodies``), of the forces on
        that body only; its ``residual`` is zero to round-off.  Empty for one body.
    name : str
        What the forces act on: ``"the body"``, or ``"body k (regions ...)"``.

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> balance = ndf.force_balance(ndf.solve(problem, ndf.uniform_mesh(problem, 0.5)))
    >>> balance.relative_residual < 1e-10
    True
    """

    contact: dict
    reactions: dict
    traction: dict
    body: np.ndarray
    pairs: dict = field(default_factory=dict)
    bodies: tuple = ()
    name: str = "the body"

    def vectors(self):
        """Every force as (kind, side, vector): reactions, contact, contact pairs (both sides), traction, body
        force."""
        return ([(r.part, side, r.force) for side, r in self.reactions.items()]
                + [("contact", side, c.force) for side, c in self.contact.items()]
                + [("pair", side, c.force) for side, c in self.pairs.items()]
                + [("traction", side, g) for side, g in self.traction.items()] + [("body", "", self.body)])

    def sides(self):
        """``{side: ContactSide}`` of the foundation's contact sides and of both sides of every pair (for plots)."""
        return {**self.contact, **self.pairs}

    def pair_resultants(self):
        """Per contact pair (side, other side, force on the side's body, force on the other's body, their sum):
        action and reaction, the sum zero to round-off."""
        seen, result = set(), []
        for side, c in self.pairs.items():
            if side not in seen and c.partner in self.pairs:
                seen.update((side, c.partner))
                other = self.pairs[c.partner].force
                result.append((side, c.partner, c.force, other, c.force + other))
        return result

    @property
    def residual(self):
        """The sum of reactions, body force, tractions and contact forces.

        Zero to round-off (global equilibrium).
        """
        return np.sum([vector for _, _, vector in self.vectors()], axis=0)

    @property
    def scale(self):
        """The largest force of :meth:`~ngdgfric.ForceBalance.vectors` (Euclidean norm), to judge
        :attr:`~ngdgfric.ForceBalance.residual` by."""
        return max(float(np.linalg.norm(vector)) for _, _, vector in self.vectors())

    @property
    def relative_residual(self):
        """The length of :attr:`~ngdgfric.ForceBalance.residual` over :attr:`~ngdgfric.ForceBalance.scale` (0 if
        every force vanishes)."""
        scale = self.scale
        return float(np.linalg.norm(self.residual)) / scale if scale > 0 else 0.0

    def rows(self):
        """One dict per force for a CSV file: kind, side, force_x, force_y, and for contact sides normal,
        tangential, the side's length and for each zone its length, number of pieces and first and last point."""
        rows = []
        for kind, side, vector in self.vectors():
            row = dict(kind=kind, side=side, force_x=float(vector[0]), force_y=float(vector[1]))
            if kind in ("contact", "pair"):
                c = self.sides()[side]
                row.update(normal=c.normal, tangential=c.tangential, length=c.length)
                if kind == "pair":
                    row.update(partner=c.partner)
                for name in ("contact", "stick", "slip"):
                    zone = getattr(c, name)
                    start, end = zone.start or (np.nan, np.nan), zone.end or (np.nan, np.nan)
                    row.update({f"{name}_length": zone.length, f"{name}_pieces": len(zone.pieces),
                                f"{name}_start_x": start[0], f"{name}_start_y": start[1],
                                f"{name}_end_x": end[0], f"{name}_end_y": end[1]})
            rows.append(row)
        for body in self.bodies:
            residual = body.residual
            rows.append(dict(kind="residual", side=body.name, force_x=float(residual[0]), force_y=float(residual[1])))
        residual = self.residual
        rows.append(dict(kind="residual", side="", force_x=float(residual[0]), force_y=float(residual[1])))
        return rows

    def summary(self):
        """A few lines for a terminal: per side the forces and zones, then the equilibrium residual; with several
        bodies, those of each body, then each pair's action and reaction and the residual of all forces."""
        if not self.bodies:
            return self._lines()
        lines = []
        for body in self.bodies:
            lines.append(f"{body.name}:")
            lines += [f"  {line}" for line in body._lines()]
        for side, other, force, reaction, total in self.pair_resultants():
            size = max(float(np.linalg.norm(force)), float(np.linalg.norm(reaction)))
            relative = float(np.linalg.norm(total)) / size if size > 0 else 0.0
            lines.append(f"pair {side!r} / {other!r}: force on {side!r} ({force[0]:.6e}, {force[1]:.6e}), "
                         f"on {other!r} ({reaction[0]:.6e}, {reaction[1]:.6e}), sum ({total[0]:.3e}, {total[1]:.3e}), "
                         f"{relative:.1e} of the force")
        residual = self.residual
        lines.append(f"equilibrium of all bodies: sum of forces ({residual[0]:.3e}, {residual[1]:.3e}), "
                     f"{self.relative_residual:.1e} of the largest")
        return lines

    def _lines(self):
        """The lines of one body: per side the forces and zones, then the equilibrium residual."""
        lines = []
        for side, r in self.reactions.items():
            lines.append(f"{r.part} side {side!r}: reaction ({r.force[0]:.6e}, {r.force[1]:.6e})")
        for side, c in self.sides().items():
            kind = f"pair side {side!r} (with {c.partner!r})" if c.partner else f"contact side {side!r}"
            lines.append(f"{kind}: normal {c.normal:.6e}, tangential {c.tangential:.6e}, "
                         f"force ({c.force[0]:.6e}, {c.force[1]:.6e})")
            lines += [f"  {name + ' zone':12s} {_zone_text(getattr(c, name), c.length)}"
                      for name in ("contact", "stick", "slip")]
        for side, g in self.traction.items():
            lines.append(f"traction side {side!r}: load ({g[0]:.6e}, {g[1]:.6e})")
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
    r"""The forces on the body of a solution, and their balance.

    Contact resultants and zones per contact side, reactions per Dirichlet and symmetry side, the loads
    (module docstring of :mod:`ngdgfric.forces`; the zones: :mod:`ngdgfric.contact.forces`).

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve`.
    lam_tol : float, optional
        A point with :math:`|\lambda_\tau| \ge 1 - \mathtt{lam\_tol}` is at the friction bound.
        Default ``1e-6``.
    slip_tol : float, optional
        A point at the bound slips where :math:`|u_\tau| > \mathtt{slip\_tol} \max |u_h|` on :math:`\Gamma_C`.
        Default ``1e-8``.

    Returns
    -------
    ForceBalance
        The forces (:class:`~ngdgfric.ForceBalance`); their sum, :attr:`~ngdgfric.ForceBalance.residual`, is zero
        to round-off.

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> balance = ndf.force_balance(ndf.solve(problem, ndf.uniform_mesh(problem, 0.5)))
    >>> sorted(balance.contact), sorted(balance.reactions), sorted(balance.traction)
    (['contact'], ['dirichlet'], ['traction'])
    >>> balance.relative_residual < 1e-10
    True
    """
    disc = sol.discretization
    constants = constant_vectors(disc.V)
    with threads(disc.V.ndof):
        contact = contact_sides(sol, lam_tol, slip_tol, constants)
        reactions = _reactions(disc, sol.u, constants)
        traction, body_load = _loads(disc, constants)
        balance = ForceBalance(contact, reactions, traction, constants @ body_load)
        geometry = sol.problem.geometry
        if len(geometry.bodies) == 1:
            return balance
        per_body = [constant_vectors(disc.V, geometry.body_regions(k)) for k in range(len(geometry.bodies))]
        pairs = pair_sides(sol, lam_tol, slip_tol, per_body) if sol.problem.pairs else {}
    bodies = tuple(_of_body(balance, pairs, geometry, k, e @ body_load) for k, e in enumerate(per_body))
    return ForceBalance(contact, reactions, traction, balance.body, pairs, bodies)


def _of_body(balance, pairs, geometry, number, body_force):
    """The :class:`ForceBalance` of body ``number``: the forces of ``balance`` and ``pairs`` on its sides, and its
    body force."""
    def own(forces):
        return {side: value for side, value in forces.items() if geometry.body_of_side(side) == number}

    return ForceBalance(own(balance.contact), own(balance.reactions), own(balance.traction), body_force, own(pairs),
                        name=f"body {number} ({', '.join(geometry.body_regions(number))})")


def _found(problem, mesh, part):
    """The sides of a boundary part that the mesh has."""
    return [side for side in problem.sides(part) if side in mesh.GetBoundaries()]



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
    consistency, penalised = support_terms(disc.forms, u, v, part, sides=[side])
    form = ngs.BilinearForm(disc.V, nonassemble=True)
    for term in consistency + ([penalised] if penalised is not None else []):
        form += term
    return form


def _dirichlet_load(disc, side):
    """The part of the load vector that u_D carries on one Dirichlet side
    (:func:`ngdgfric.dg.forms.dirichlet_load_terms`)."""
    form = ngs.LinearForm(disc.V)
    for term in dirichlet_load_terms(disc.forms, disc.V.TestFunction(), sides=[side]):
        form += term
    form.Assemble()
    return form.vec.FV().NumPy().copy()


def _lifting_parts(disc, u, constants):
    """{side: the lifting terms of B_h(u_h, e_i) - (u_D part) on the edges of the side, an (x, y) array}.

    In the moments of :mod:`ngdgfric.dg.liftings`, (C r_e[w], r_e[v]) = m_e[v]^T S_T,ee m_e[w] and (C r_0[w],
    r_e[v]) = sum_{e' in T} m_e[v]^T S_T,ee' m_e'[w] for the boundary edge e of element T: with w = u_h - u_D and
    v = e_i, summed over the edges of the side, eta times the first (Bassi, Brezzi) and the second (Brezzi, LDG)."""
    method, problem, mesh = disc.method, disc.problem, disc.mesh
    if method.penalty != "lift" and not method.global_lift:
        return {}
    ops = liftings(problem, disc.material, mesh, disc.V, disc.orders)
    kernel = ops.kernel(disc.penalty.boundary if method.penalty == "lift" else 0.0, float(method.global_lift))
    jumps = ops.moments_of(u.vec.FV().NumPy())
    if ops.data is not None:
        jumps -= ops.data
    lifted = np.einsum("trs,ts->tr", kernel, ops.per_element(jumps))  # S_T m_T[u_h - u_D]
    tests = np.array([ops.per_element(ops.moments_of(e)) for e in constants])  # m_T[e_i]
    rows = ops.edge_rows
    parts = {}
    for side in _found(problem, mesh, "dirichlet") + _found(problem, mesh, "symmetry"):
        element, local = np.nonzero(facet_indicator(mesh, pattern([side])).vec.FV().NumPy()[ops.facets] > 0.5)
        test = np.take_along_axis(tests[:, element], rows[local][None], axis=2)  # (2, edges, 3 q)
        parts[side] = np.einsum("ier,er->i", test, np.take_along_axis(lifted[element], rows[local], axis=1))
    return parts


def _loads(disc, constants):
    """({traction side: int_S g ds}, the vector (f, v) on V_h): the load vector's terms
    (:func:`ngdgfric.dg.forms.load_terms`), the tractions at v = e_i (``constants``)."""
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
    return traction, body.vec.FV().NumPy().copy()
