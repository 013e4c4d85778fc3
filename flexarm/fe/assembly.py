"""Vectorised assembly of stiffness and consistent mass matrices into CSR.

One kernel evaluates all elements and quadrature points of a chunk at once and gives
an ``(n_elem, 3*nn, 3*nn)`` stack (``element_stiffness``).  The sparse pattern is
computed once per mesh at *node* level (one 3x3 block per node pair, ``NodePattern``:
node pairs bucketed by row with a counting sort, then each short row sorted).  Element
blocks are scatter-added into the pattern slots chunk by chunk, in place, and the CSR
arrays of K and M are gathered straight from the slot values in CSR order, so the
matrices come out with sorted indices and no duplicates.  DOF index is
``3*node + component``.  The result is deterministic: every sum runs in a fixed order.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from .material import Material
from .mesh import TetMesh
from .quadrature import tet_quadrature
from .tet4 import Tet4
from .tet10 import Tet10

__all__ = [
    "element_type",
    "element_stiffness",
    "element_mass",
    "stiffness_blocks",
    "is_affine",
    "NodePattern",
    "stiffness_matrix",
    "mass_matrix",
    "assemble",
]

log = logging.getLogger(__name__)

#: Elements per vectorised chunk for Tet4; Tet10 chunks hold the same number of node
#: pairs (CHUNK * 16 / 100 elements), so the kernel output stays ~19 MB per chunk and
#: the scatter reads it while it is still in cache.
CHUNK = 16384


def element_type(mesh: TetMesh):
    """The element class (:class:`Tet4` or :class:`Tet10`) of ``mesh``."""
    return Tet4 if mesh.order == 1 else Tet10


def _geometry(coords: np.ndarray, dN: np.ndarray, weights: np.ndarray):
    """Physical gradients (e, q, nn, 3) and weights*detJ (e, q) of a chunk."""
    J = np.matmul(coords.transpose(0, 2, 1)[:, None], dN[None])
    detJ = np.linalg.det(J)
    G = np.matmul(dN[None], np.linalg.inv(J))
    return G, detJ * weights


def _affine_inverse(mesh: TetMesh, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse Jacobian (e, 3, 3) [1/m] and det J (e,) of the corner map, vectorised.

    Rows of the inverse are the cofactor vectors: no per-matrix LAPACK call.
    """
    X = mesh.points[tets[:, :4]]
    a = X[:, 1:] - X[:, :1]  # a[:, j] = dx/dxi_j
    c0, c1, c2 = np.cross(a[:, 1], a[:, 2]), np.cross(a[:, 2], a[:, 0]), np.cross(a[:, 0], a[:, 1])
    det = np.einsum("ei,ei->e", a[:, 0], c0)
    return np.stack([c0, c1, c2], axis=1) / det[:, None, None], det


def is_affine(mesh: TetMesh) -> bool:
    """True when every element is straight-sided (Tet4, or Tet10 with mid-edge midpoints)."""
    if mesh.order == 1:
        return True
    from .mesh import TET10_EDGES

    corners = mesh.points[mesh.tets[:, TET10_EDGES]]  # (m, 6, 2, 3)
    mids = mesh.points[mesh.tets[:, 4:]]
    dev = np.abs(mids - corners.mean(axis=2)).max()
    scale = np.abs(corners[:, :, 0] - corners[:, :, 1]).max()
    return bool(dev <= 1e-12 * scale)


def _reference_gradient_products(el) -> np.ndarray:
    """D[a, b, k, l] = int_ref dN_a/dxi_k dN_b/dxi_l (exact for straight elements)."""
    pts, w = tet_quadrature(el.stiffness_degree)
    dN = el.shape_grad(pts)
    return np.einsum("q,qak,qbl->abkl", w, dN, dN)


def _stiffness_kernel(
    mesh: TetMesh, material: Material, elements=slice(None), affine: bool | None = None,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Element stiffness blocks in scatter layout (nn, nn, e, 3, 3) [N/m], C-contiguous.

    Node pair first, element second: the affine GEMM writes this layout directly and
    ``reshape(-1, 9)`` gives the rows (a, b, e) that the scatter consumes, no copy.
    ``out`` (at least nn^2 e 9 float64, contiguous) is reused as the GEMM target, which
    saves page faults on a fresh array per chunk.
    """
    el = element_type(mesh)
    tets = mesh.tets[elements]
    nn = el.n_nodes
    lam, mu = material.lame_lambda, material.lame_mu
    if affine is None:
        affine = is_affine(mesh)
    if not affine:
        pts, w = tet_quadrature(el.curved_stiffness_degree)
        G, wdet = _geometry(mesh.points[tets], el.shape_grad(pts), w)
        n_e = len(tets)
        Gf = G.reshape(n_e, len(w), 3 * nn)
        A = np.matmul((Gf * wdet[:, :, None]).transpose(0, 2, 1), Gf).reshape(n_e, nn, 3, nn, 3)
        S = np.einsum("eaibi->eab", A)
        K = lam * A + mu * A.transpose(0, 1, 4, 3, 2)
        K += mu * S[:, :, None, :, None] * np.eye(3)[None, None, :, None, :]
        return np.ascontiguousarray(K.transpose(1, 3, 0, 2, 4))
    n_e = len(tets)
    D = _reference_gradient_products(el)  # (nn, nn, 3, 3)
    lhs = (lam * D + mu * D.transpose(0, 1, 3, 2)).reshape(nn * nn, 9)
    P, det = _affine_inverse(mesh, tets)
    # Q[k, l, e, i, j] = det P[k, i] P[l, j], built in GEMM layout (no transposed copy)
    Pt = P.transpose(1, 0, 2)
    Q = (det[:, None] * Pt)[:, None, :, :, None] * Pt[None, :, :, None, :]
    size = nn * nn * n_e * 9
    K = np.zeros(size) if out is None or out.size < size else out.reshape(-1)[:size]
    K = np.matmul(lhs, Q.reshape(9, n_e * 9), out=K.reshape(nn * nn, n_e * 9))  # one GEMM
    K = K.reshape(nn, nn, n_e, 3, 3)
    # mu tr(D_ab P P^T) det on the diagonal i == j: a second, 9-deep GEMM
    G = np.matmul(det[:, None, None] * P, P.transpose(0, 2, 1)).reshape(n_e, 9)
    S = (mu * D.reshape(nn * nn, 9)) @ G.T  # (nn^2, e)
    K3 = K.reshape(nn * nn, n_e, 9)
    for d in (0, 4, 8):
        K3[:, :, d] += S
    return K


def stiffness_blocks(
    mesh: TetMesh, material: Material, elements=slice(None), affine: bool | None = None
) -> np.ndarray:
    """Element stiffness as node-pair blocks (e, nn, nn, 3, 3) [N/m].

    ``K[e, a, b, i, j] = int lam dNa/dx_i dNb/dx_j
    + mu (dNa/dx_j dNb/dx_i + delta_ij grad Na . grad Nb)``.

    Straight-sided elements take the fast path: with ``P = J^-1``,
    ``K_ab = det J (P^T (lam D_ab + mu D_ab^T) P + mu tr(D_ab P P^T) I)`` where ``D``
    holds the reference gradient products, so all elements of a chunk are one GEMM
    (plus a 9-deep one for the trace term).  The result is a transposed view of the
    scatter layout.
    """
    return _stiffness_kernel(mesh, material, elements, affine).transpose(2, 0, 1, 3, 4)


def element_stiffness(mesh: TetMesh, material: Material, elements=slice(None)) -> np.ndarray:
    """Element stiffness stack (e, 3nn, 3nn) [N/m], local DOF ``3*a + i``.

    Examples
    --------
    >>> from flexarm.fe.material import MATERIALS
    >>> Ke = element_stiffness(TetMesh.unit_tet(), MATERIALS["steel"])
    >>> Ke.shape, bool(np.allclose(Ke[0], Ke[0].T))
    ((1, 12, 12), True)
    """
    B = stiffness_blocks(mesh, material, elements)
    n_e, nn = B.shape[:2]
    return B.transpose(0, 1, 3, 2, 4).reshape(n_e, 3 * nn, 3 * nn)


def _reference_mass(el) -> np.ndarray:
    pts, w = tet_quadrature(el.mass_degree)
    N = el.shape(pts)
    return np.einsum("q,qa,qb->ab", w, N, N)


def _mass_kernel(mesh: TetMesh, rho: float, elements=slice(None), affine: bool | None = None):
    """Scalar element mass in scatter layout (nn, nn, e) [kg], C-contiguous."""
    el = element_type(mesh)
    tets = mesh.tets[elements]
    if affine is None:
        affine = is_affine(mesh)
    if affine:
        _, det = _affine_inverse(mesh, tets)
        return _reference_mass(el)[:, :, None] * (rho * det)
    pts, w = tet_quadrature(el.mass_degree)
    N = el.shape(pts)
    J = np.matmul(mesh.points[tets].transpose(0, 2, 1)[:, None], el.shape_grad(pts)[None])
    wdet = np.linalg.det(J) * w
    NN = np.einsum("qa,qb->abq", N, N).reshape(-1, len(w))
    return (NN @ (rho * wdet).T).reshape(el.n_nodes, el.n_nodes, len(tets))


def element_mass(mesh: TetMesh, rho: float, elements=slice(None), affine: bool | None = None):
    """Scalar element mass stack (e, nn, nn) [kg]: ``rho int N_a N_b dV``.

    The vector mass matrix is this block times the 3x3 identity.
    """
    return _mass_kernel(mesh, rho, elements, affine).transpose(2, 0, 1)


try:  # in-place scatter-add (SciPy's compiled CSC mat-vec kernel); see _scatter_add
    from scipy.sparse._sparsetools import csc_matvecs as _csc_matvecs
except ImportError:  # pragma: no cover - private SciPy API moved
    _csc_matvecs = None


def _scatter_add(out: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
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

    The DOF-level matrices follow from it without sorting: node row ``r`` with ``c``
    slots gives DOF rows ``3r + i`` holding columns ``3 col + j`` in the same order, so
    slot ``s`` and component ``i`` own the triple of K entries starting at
    ``3 t`` and the single M entry ``t``, with ``t = 2 indptr[r] + s + i c``.
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
        indptr = n_before[row_ptr].astype(np.int64)
        indices = cols[is_new].astype(np.int64)
        return cls(n, indptr, indices, slots.reshape(n_e, nn, nn))

    @property
    def nnz_blocks(self) -> int:
        return int(self.indices.size)

    @cached_property
    def _dof_order(self) -> np.ndarray:
        """(3 nnz,) int: for each DOF-level triple ``t`` (see class notes), ``3 s + i``.

        Gathering with it turns slot-ordered blocks into CSR order (K, 3 entries per
        triple) or slot values into M's entries (one per triple).
        """
        counts = np.diff(self.indptr)
        itype = _index_dtype(9 * self.nnz_blocks + 1, 3 * self.n_nodes)
        base = np.repeat((2 * self.indptr[:-1]).astype(itype), counts)
        base += np.arange(self.nnz_blocks, dtype=itype)
        count_of_slot = np.repeat(counts.astype(itype), counts)
        src = np.zeros(3 * self.nnz_blocks, dtype=itype)
        s3 = 3 * np.arange(self.nnz_blocks, dtype=itype)
        for i in range(3):
            src[base] = s3 + i
            base += count_of_slot
        return src

    def _csr(self, data: np.ndarray, indices: np.ndarray, per_slot: int) -> sp.csr_matrix:
        n, n3 = self.n_nodes, 3 * self.n_nodes
        counts = np.diff(self.indptr)
        indptr = np.zeros(n3 + 1, dtype=indices.dtype)
        starts = 3 * per_slot * self.indptr[:-1, None] + per_slot * counts[:, None] * np.arange(3)
        indptr[:-1] = starts.reshape(3 * n)
        indptr[-1] = 3 * per_slot * self.nnz_blocks
        A = sp.csr_matrix((data, indices, indptr), shape=(n3, n3))
        A.has_sorted_indices = True  # columns 3 col + j ascend because node columns do
        return A

    def scatter(self, values: np.ndarray, elements: slice) -> np.ndarray:
        """Sum ``values`` (e, nn, nn, ...) of the chunk ``elements`` into pattern slots."""
        slots = self.slots[elements].reshape(-1)
        flat = np.ascontiguousarray(values, dtype=np.float64).reshape(len(slots), -1)
        out = np.zeros((self.nnz_blocks, flat.shape[1]))
        _scatter_add(out, slots, flat)
        return out

    def block_matrix(self, blocks: np.ndarray) -> sp.csr_matrix:
        """CSR (3n, 3n) from one 3x3 block per pattern slot."""
        src = self._dof_order
        rows = np.ascontiguousarray(blocks, dtype=np.float64).reshape(-1, 3)
        data = np.take(rows, src, axis=0).reshape(-1)
        col3 = np.take((3 * self.indices).astype(src.dtype), src // 3)
        indices = np.zeros((len(src), 3), dtype=src.dtype)
        np.add(col3[:, None], np.arange(3, dtype=src.dtype), out=indices)
        return self._csr(data, indices.reshape(-1), 3)

    def diagonal_block_matrix(self, values: np.ndarray) -> sp.csr_matrix:
        """CSR (3n, 3n) of ``values (nnz,) (x) I3`` without storing the zero off-blocks."""
        src = self._dof_order
        slot = src // 3
        data = np.take(np.asarray(values, dtype=np.float64), slot)
        indices = np.take((3 * self.indices).astype(src.dtype), slot)
        indices += src - 3 * slot
        return self._csr(data, indices, 1)


class _Assembler:
    """Caches the node pattern of one mesh (logic stays in the functions above)."""

    def __init__(self, mesh: TetMesh):
        self.mesh = mesh

    @cached_property
    def pattern(self) -> NodePattern:
        return NodePattern.of(self.mesh)

    @property
    def chunk_size(self) -> int:
        nn = self.mesh.tets.shape[1]
        return max(1, CHUNK * 16 // (nn * nn))

    def chunks(self):
        m, size = self.mesh.n_tets, self.chunk_size
        for start in range(0, m, size):
            yield slice(start, min(start + size, m))

    @cached_property
    def affine(self) -> bool:
        return is_affine(self.mesh)

    def _chunk_slots(self, ch: slice) -> np.ndarray:
        """Slots of a chunk in scatter order (a, b, e)."""
        return self.pattern.slots[ch].transpose(1, 2, 0).reshape(-1)

    def stiffness(self, material: Material) -> sp.csr_matrix:
        pat = self.pattern
        blocks = np.zeros((pat.nnz_blocks, 9))
        nn = self.mesh.tets.shape[1]
        buffer = np.zeros(nn * nn * min(self.chunk_size, self.mesh.n_tets) * 9)
        for ch in self.chunks():
            Kb = _stiffness_kernel(self.mesh, material, ch, self.affine, buffer)
            _scatter_add(blocks, self._chunk_slots(ch), Kb.reshape(-1, 9))
        return pat.block_matrix(blocks)

    def mass(self, rho: float) -> sp.csr_matrix:
        pat = self.pattern
        values = np.zeros((pat.nnz_blocks, 1))
        for ch in self.chunks():
            Me = _mass_kernel(self.mesh, rho, ch, self.affine)
            _scatter_add(values, self._chunk_slots(ch), Me.reshape(-1, 1))
        return pat.diagonal_block_matrix(values[:, 0])


def stiffness_matrix(mesh: TetMesh, material: Material) -> sp.csr_matrix:
    """Global stiffness K (3n, 3n) CSR [N/m].

    Examples
    --------
    >>> from flexarm.fe.material import MATERIALS
    >>> K = stiffness_matrix(TetMesh.box(divisions=(1, 1, 1)), MATERIALS["steel"])
    >>> K.shape, bool(abs(K - K.T).max() < 1e-6 * abs(K).max())
    ((24, 24), True)
    """
    return _Assembler(mesh).stiffness(material)


def mass_matrix(mesh: TetMesh, rho: float) -> sp.csr_matrix:
    """Global consistent mass M (3n, 3n) CSR [kg].

    Examples
    --------
    >>> M = mass_matrix(TetMesh.box(divisions=(2, 2, 2), order=2), rho=1000.0)
    >>> round(float(M.sum()) / 3, 9)  # total mass, each direction
    1000.0
    """
    return _Assembler(mesh).mass(rho)


def assemble(mesh: TetMesh, material: Material) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Stiffness and consistent mass (K [N/m], M [kg]) sharing one sparsity computation."""
    t0 = time.perf_counter()
    log.info("assembling %d Tet%d elements", mesh.n_tets, 4 if mesh.order == 1 else 10)
    asm = _Assembler(mesh)
    K = asm.stiffness(material)
    M = asm.mass(material.rho)
    log.info("assembled K, M: %d DOF in %.2f s", K.shape[0], time.perf_counter() - t0)
    return K, M
