r"""MARK (Section 6): Doerfler's bulk criterion, and its parameter near the tolerance.

:func:`~ngdgfric.dorfler_mark` takes the smallest set :math:`\mathcal{M}` of elements with
:math:`\sum_{T \in \mathcal{M}} \eta_T^2 \ge \theta \sum_T \eta_T^2`; the paper uses :math:`\theta = 0.3`,
:func:`~ngdgfric.adapt` 0.8 (why: :mod:`ngdgfric.adaptivity`) and, on the level before the tolerance,
``landing_theta``.
"""

import numpy as np

__all__ = ["dorfler_mark", "landing_theta", "LANDING"]


def dorfler_mark(element_indicators, theta=0.3):
    r"""Mark the smallest set of elements that carries the fraction theta of the squared estimate (Doerfler).

    The marked set :math:`\mathcal{M}` is the smallest with
    :math:`\sum_{T \in \mathcal{M}} \eta_T^2 \ge \theta \sum_T \eta_T^2` (Section 6); the largest indicators are
    taken first, ties at the threshold broken by element number.

    Parameters
    ----------
    element_indicators : array_like
        The squared indicators :math:`\eta_T^2`, one per element (``Estimate.eta_T_squared``), finite and
        nonnegative.
    theta : float, optional
        The bulk parameter :math:`\theta \in (0, 1]`.  Default ``0.3``, the paper's.

    Returns
    -------
    numpy.ndarray
        A boolean mask, one entry per element: ``True`` where marked.  All ``False`` when every indicator is 0.

    Raises
    ------
    ValueError
        ``theta`` outside :math:`(0, 1]`, or indicators that are not a 1-d array of finite nonnegative numbers.

    Examples
    --------
    >>> ndf.dorfler_mark([4.0, 1.0, 3.0, 2.0], theta=0.5)
    array([ True, False,  True, False])
    """
    if not (isinstance(theta, (int, float)) and 0 < theta <= 1):
        raise ValueError(f"theta must be in (0, 1], got {theta!r}")
    values = np.asarray(element_indicators, dtype=float)
    if values.ndim != 1 or np.any(values < 0) or not np.all(np.isfinite(values)):
        raise ValueError("element indicators must be a 1-d array of finite nonnegative numbers")
    marked = np.zeros(values.size, dtype=bool)
    total = values.sum()
    if total == 0:
        return marked
    order = np.argsort(-values, kind="stable")
    cumulative = np.cumsum(values[order])
    count = int(np.searchsorted(cumulative, theta * total * (1 - 1e-14))) + 1
    marked[order[:min(count, values.size)]] = True
    return marked



LANDING = {"residual": 0.7, "equilibrated": 0.85}
"""The fraction of the tolerance ``landing_theta`` aims the last level at, per estimator: the guaranteed bound is
within 1.1-2 of the error, so that its stop at 0.85 tol puts the error in [tol / 2, tol]."""


def landing_theta(theta, eta_h, tol, estimator="residual", reduction=1.0):
    """The Doerfler parameter of a level with estimate ``eta_h`` that has not reached ``tol``: ``theta``, but near the
    tolerance no more than the share of eta_h^2 that must go for the rest to be (LANDING tol)^2, at least 0.3 (the
    paper's): with theta = 0.8 and big hp steps (eta_h falling 3-8 times per level) the last level would
    otherwise overshoot to errors of tol/20 at the cost of the largest solve of the loop.  ``reduction``: the
    previous level's eta_h over the (1 - theta)^(1/2) eta_h this rule expected of it (hp steps fall further than
    marking alone predicts: 0.75-0.9 on Example 6.2), by which the share is corrected."""
    if tol is None:
        return theta
    return min(theta, max(0.3, 1.0 - (LANDING[estimator] * tol / (reduction * eta_h)) ** 2))

