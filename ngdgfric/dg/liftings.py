r"""Lifting operators :math:`r_e` and :math:`r_0` (Arnold, Brezzi, Cockburn, Marini 2002) for the lifting methods.

The methods :math:`B_h^{(3)}`, :math:`B_h^{(4)}` and :math:`B_h^{(5)}` use them, edge by edge.  For a symmetric
tensor :math:`\phi` on an edge :math:`e \in \mathcal{E}_h^o`, :math:`r_e(\phi) \in \Sigma_h` is defined by

.. math::

    \int_\Omega r_e(\phi) : \tau \, dx = - \int_e \phi : \{\!\{\tau\}\!\} \, ds
    \qquad \text{for all } \tau \in \Sigma_h,

and :math:`r_0 = \sum_{e \in \mathcal{E}_h^o} r_e`.  :math:`\Sigma_h`: discontinuous symmetric :math:`2 \times 2`
tensors of degree :math:`p` (the largest order of :math:`V_h`).  It contains :math:`\varepsilon_h(V_h)`, as ABCM
require; degree :math:`p` rather than :math:`p - 1` because the jumps :math:`[\![v]\!]` of :math:`V_h` are of
degree :math:`p` on the edges, and only then is :math:`r_e` injective on them
(:math:`\|r_e([\![v]\!])\| \sim h_e^{-1/2} \|[\![v]\!]\|_e`), so that the local lifting penalty of Bassi et al.
controls every jump.  With a varying material :math:`\{\!\{\tau\}\!\} = w^+ \tau^+ + w^- \tau^-` is the weighted
average of :mod:`ngdgfric.dg.material` and :math:`C` is each element's own.  On symmetry sides the lifting sees
the normal part :math:`(u \cdot n)\, n` of :math:`u` (``normal_part`` of :mod:`ngdgfric.dg.forms`).

:math:`r_e` lives on the (one or two) elements of :math:`e`, and on an element :math:`T` it depends on
:math:`[\![u]\!]` only through its moments :math:`m_e = (\int_e [\![u]\!]_c \psi_a \, ds)` against a basis
:math:`\psi_0, \dots, \psi_p` of polynomials of degree :math:`p` on :math:`e`, :math:`c = xx, yy, xy`: the traces
on :math:`e` of the scalar basis :math:`\phi_k` of :math:`\Sigma_h(T)` lie in their span (on a curved edge too:
both are polynomials of the edge's reference coordinate),
:math:`\phi_k = \sum_a (E_T N_e^{-1})_{ka} \psi_a` with :math:`E_T = (\int_e w_T \phi_k \psi_a)` and
:math:`N_e = (\int_e \psi_a \psi_b)`, so

.. math::

    (C r_e([\![u]\!]), r_e([\![v]\!]))_T = m_e[u]^T S_{T,ee}\, m_e[v], \qquad
    S_T = (E_T N^{-1})^T M_T^{-1} M_T^C M_T^{-1} (E_T N^{-1}),

with :math:`M_T` the mass matrix of :math:`\Sigma_h(T)` and :math:`M_T^C` that of :math:`(C \sigma, \tau)`:
:math:`S_T` is a small kernel on the moments of :math:`T`'s three edges (:math:`3 (p + 1)` per edge and component;
:math:`2 \mu` and :math:`\lambda` in two scalar kernels), and
:math:`(C r_0([\![u]\!]), r_0([\![v]\!]))_T = \sum_{e, e' \in T} m_e[u]^T S_{T,ee'}\, m_{e'}[v]`.  With a weight
:math:`w_T` that varies along a curved interface (a material that varies inside its elements) the moments are
the quadrature-free projection of :math:`w_T \phi_k` onto polynomials of degree :math:`p` on :math:`e`.

Assembly (``lifting_terms``), no loop over edges or elements: NGSolve assembles the moment matrix
(element-boundary integrals of :math:`\operatorname{sym}(u \otimes n)` against a facet space of degree :math:`p`,
both sides of an edge adding up to the jump) and the small matrices :math:`E, N, M, M^C`; numpy forms the kernels
element by element and the local matrices :math:`b^T S b` edge by edge (Bassi et al.) or element by element over
the element and its neighbours (the global lifting of Brezzi et al. and LDG, whose stencil reaches the neighbours'
neighbours), batched by block size, and adds them into the matrix by positions computed from the element blocks of
its rows (:mod:`ngdgfric.dg.blocks`).  The operators are built by :mod:`ngdgfric.dg.moments`.
"""

import numpy as np

from ..threads import threads
from .blocks import Pattern, neighbours
from .moments import csr, liftings

__all__ = ["lifting_terms"]


def lifting_terms(context, V, orders, A):
    """B_h's matrix ``A`` with the lifting terms of ``context.method`` added, and the load vector they give a
    prescribed displacement u_D (a numpy array; None if u_D = 0 or the method has no liftings): (matrix, load).

    ``context``: the ``FormsContext`` of :mod:`ngdgfric.dg.forms` (data, material, method; eta is
    ``context.penalty.boundary``); ``V``: V_h; ``orders``: the degree of every element of V_h (Sigma_h has the
    largest).  Bassi et al. (B_h^(3)): eta sum_e (C r_e, r_e), edge by edge into the pattern of ``A`` (whose values
    change: it is returned); Brezzi et al. (B_h^(4)): that plus (C r_0, r_0), and LDG (B_h^(5)): (C r_0, r_0),
    element by element into a new matrix whose stencil reaches the neighbours' neighbours, with ``A`` added.  With
    [u] = u - u_D on Gamma_D, (C r_e[u], r_e[v]) = m[v]^T S (m[u] - m[u_D]), so u_D adds m[v]^T S m[u_D] to the
    right-hand side.
    """
    method = context.method
    if method.penalty != "lift" and not method.global_lift:
        return A, None
    ops = liftings(context.problem, context.material, context.mesh, V, orders)
    local = context.penalty.boundary if method.penalty == "lift" else 0.0
    other, across = neighbours(ops.facets)
    with threads(V.ndof):
        sides = _side_moments(ops, other)
        if not method.global_lift:
            pattern = Pattern.of(A, ops.blocks, other)
            load = _edge_terms(ops, ops.kernel(local, 0.0), sides, other, across, pattern)
            return pattern.matrix, load
        pattern = Pattern.two_ring(ops.blocks, other)
        _add_matrix(pattern, Pattern.of(A, ops.blocks, other))
        return pattern.matrix, _element_terms(ops, ops.kernel(local, 1.0), sides, other, across, pattern)


class _Store:
    """Dense blocks of varying size stored by size: ``groups`` {n: (indices, blocks (count, ..., 2 n))} over a flat
    index space of ``count`` entries (half-edges 3 T + j, elements, or element-edge pairs)."""

    def __init__(self, groups, count):
        self.groups = groups
        self.where = np.zeros(count, dtype=np.int64)
        for indices, _ in groups.values():
            self.where[indices] = np.arange(len(indices))

    def get(self, indices, n):
        """The blocks of ``indices``, all of size ``n``."""
        return self.groups[n][1][self.where[indices]]


def _side_moments(ops, other):
    """The moment blocks b of every element T on each of its edges j, a :class:`_Store` over the half-edges
    3 T + j: (3 q, 2 n_T) each (rows: component xx, yy, xy and a; columns: T's DOFs of component 0, then 1), from the
    rows of B, where an edge's elements have their blocks of each component (the element of lower number first)."""
    values, _, rowptr = csr(ops.moments, None, "B")
    q, sizes = ops.q, ops.blocks.sizes
    ne = len(ops.facets)
    element, facet, opposite = np.repeat(np.arange(ne), 3), ops.facets.ravel(), other.ravel()
    own, far = sizes[element], np.where(opposite >= 0, sizes[np.maximum(opposite, 0)], 0)
    first = np.where((opposite >= 0) & (opposite < element), far, 0)
    half = own + far
    component_rows = (np.arange(3)[:, None] * (ops.moments.height // 3) + np.arange(q)[None, :]).ravel()
    rows = facet[:, None] * q + component_rows[None, :]  # (3 ne, 3 q)
    if not np.array_equal(np.diff(rowptr)[rows], np.broadcast_to(2 * half[:, None], rows.shape)):
        raise RuntimeError("the rows of the moment matrix do not hold the blocks of their edge's elements")
    groups = {}
    for chosen, (n,) in _by_size(own):
        local = np.arange(n)[None, :]
        columns = np.concatenate([first[chosen][:, None] + local, (half + first)[chosen][:, None] + local], axis=1)
        groups[n] = (chosen, values[rowptr[rows[chosen]][:, :, None] + columns[:, None, :]])
    return _Store(groups, 3 * ne)


def _by_size(*sizes):
    """(indices, key) for the groups of equal entries of the arrays ``sizes`` (key: their values)."""
    keys = np.stack(sizes, axis=1)
    unique, inverse = np.unique(keys, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    for k, key in enumerate(unique):
        yield np.flatnonzero(inverse == k), tuple(int(x) for x in key)


def _transposed(blocks):
    return np.swapaxes(blocks, 1, 2)


def _edge_blocks(ops, kernel):
    """The diagonal edge blocks of the kernels, (ne, 3, 3 q, 3 q): rows and columns (component, a)."""
    rows = ops.edge_rows
    return np.stack([kernel[:, rows[j][:, None], rows[j][None, :]] for j in range(3)], axis=1)


def _edge_terms(ops, kernel, sides, other, across, pattern):
    """Bassi et al.: b_R^T S_e b_S for the sides R, S of every edge e of E_h^o (S_e: the two elements' kernels on
    e), added into ``pattern``'s matrix, element by element for R = S (sum over the element's edges) and edge by
    edge for R != S; returns the load of u_D (sum_e b_R^T S_e m_e[u_D])."""
    sizes = ops.blocks.sizes
    blocks = _edge_blocks(ops, kernel)  # (ne, 3, 3 q, 3 q)
    inner = other >= 0
    edge_kernel = blocks.copy()
    edge_kernel[inner] += blocks[other[inner], across[inner]]
    weighted = {}
    for chosen, (n,) in _by_size(sizes):
        b = sides.get(3 * chosen[:, None] + np.arange(3), n)  # (count, 3, 3 q, 2 n)
        product = edge_kernel[chosen] @ b
        weighted[n] = (chosen, product)
        flat = b.reshape(len(chosen), -1, 2 * n)
        pattern.add(chosen, chosen, _transposed(flat) @ product.reshape(flat.shape))
    weighted = _Store(weighted, len(sizes))
    element, local = np.nonzero(inner & (other > np.arange(len(sizes))[:, None]))  # each inner edge once
    neighbour = other[element, local]
    for chosen, (n, m) in _by_size(sizes[element], sizes[neighbour]):
        t, j = element[chosen], local[chosen]
        product = weighted.get(t, n)[np.arange(len(t)), j]  # S_e b_T (count, 3 q, 2 n)
        block = _transposed(sides.get(3 * neighbour[chosen] + across[t, j], m)) @ product  # (count, 2 m, 2 n)
        pattern.add(neighbour[chosen], t, block)
        pattern.add(t, neighbour[chosen], _transposed(block))
    if ops.data is None:
        return None
    load = np.zeros(2 * ops.blocks.stride)
    data = _edge_data(ops)[ops.facets]  # (ne, 3, 3 q)
    for chosen, (n,) in _by_size(sizes):
        np.add.at(load, ops.blocks.dofs(chosen, n), np.einsum("tjra,tjr->ta", weighted.get(chosen, n),
                                                              data[chosen]))
    return load


def _edge_data(ops):
    """m[u_D] per edge, (facets, 3 q): rows (component, a)."""
    return np.moveaxis(ops.data, 0, 1).reshape(ops.data.shape[1], -1)


def _element_terms(ops, kernel, sides, other, across, pattern):
    """The global lifting, with Brezzi et al.'s local one folded into ``kernel``: for every element T, U_P^T S_T U_P'
    for P, P' among T itself (U_T: T's moment blocks on its three edges) and its neighbours (U: the neighbour's block
    on the edge it shares with T, in that edge's kernel rows), added into ``pattern``'s matrix; returns the load of
    u_D (sum_T U_P^T S_T m_T[u_D])."""
    q, sizes, ne = ops.q, ops.blocks.sizes, len(ops.facets)
    rows = ops.edge_rows
    own = {}  # U_T (9 q, 2 n_T) by element, rows (component, j, a)
    for chosen, (n,) in _by_size(sizes):
        u = sides.get(3 * chosen[:, None] + np.arange(3), n).reshape(len(chosen), 3, 3, q, 2 * n)
        own[n] = (chosen, u.transpose(0, 2, 1, 3, 4).reshape(len(chosen), 9 * q, 2 * n))
    own = _Store(own, ne)
    for chosen, (n,) in _by_size(sizes):
        u = own.get(chosen, n)
        pattern.add(chosen, chosen, _transposed(u) @ (kernel[chosen] @ u))
    element, local = np.nonzero(other >= 0)  # the pairs (T, j) with a neighbour across edge j
    neighbour, mirror = other[element, local], 3 * other[element, local] + across[element, local]
    far = {}  # S_T[:, rows j] b of the neighbour, by pair
    for chosen, (m,) in _by_size(sizes[neighbour]):
        columns = kernel[element[chosen][:, None], :, rows[local[chosen]]]  # (count, 3 q, 9 q)
        far[m] = (chosen, _transposed(columns) @ sides.get(mirror[chosen], m))
    far = _Store(far, len(element))
    for chosen, (n, m) in _by_size(sizes[element], sizes[neighbour]):
        block = _transposed(own.get(element[chosen], n)) @ far.get(chosen, m)
        pattern.add(element[chosen], neighbour[chosen], block)
        pattern.add(neighbour[chosen], element[chosen], _transposed(block))
    pair_of = np.full((ne, 3), -1)
    pair_of[element, local] = np.arange(len(element))
    first, second = (x.ravel() for x in np.meshgrid(np.arange(len(element)), np.arange(3), indexing="ij"))
    second = pair_of[element[first], second]  # pairs (T, i), (T, j) of one element, both with a neighbour
    keep = second >= 0
    first, second = first[keep], second[keep]
    for chosen, (n, m) in _by_size(sizes[neighbour[first]], sizes[neighbour[second]]):
        a, b = first[chosen], second[chosen]
        product = np.take_along_axis(far.get(b, m), rows[local[a]][:, :, None], axis=1)  # (count, 3 q, 2 m)
        pattern.add(neighbour[a], neighbour[b], _transposed(sides.get(mirror[a], n)) @ product)
    if ops.data is None:
        return None
    return _element_load(ops, kernel, sides, own, element, local, neighbour, mirror, rows)


def _element_load(ops, kernel, sides, own, element, local, neighbour, mirror, rows):
    """sum_T U_P^T S_T m_T[u_D] (:func:`_element_terms`) as a vector on V_h."""
    sizes = ops.blocks.sizes
    lifted = np.einsum("trs,ts->tr", kernel, ops.per_element(ops.data))  # S_T m_T, rows (component, j, a)
    load = np.zeros(2 * ops.blocks.stride)
    for chosen, (n,) in _by_size(sizes):
        np.add.at(load, ops.blocks.dofs(chosen, n), np.einsum("tra,tr->ta", own.get(chosen, n), lifted[chosen]))
    for chosen, (m,) in _by_size(sizes[neighbour]):
        part = np.take_along_axis(lifted[element[chosen]], rows[local[chosen]], axis=1)  # (count, 3 q)
        np.add.at(load, ops.blocks.dofs(neighbour[chosen], m),
                  np.einsum("hra,hr->ha", sides.get(mirror[chosen], m), part))
    return load


def _add_matrix(target, source):
    """Add the matrix of the pattern ``source`` into that of ``target`` (whose rings contain source's), block by
    block."""
    sizes = source.blocks.sizes
    rows = np.repeat(np.arange(len(sizes)), np.diff(source.ring_ptr))
    for chosen, (n, m) in _by_size(sizes[rows], sizes[source.ring]):
        target.add(rows[chosen], source.ring[chosen], source.gather(rows[chosen], source.ring[chosen], n, m))
