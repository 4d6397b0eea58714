"""Element blocks of V_h and of its matrices (ngdgfric.dg.blocks): the positions computed from the element layout
are those of NGSolve's own entries."""

import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.dg.blocks import ElementBlocks, Pattern, neighbours
from ngdgfric.dg.moments import liftings


@pytest.fixture(scope="module")
def hp():
    """A DG matrix with degrees 1..4 per element on a bisected Netgen mesh, its blocks and the elements' edges."""
    p = ndf.example_6_1()
    mesh = ndf.netgen_mesh(p, 0.4)
    ndf.meshes.refine(mesh, np.arange(mesh.ne) % 2 == 0)
    orders = np.random.default_rng(5).integers(1, 5, size=mesh.ne)
    disc = ndf.Discretization(p, mesh, method="sipg", order=orders)
    facets = liftings(disc.problem, disc.material, mesh, disc.V, orders).facets
    return disc, ElementBlocks.of(orders, disc.V.ndof), neighbours(facets)[0]


def test_the_blocks_of_element_pairs_are_the_matrix_entries_of_their_dofs(hp):
    disc, blocks, other = hp
    pattern = Pattern.of(disc.A, blocks, other)
    dense = disc.A.ToDense().NumPy()
    rows = np.repeat(np.arange(len(other)), 4)
    cols = np.column_stack([np.arange(len(other)), other]).ravel()
    keep = cols >= 0
    for r, c in zip(rows[keep], cols[keep], strict=True):
        n, m = blocks.sizes[r], blocks.sizes[c]
        block = pattern.gather(np.array([r]), np.array([c]), n, m)[0]
        assert np.array_equal(block, dense[np.ix_(blocks.dofs(np.array([r]), n)[0], blocks.dofs(np.array([c]), m)[0])])


def test_neighbours_are_mutual_and_share_the_edge(hp):
    _, _, other = hp
    element, local = np.nonzero(other >= 0)
    assert np.all(np.any(other[other[element, local]] == element[:, None], axis=1))


def test_a_pattern_other_than_the_matrix_is_refused(hp):
    disc, blocks, other = hp
    with pytest.raises(RuntimeError, match="do not hold the element blocks"):
        Pattern.build(disc.A, np.arange(len(other) + 1), np.arange(len(other)), blocks)  # each element alone
    two = Pattern.two_ring(blocks, other)
    with pytest.raises(RuntimeError, match="outside the matrix's pattern"):
        far = np.flatnonzero(~np.isin(np.arange(len(other)), two.ring[two.ring_ptr[0]:two.ring_ptr[1]]))[0]
        two.positions(np.array([0]), np.array([far]), blocks.sizes[0], blocks.sizes[far])
