"""Observed convergence and agreement: rates between meshes, least-squares slopes against the number of
DOFs, and the relative difference of two discrete solutions."""

import math

import numpy as np

__all__ = ["rates", "slope", "max_rel_diff"]


def rates(errors, hs):
    """Observed orders log(e_k-1 / e_k) / log(h_k-1 / h_k) (None for the first entry)."""
    out = [None]
    for k in range(1, len(errors)):
        out.append(math.log(errors[k - 1] / errors[k]) / math.log(hs[k - 1] / hs[k]))
    return out


def slope(dofs, values):
    """Least-squares slope of log ``values`` against log ``dofs`` (NaN for fewer than two points).

    An error or estimator of order h^p on shape-regular meshes in 2D falls like N^(-p/2).
    """
    n, e = np.log(dofs), np.log(values)
    return float(np.polyfit(n, e, 1)[0]) if len(n) > 1 else math.nan


def max_rel_diff(a, b):
    """max |u_a - u_b| / max |u_b| over the DOFs of two Solutions ``a``, ``b`` on the same space."""
    a, b = a.u.vec.FV().NumPy(), b.u.vec.FV().NumPy()
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))
