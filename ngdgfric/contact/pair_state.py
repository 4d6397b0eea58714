r"""The state of a solution at the points of its contact pairs (:class:`~ngdgfric.ContactPair`, two bodies).

At the points :math:`x_k` of a pair's side (:mod:`ngdgfric.contact.pairing`), with :math:`n, t` the outward normal
and the tangent of the pair's side and :math:`\pi(x_k)` the closest point of the other side, the rows of :math:`B`
(:mod:`ngdgfric.contact.pair_traces`) give the jump :math:`[u] = u^1(x_k) - u^2(\pi(x_k))`:
:math:`[u]_n = [u] \cdot n`, :math:`[u]_\tau = [u] \cdot t`.  The compliance law (1.8) and the friction law (1.9)
hold there as on the foundation, with the pair's gap :math:`g` (geometric gap plus the pair's ``g_a``):

.. math::

    f_{n,k} = \omega_k c_n ([u]_n - g)_+^{m_n}, \qquad f_{t,k} = \omega_k \beta_k \lambda_{\tau,k}, \qquad
    \beta_k = c_\tau ([u]_n - g)_+^{m_t} \ (c_\tau \text{ for } m_t = 0),

and the forces act on the pair's side as :math:`-(f_n n + f_t t)` and on the other side as
:math:`+(f_n n + f_t t)` (:math:`B^T f` is action and reaction).  The solvers return :math:`f` and
:math:`\lambda_\tau` at these points (``sol.info["pair_forces"]``, ``sol.info["pair_multiplier"]``);
``pair_law_term`` evaluates the laws at :math:`u_h` instead, for the equilibrium residual of
:func:`ngdgfric.kkt_residuals`.
"""

import numpy as np

from .laws import bound_rate, law_forces

__all__ = ["pair_state", "pair_law_term", "PAIR_STATE_KEYS"]

PAIR_STATE_KEYS = ("x", "y", "other_x", "other_y", "weight", "gap", "jump_n", "jump_tau", "penetration", "f_n", "f_t",
                   "pressure", "lam_tau", "bound")
"""The arrays of each pair's entry of :func:`pair_state`."""


def _slices(contact):
    """(pair, PairPoints, normal rows, tangential rows) of every pair of ``contact.pairs``: the pairs' points follow
    the foundation's in the rows of B (:class:`~ngdgfric.contact.traces.ContactTraces`)."""
    traces = contact.traces
    start = traces.foundation
    for pair, points, _ in contact.pairs:
        yield pair, points, slice(start, start + points.M), slice(traces.M + start, traces.M + start + points.M)
        start += points.M


def pair_state(sol):
    r"""The state of a solution at the points of each contact pair.

    Parameters
    ----------
    sol : Solution
        A solution of :func:`ngdgfric.solve` of a problem with contact pairs.

    Returns
    -------
    list of dict of str to numpy.ndarray
        One dict per pair of ``sol.problem.pairs``, in that order, with one array over the pair's points each (the
        points of ``Contact(...).pairs``, in the order of ``sol.info["pair_forces"]``):

        - ``x``, ``y``: the points on the pair's side; ``other_x``, ``other_y``: their closest points on the other
          side;
        - ``weight``: :math:`\omega_k`, the Gauss weight times the length of the piece;
        - ``gap``: the pair's gap :math:`g` (geometric gap plus ``g_a``);
        - ``jump_n``, ``jump_tau``: :math:`[u_h]_n`, :math:`[u_h]_\tau` (module docstring);
        - ``penetration``: :math:`[u_h]_n - g` (positive in contact);
        - ``f_n``, ``f_t``: the solver's forces at the points (``sol.info["pair_forces"]``);
        - ``pressure``: :math:`f_n / \omega`, the normal traction;
        - ``lam_tau``: the multiplier (``sol.info["pair_multiplier"]``);
        - ``bound``: the friction bound :math:`c_\tau ([u_h]_n - g)_+^{m_t}` (:math:`c_\tau` for :math:`m_t = 0`).

    Examples
    --------
    >>> lower = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "right1", "c1", "left1"])
    >>> upper = ndf.Loop([(0, 1), (1, 1), (1, 1.5), (0, 1.5)], ["c2", "right2", "top", "left2"])
    >>> problem = ndf.ContactProblem(
    ...     E=1.0, nu=0.3, f=(0, 0), g={"top": (0, -0.01)}, c_n=0.0, m_n=1.0, g_a=0.0, c_tau=0.0,
    ...     geometry=ndf.Domain({"lower": lower, "upper": upper}), symmetry=("bottom", "left1", "left2"),
    ...     dirichlet=(), traction=("right1", "right2", "top"), contact=(),
    ...     pairs=[ndf.ContactPair("c2", "c1", c_n=50.0)])
    >>> state, = ndf.pair_state(ndf.solve(problem, ndf.netgen_mesh(problem, 0.5)))
    >>> bool(abs(state["pressure"] - 0.01).max() < 1e-12)
    True
    """
    traces = sol.contact.traces
    w = traces.apply(sol.u.vec.FV().NumPy())
    forces = np.asarray(sol.info["pair_forces"])
    multiplier = np.asarray(sol.info["pair_multiplier"])
    states, start = [], 0
    for pair, points, normal, tangential in _slices(sol.contact):
        f_n, f_t = forces[0, start:start + points.M], forces[1, start:start + points.M]
        penetration = w[normal] - points.gap
        states.append({
            "x": points.xy[:, 0], "y": points.xy[:, 1], "other_x": points.other_xy[:, 0],
            "other_y": points.other_xy[:, 1], "weight": points.weight, "gap": points.gap, "jump_n": w[normal],
            "jump_tau": w[tangential], "penetration": penetration, "f_n": f_n, "f_t": f_t,
            "pressure": f_n / points.weight, "lam_tau": multiplier[start:start + points.M],
            "bound": bound_rate(penetration, pair.c_tau, pair.m_t)[0] * np.ones(points.M)})
        start += points.M
    return states


def pair_law_term(contact, u, lam_tau):
    r""":math:`B^T f` over the pairs' points of a :class:`~ngdgfric.Contact`, the forces :math:`f` of the laws
    (``law_forces`` of :mod:`ngdgfric.contact.laws`, with the pairs' data of the traces) at the traces of the
    coefficient vector ``u`` (numpy) and the pairs' multiplier values ``lam_tau``: the pairs' term of the residual of
    (3.3), a vector on :math:`V_h` (numpy)."""
    traces = contact.traces
    start = traces.foundation
    f = law_forces(traces, traces.apply(u), np.concatenate([np.zeros(start), lam_tau]))
    f[:start] = f[traces.M:traces.M + start] = 0.0  # the foundation's points: the forms' own terms
    return traces.apply_transpose(f)
