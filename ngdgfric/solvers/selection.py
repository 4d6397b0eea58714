r"""One set of contact forces where the laws leave several: the smallest friction traction with the same effect on u.

Where the rows of :math:`B` of an element are dependent (``ContactTraces.redundant``: on hp meshes an element of
degree :math:`p_T` with :math:`q = p + 1 > p_T + 1` Gauss points on its contact edge, or an element with two edges on
:math:`\Gamma_C`), the displacement is unique but the forces are not.  The normal forces are (:math:`f_n = N(w_n)`
at every point), and so are the tangential ones where the point slips (:math:`f_t = \pm\beta`); at the sticking
points :math:`Z` (:math:`w_t = 0`, :math:`|f_t| \le \beta`, the points at the bound that do not slip included,
``ZERO_SLIP``) any :math:`f_Z` with the same :math:`B_Z^T f_Z`
solves (3.3)-(3.4).  The multiplier :math:`\lambda_\tau = f_t / \beta` enters :math:`\eta_4` (Section 4), so without
a rule :math:`\eta_h` would depend on the path of the solver (measured on the rubber pad's hp levels: 1.17e-3,
6.6e-3 and 1.07e-2 at one level for three starting points).

The rule (``select``): among the forces of a solution, the sticking tangential forces of each group of elements
coupled through their rows of :math:`B` are replaced by those of least traction norm
:math:`\sum_{q \in Z} f_q^2 / \omega_q = \int_Z t^2` (Gauss rule) with the same :math:`B_Z^T f_Z`,

.. math::

    f_Z \leftarrow \Omega^{1/2} P\, \Omega^{-1/2} f_Z, \qquad P \text{ the orthogonal projection onto the range of }
    \Omega^{1/2} B_Z

(the traction becomes the trace of a polynomial of the element's own degree), unless that passes the bound
:math:`|f_t| \le \beta` somewhere in the group, which then keeps its forces.  :math:`B^T f`, so :math:`u` and the
traces, are unchanged; the laws still hold.  Only the foundation's points are treated (a contact pair's points are
redundant by construction and carry their own multiplier).
"""

import numpy as np

__all__ = ["select", "RANK_TOLERANCE", "ZERO_SLIP"]

ZERO_SLIP = 1e-10
"""A point belongs to Z where it sticks by the law's test or where its slip |w_t| is at most this times the largest
trace: a point at the bound |f_t| = beta that does not move (stick and slip both hold) is free to leave the bound."""

RANK_TOLERANCE = 1e-10
"""Singular values of Omega^(1/2) B_Z below this times the largest count as zero (the rank of a group's rows)."""


def _groups(rows, cols):
    """A label per entry of the COO pattern (rows, cols): entries whose rows are connected through shared columns
    share the smallest row index of their component (min-label propagation)."""
    label = rows.copy()
    while True:
        column_label = np.full(cols.max() + 1, np.iinfo(np.int64).max)
        np.minimum.at(column_label, cols, label)
        row_label = np.full(rows.max() + 1, np.iinfo(np.int64).max)
        np.minimum.at(row_label, rows, column_label[cols])
        new = row_label[rows]
        if np.array_equal(new, label):
            return label
        label = new


def select(traces, f, state):
    """The forces f (length 2 M, ``ContactTraces`` ``traces`` order) with the sticking tangential forces of the
    foundation's points replaced by the least-norm ones of the module docstring; ``state``: the
    :class:`~ngdgfric.solvers.reduced.PointState` of the laws at f (its ``stick`` and ``beta``).  f itself where the
    points are not redundant or none sticks (the same object, so that a caller can tell)."""
    if not traces.redundant:
        return f
    M, foundation = traces.M, traces.foundation
    slip = np.abs(state.w[M:]) / max(float(np.max(np.abs(state.w), initial=0.0)), np.finfo(float).tiny)
    points = np.flatnonzero((state.stick | (slip <= ZERO_SLIP))[:foundation])
    if points.size == 0:
        return f
    chosen = np.isin(traces.rows, M + points)
    rows, cols, values = traces.rows[chosen], traces.cols[chosen], traces.values[chosen]
    labels = _groups(rows, cols)
    order = np.argsort(labels, kind="stable")  # the entries group by group
    starts = np.flatnonzero(np.diff(labels[order], prepend=-1))
    out = f.copy()
    for mine in np.split(order, starts[1:]):
        group_rows, row_index = np.unique(rows[mine], return_inverse=True)
        group_cols, col_index = np.unique(cols[mine], return_inverse=True)
        if group_rows.size <= 1:
            continue
        weight = np.sqrt(traces.omega[group_rows - M])
        matrix = np.zeros((group_rows.size, group_cols.size))
        matrix[row_index, col_index] = values[mine]
        U, singular, _ = np.linalg.svd(weight[:, None] * matrix, full_matrices=False)
        basis = U[:, singular > RANK_TOLERANCE * singular[0]]
        if basis.shape[1] == group_rows.size:
            continue  # independent rows: the forces are unique already
        scaled = f[group_rows] / weight
        selected = weight * (basis @ (basis.T @ scaled))
        if np.all(np.abs(selected) <= state.beta[group_rows - M]):
            out[group_rows] = selected
    return out
