"""Node-level sparsity pattern of a tet mesh and the scatter into CSR.

The pattern is computed once per mesh at *node* level (one 3x3 block per node pair,
:class:`NodePattern`: node pairs bucketed by row with a counting sort, then each short
row sorted).  Element values are scatter-added into the pattern slots in place; the slots
are in node-level CSR order, so K's 3x3 blocks form a BSR matrix that SciPy's compiled
pass turns into CSR, and M's DOF rows are its node rows taken three times.  The matrices
come out with sorted indices and no duplicates.  DOF index is
``3*node + component``.  Every sum runs in a fixed order: the result is deterministic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .mesh import TetMesh

__all__ = ["NodePattern", "scatter_add", "touched_zeros"]


try:  # in-place scatter-add (SciPy's compiled CSC mat-vec kernel); see scatter_add
    from scipy.sparse._sparsetools import csc_matvecs as _csc_matvecs
except ImportError:  # pragma: no cover - private SciPy API moved
    _csc_matvecs = None


def scatter_add(out: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """``out[rows[k]] += values[k]`` for k in order (rows repeat), in place.

    ``out`` (N, v) and ``values`` (L, v) are C-contiguous float64.  A 0/1 CSC matrix with
    one entry per column is a scatter-add; SciPy's kernel ``csc_matvecs`` adds it into
    ``out`` directly, so no (N, v) temporary is made per chunk.
    """
    assert out.flags.c_contiguous and out.dtype == np.float64  # reshape must be a view
    n_rows, n_vec = out.shape
    L = len(rows)
    ptr = np.arange(L + 1, dtype=rows.dtype)
    if _csc_matvecs is not None:
        _csc_matvecs(n_rows, L, n_vec, ptr, rows, np.ones(L), values.reshape(-1), out.reshape(-1))
    else:  # pragma: no cover
        out += sp.csc_matrix((np.ones(L), rows, ptr), shape=(n_rows, L)) @ values


def _index_dtype(*sizes: int):
    return np.int32 if max(sizes, default=0) < np.iinfo(np.int32).max else np.int64


@dataclass(frozen=True, eq=False)
class NodePattern:
    """Node-level sparsity pattern of a mesh, shared by K and M.

    Attributes
    ----------
    indptr, indices : CSR arrays of the (n_nodes, n_nodes) node graph (sorted columns).
    slots : (n_elem, nn, nn) int
        Position in ``indices`` of every element node pair.

    The DOF-level matrices follow from it without sorting: node row ``r`` gives DOF rows
    ``3r + i`` holding columns ``3 col + j`` in the same order.
    """

    n_nodes: int
    indptr: np.ndarray
    indices: np.ndarray
    slots: np.ndarray

    @classmethod
    def of(cls, mesh: TetMesh) -> NodePattern:
        """The pattern of ``mesh``: bucket node pairs by row (counting sort), sort each row.

        Cost is linear in the 10^2 (Tet10) pairs per element plus a sort of each short
        row, instead of one global sort of all pair keys.
        """
        n = mesh.n_nodes
        tets = mesh.tets
        n_e, nn = tets.shape
        n_pairs = n_e * nn * nn
        itype = _index_dtype(n_pairs + 1, n)
        # Occurrences (e, a) of every node, grouped by node: CSR -> CSC is a counting sort.
        occ = sp.csr_matrix(
            (np.arange(n_e * nn, dtype=itype), tets.reshape(-1).astype(itype),
             np.arange(0, n_e * nn + 1, nn, dtype=itype)),
            shape=(n_e, n),
        ).tocsc()
        ea = occ.data.astype(itype, copy=False)  # e * nn + a, grouped by node a
        # Row r of the pair list holds (tets[e, b], pair id (e*nn + a)*nn + b) for all b.
        cols = tets[ea // nn].astype(itype).reshape(-1)
        pairs = (ea[:, None] * nn + np.arange(nn, dtype=itype)).reshape(-1)
        row_ptr = (occ.indptr * nn).astype(itype)
        rows = sp.csr_matrix((pairs, cols, row_ptr), shape=(n, n))
        rows.has_sorted_indices = False
        rows.sort_indices()  # per-row sort, pair ids travel along
        cols, pairs = rows.indices, rows.data
        is_new = np.zeros(n_pairs, dtype=bool)
        if n_pairs:
            is_new[0] = True
            np.not_equal(cols[1:], cols[:-1], out=is_new[1:])
            is_new[row_ptr[:-1][np.diff(row_ptr) > 0]] = True
        n_before = np.zeros(n_pairs + 1, dtype=itype)
        np.cumsum(is_new, out=n_before[1:])
        slots = np.zeros(n_pairs, dtype=itype)
        slots[pairs] = n_before[1:] - 1
        # int32 where 9 nnz fits: SciPy keeps that index type through BSR -> CSR
        otype = _index_dtype(9 * int(n_before[-1]) + 1, 3 * n)
        indptr = n_before[row_ptr].astype(otype)
        indices = cols[is_new].astype(otype)
        return cls(n, indptr, indices, slots.reshape(n_e, nn, nn))

    @property
    def nnz_blocks(self) -> int:
        return int(self.indices.size)

    def _node_csr(self, values: np.ndarray) -> sp.csr_matrix:
        """(n, n) CSR of one value per slot (the pattern's own arrays, not copied)."""
        return sp.csr_matrix((values, self.indices, self.indptr), shape=(self.n_nodes,) * 2)

    def scatter(self, values: np.ndarray, elements: slice) -> np.ndarray:
        """Sum ``values`` (e, nn, nn, ...) of the chunk ``elements`` into pattern slots."""
        slots = self.slots[elements].reshape(-1)
        flat = np.ascontiguousarray(values, dtype=np.float64).reshape(len(slots), -1)
        out = touched_zeros((self.nnz_blocks, flat.shape[1]))
        scatter_add(out, slots, flat)
        return out

    def block_matrix(self, blocks: np.ndarray) -> sp.csr_matrix:
        """CSR (3n, 3n) from one 3x3 block per pattern slot.

        The slots are the node-level CSR order, so ``blocks`` already is a block-sparse
        (BSR) matrix; SciPy's compiled BSR -> CSR pass lays out the DOF rows in one sweep.
        """
        n3 = 3 * self.n_nodes
        bsr = sp.bsr_matrix((np.ascontiguousarray(blocks, dtype=np.float64).reshape(-1, 3, 3),
                             self.indices, self.indptr), shape=(n3, n3))
        A = bsr.tocsr()
        A.has_sorted_indices = True  # columns 3 col + j ascend because node columns do
        return A

    def diagonal_block_matrix(self, values: np.ndarray) -> sp.csr_matrix:
        """CSR (3n, 3n) of ``values (nnz,) (x) I3`` without storing the zero off-blocks.

        DOF row ``3r + i`` is node row ``r`` with columns ``3 col + i``: the node matrix's
        rows taken three times each (SciPy's compiled row gather), then columns spread.
        """
        n = self.n_nodes
        rows = self._node_csr(np.asarray(values, dtype=np.float64))[np.repeat(np.arange(n), 3)]
        component = np.repeat(np.tile(np.arange(3, dtype=rows.indices.dtype), n),
                              np.diff(rows.indptr))
        indices = rows.indices * rows.indices.dtype.type(3)
        indices += component
        A = sp.csr_matrix((rows.data, indices, rows.indptr), shape=(3 * n, 3 * n))
        A.has_sorted_indices = True
        return A


def touched_zeros(shape) -> np.ndarray:
    """Zeros written once front to back, for an array that is then added into at random.

    A fresh ``np.zeros`` is mapped lazily: a random scatter then faults its pages in one
    at a time in random order (two faults per page, read then write), which in a virtual
    machine costs several times the scatter itself.  Filling an ``np.empty`` array in
    order takes the faults in a sequential sweep (and lets NumPy's huge-page advice work).
    """
    out = np.empty(shape)
    out.fill(0.0)
    return out
