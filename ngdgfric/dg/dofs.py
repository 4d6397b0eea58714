r"""The size of the DG space :math:`V_h` of Section 3: vector polynomials of degree :math:`p_T` on each triangle.

A triangle :math:`T` of degree :math:`p` carries :math:`(p + 1)(p + 2) / 2` scalar basis functions per component,
so :math:`\dim V_h = \sum_T (p_T + 1)(p_T + 2)`.  Everything that counts DOFs before a space exists (the size
checks, the hp state, the coefficient layout of ``copy_orders`` in :mod:`ngdgfric.transfer`, studies that stop at
a number of DOFs) counts them here.
"""

import numpy as np

__all__ = ["element_dofs", "dg_ndof"]


def element_dofs(orders):
    """n_T = (p_T + 1)(p_T + 2), the DOFs of each element of degree ``orders`` (a number or an array; two
    components of n_T / 2 each)."""
    p = np.asarray(orders)
    return (p + 1) * (p + 2)


def dg_ndof(orders, elements=1):
    """dim V_h = sum_T (p_T + 1)(p_T + 2) for element degrees ``orders`` (or ``elements`` elements of the one
    degree ``orders``)."""
    return int(np.sum(element_dofs(orders))) * int(elements)
