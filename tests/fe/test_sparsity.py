"""Node sparsity pattern and scatter: the pattern is the node graph of the mesh, slots point at
each element pair, and block/diagonal CSR matrices equal a brute-force dense assembly."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import TetMesh
from flexarm.fe.sparsity import NodePattern, scatter_add


def _shuffled(order: int) -> TetMesh:
    """A box with its nodes renumbered at random (rows of the pattern are then unsorted)."""
    mesh = TetMesh.box((1.0, 0.6, 0.4), (3, 2, 1), order=order)
    perm = np.random.default_rng(order).permutation(mesh.n_nodes)
    inv = np.argsort(perm)
    return TetMesh(mesh.points[perm], inv[mesh.tets])


@pytest.fixture(params=[1, 2], ids=["tet4", "tet10"])
def mesh(request):
    return _shuffled(request.param)


def test_pattern_is_the_node_graph(mesh):
    pat = NodePattern.of(mesh)
    n = mesh.n_nodes
    adjacency = np.zeros((n, n), dtype=bool)
    for t in mesh.tets:
        adjacency[np.ix_(t, t)] = True
    assert pat.n_nodes == n and pat.nnz_blocks == int(adjacency.sum())
    for r in range(n):
        cols = pat.indices[pat.indptr[r]:pat.indptr[r + 1]]
        np.testing.assert_array_equal(cols, np.flatnonzero(adjacency[r]))  # sorted, unique


def test_slots_point_at_each_element_pair(mesh):
    pat = NodePattern.of(mesh)
    nn = mesh.tets.shape[1]
    assert pat.slots.shape == (mesh.n_tets, nn, nn)
    rows = np.broadcast_to(mesh.tets[:, :, None], pat.slots.shape)
    cols = np.broadcast_to(mesh.tets[:, None, :], pat.slots.shape)
    np.testing.assert_array_equal(pat.indices[pat.slots], cols)
    assert np.all(pat.slots >= pat.indptr[rows]) and np.all(pat.slots < pat.indptr[rows + 1])


def test_block_matrices_equal_dense_assembly(mesh):
    pat = NodePattern.of(mesh)
    nn, n = mesh.tets.shape[1], mesh.n_nodes
    rng = np.random.default_rng(5)
    Ke = rng.normal(size=(mesh.n_tets, nn, nn, 3, 3))
    me = rng.normal(size=(mesh.n_tets, nn, nn))
    dense_K, dense_M = np.zeros((n, 3, n, 3)), np.zeros((n, n))
    for e, t in enumerate(mesh.tets):
        for a in range(nn):
            for b in range(nn):
                dense_K[t[a], :, t[b], :] += Ke[e, a, b]
                dense_M[t[a], t[b]] += me[e, a, b]
    half = mesh.n_tets // 2  # two chunks, summed in place
    blocks = pat.scatter(Ke[:half], slice(0, half)) + pat.scatter(Ke[half:], slice(half, None))
    K = pat.block_matrix(blocks)
    M = pat.diagonal_block_matrix(pat.scatter(me, slice(None))[:, 0])
    assert K.has_canonical_format and M.has_canonical_format
    np.testing.assert_allclose(K.toarray(), dense_K.reshape(3 * n, 3 * n), atol=1e-12)
    np.testing.assert_allclose(M.toarray(), np.kron(dense_M, np.eye(3)), atol=1e-12)
    assert M.nnz == 3 * pat.nnz_blocks and K.nnz == 9 * pat.nnz_blocks
    # deterministic: a second pattern and scatter give the same bits
    again = NodePattern.of(mesh)
    np.testing.assert_array_equal(again.slots, pat.slots)
    K2 = again.block_matrix(again.scatter(Ke, slice(None)))
    np.testing.assert_array_equal(K2.data, pat.block_matrix(pat.scatter(Ke, slice(None))).data)


def test_scatter_add_in_order_with_repeated_rows():
    out = np.zeros((4, 2))
    rows = np.array([2, 0, 2, 2], dtype=np.int64)
    vals = np.array([[1.0, 10.0], [2.0, 20.0], [3.0, 30.0], [4.0, 40.0]])
    scatter_add(out, rows, vals)
    scatter_add(out, rows[:1], vals[:1])
    np.testing.assert_array_equal(out, [[2, 20], [0, 0], [9, 90], [0, 0]])
