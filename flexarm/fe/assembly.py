"""Vectorised assembly of stiffness and consistent mass matrices into CSR.

One kernel evaluates all elements and quadrature points of a chunk at once and gives
an ``(n_elem, 3*nn, 3*nn)`` stack (``element_stiffness``).  The sparse pattern is
computed once per mesh at *node* level (one 3x3 block per node pair); element blocks
are summed into it with ``np.bincount`` and the matrix is built as BSR(3x3) -> CSR,
so the matrix comes out with sorted indices and no duplicates.  DOF index is
``3*node + component``.
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

#: Elements per vectorised chunk: bounds peak memory (~150 MB for Tet10).
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


def stiffness_blocks(
    mesh: TetMesh, material: Material, elements=slice(None), affine: bool | None = None
) -> np.ndarray:
    """Element stiffness as node-pair blocks (e, nn, nn, 3, 3) [N/m].

    ``K[e, a, b, i, j] = int lam dNa/dx_i dNb/dx_j
    + mu (dNa/dx_j dNb/dx_i + delta_ij grad Na . grad Nb)``.

    Straight-sided elements take the fast path: with ``P = J^-1``,
    ``K_ab = det J (P^T (lam D_ab + mu D_ab^T) P + mu tr(D_ab P P^T) I)`` where ``D``
    holds the reference gradient products, so all elements of a chunk are one GEMM.
    """
    el = element_type(mesh)
    tets = mesh.tets[elements]
    nn = el.n_nodes
    lam, mu = material.lame_lambda, material.lame_mu
    if affine is None:
        affine = is_affine(mesh)
    if not affine:
        pts, w = tet_quadrature(el.stiffness_degree)
        G, wdet = _geometry(mesh.points[tets], el.shape_grad(pts), w)
        n_e = len(tets)
        Gf = G.reshape(n_e, len(w), 3 * nn)
        A = np.matmul((Gf * wdet[:, :, None]).transpose(0, 2, 1), Gf).reshape(n_e, nn, 3, nn, 3)
        S = np.einsum("eaibi->eab", A)
        K = lam * A + mu * A.transpose(0, 1, 4, 3, 2)
        K += mu * S[:, :, None, :, None] * np.eye(3)[None, None, :, None, :]
        return K.transpose(0, 1, 3, 2, 4)
    D = _reference_gradient_products(el).reshape(nn * nn, 9)
    Dt = _reference_gradient_products(el).transpose(0, 1, 3, 2).reshape(nn * nn, 9)
    P, det = _affine_inverse(mesh, tets)
    # Q[e, (k,l), (i,j)] = det * P[k,i] P[l,j]
    Q = np.einsum("e,eki,elj->eklij", det, P, P).reshape(-1, 9, 9)
    trQ = Q[:, :, [0, 4, 8]].sum(axis=2)  # (e, 9): sum_m Q[e, kl, mm]
    Q2 = np.zeros_like(Q)
    Q2[:, :, [0, 4, 8]] = trQ[:, :, None]
    lhs = np.hstack([lam * D + mu * Dt, mu * D])  # (nn^2, 18)
    rhs = np.concatenate([Q, Q2], axis=1)  # (e, 18, 9)
    K = lhs @ rhs.transpose(1, 0, 2).reshape(18, -1)  # one GEMM: (nn^2, e*9)
    return K.reshape(nn, nn, len(tets), 3, 3).transpose(2, 0, 1, 3, 4)


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


def element_mass(mesh: TetMesh, rho: float, elements=slice(None), affine: bool | None = None):
    """Scalar element mass stack (e, nn, nn) [kg]: ``rho int N_a N_b dV``.

    The vector mass matrix is this block times the 3x3 identity.
    """
    el = element_type(mesh)
    tets = mesh.tets[elements]
    if affine is None:
        affine = is_affine(mesh)
    if affine:
        _, det = _affine_inverse(mesh, tets)
        return rho * det[:, None, None] * _reference_mass(el)[None]
    pts, w = tet_quadrature(el.mass_degree)
    N = el.shape(pts)
    J = np.matmul(mesh.points[tets].transpose(0, 2, 1)[:, None], el.shape_grad(pts)[None])
    wdet = np.linalg.det(J) * w
    NN = np.einsum("qa,qb->qab", N, N).reshape(len(w), -1)
    return (rho * wdet @ NN).reshape(len(tets), el.n_nodes, el.n_nodes)


@dataclass(frozen=True, eq=False)
class NodePattern:
    """Node-level sparsity pattern of a mesh, shared by K and M.

    Attributes
    ----------
    indptr, indices : CSR arrays of the (n_nodes, n_nodes) node graph (sorted columns).
    slots : (n_elem, nn, nn) int
        Position in ``indices`` of every element node pair.
    """

    n_nodes: int
    indptr: np.ndarray
    indices: np.ndarray
    slots: np.ndarray

    @classmethod
    def of(cls, mesh: TetMesh) -> NodePattern:
        n = mesh.n_nodes
        tets = mesh.tets
        nn = tets.shape[1]
        keys = (tets[:, :, None] * n + tets[:, None, :]).ravel()
        uniq, inverse = np.unique(keys, return_inverse=True)
        rows = uniq // n
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:])
        return cls(n, indptr, uniq % n, inverse.reshape(len(tets), nn, nn))

    @property
    def nnz_blocks(self) -> int:
        return int(self.indices.size)

    def scatter(self, values: np.ndarray, elements: slice) -> np.ndarray:
        """Sum ``values`` (e, nn, nn, ...) of the chunk ``elements`` into pattern slots."""
        slots = self.slots[elements].ravel()
        flat = values.reshape(len(slots), -1)
        # A 0/1 matrix with one entry per column is a scatter-add: SciPy's CSC
        # mat-vec sums all value columns in one compiled pass.
        S = sp.csc_matrix(
            (np.ones(len(slots)), slots, np.arange(len(slots) + 1)),
            shape=(self.nnz_blocks, len(slots)),
        )
        return S @ flat

    def block_matrix(self, blocks: np.ndarray) -> sp.csr_matrix:
        """CSR (3n, 3n) from one 3x3 block per pattern slot."""
        n3 = 3 * self.n_nodes
        bsr = sp.bsr_matrix((blocks.reshape(-1, 3, 3), self.indices, self.indptr), shape=(n3, n3))
        return bsr.tocsr()

    def diagonal_block_matrix(self, values: np.ndarray) -> sp.csr_matrix:
        """CSR (3n, 3n) of ``values (nnz,) (x) I3`` without storing the zero off-blocks."""
        n = self.n_nodes
        counts = np.diff(self.indptr)
        indptr = np.zeros(3 * n + 1, dtype=np.int64)
        np.cumsum(np.repeat(counts, 3), out=indptr[1:])
        # Row 3r+i holds the columns 3c+i of node row r, in the same (sorted) order.
        row_of_slot = np.repeat(np.arange(n), counts)
        comp = np.arange(3)
        start = indptr[3 * row_of_slot[:, None] + comp] + (
            np.arange(self.nnz_blocks) - self.indptr[row_of_slot]
        )[:, None]
        indices = np.zeros(3 * self.nnz_blocks, dtype=np.int64)
        data = np.zeros(3 * self.nnz_blocks)
        indices[start.ravel()] = (3 * self.indices[:, None] + comp).ravel()
        data[start.ravel()] = np.repeat(values, 3)
        return sp.csr_matrix((data, indices, indptr), shape=(3 * n, 3 * n))


class _Assembler:
    """Caches the node pattern of one mesh (logic stays in the functions above)."""

    def __init__(self, mesh: TetMesh):
        self.mesh = mesh

    @cached_property
    def pattern(self) -> NodePattern:
        return NodePattern.of(self.mesh)

    def chunks(self):
        m = self.mesh.n_tets
        for start in range(0, m, CHUNK):
            yield slice(start, min(start + CHUNK, m))

    @cached_property
    def affine(self) -> bool:
        return is_affine(self.mesh)

    def stiffness(self, material: Material) -> sp.csr_matrix:
        blocks = np.zeros((self.pattern.nnz_blocks, 9))
        for ch in self.chunks():
            Kb = stiffness_blocks(self.mesh, material, ch, self.affine)
            blocks += self.pattern.scatter(Kb, ch)
        return self.pattern.block_matrix(blocks)

    def mass(self, rho: float) -> sp.csr_matrix:
        values = np.zeros(self.pattern.nnz_blocks)
        for ch in self.chunks():
            values += self.pattern.scatter(element_mass(self.mesh, rho, ch, self.affine), ch)[:, 0]
        return self.pattern.diagonal_block_matrix(values)


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
