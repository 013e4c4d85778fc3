"""Compiled row-by-row assembly of straight-sided meshes (the C extension ``_rows``).

Each node row of K and M is built in one go: the elements around the node add their row
blocks into it while it sits in the L1 cache, then it is written once, in order, straight
into the CSR arrays.  No element stack, slot array or block matrix is stored, so the
memory traffic is close to writing the CSR arrays once, which is what bounds assembly.
The element maths is that of the affine fast path in :mod:`flexarm.fe.kernels`, with
the reference integrals taken as the exact quadrature they come from: physical gradients
``P^T dN`` at the rule's points (``P`` the inverse corner Jacobian), so a Tet4 pair costs
one outer product and a Tet10 pair four.

The extension is built at install time (``setup.py``); where it is missing (no compiler),
:func:`available` is False and :mod:`flexarm.fe.assembly` uses its NumPy path, which
gives the same matrices to rounding (they are tested against each other).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .material import Material
from .mesh import TetMesh
from .topology import TET10_EDGES

#: The argument layout this module calls; an older build (source edited, extension not
#: rebuilt) is ignored rather than called wrongly.
API_VERSION = 1

try:
    from . import _rows
except ImportError:  # pragma: no cover - built without a C compiler
    _rows = None
if _rows is not None and getattr(_rows, "API_VERSION", None) != API_VERSION:  # pragma: no cover
    logging.getLogger(__name__).warning(
        "flexarm.fe._rows is an old build: NumPy assembly (rebuild: pip install -e .)")
    _rows = None

__all__ = ["available", "RowPlan", "corner_volumes", "midside_deviation", "row_matrices"]

_I32_MAX = np.iinfo(np.int32).max


def available() -> bool:
    """True when the compiled row assembly is built (see ``setup.py``)."""
    return _rows is not None


def corner_volumes(mesh: TetMesh) -> np.ndarray:
    """(m,) float: signed volume of each element's corner tetrahedron [m^3].

    Examples
    --------
    >>> v = corner_volumes(TetMesh.unit_tet()) if available() else TetMesh.unit_tet().volumes()
    >>> round(float(v[0]) * 6, 12)
    1.0
    """
    det = np.empty(mesh.n_tets)
    _rows.corner_det(mesh.points, mesh.tets, mesh.tets.shape[1], det)
    return det / 6.0


def midside_deviation(mesh: TetMesh) -> tuple[float, float]:
    """Largest distance of a Tet10 mid-edge node from its edge's centre, and the largest
    corner coordinate difference (its scale) [m], in one compiled pass."""
    edges = np.ascontiguousarray(TET10_EDGES, dtype=np.int64)
    return _rows.midside_deviation(mesh.points, mesh.tets, edges)


@dataclass(frozen=True, eq=False)
class RowPlan:
    """Node rows of a mesh: the elements around each node and its sorted neighbours.

    Attributes
    ----------
    occ_ptr : (n + 1,) int64
        Node ``r``'s element nodes are ``occ[occ_ptr[r]:occ_ptr[r + 1]]``.
    occ : (m nn,) int64
        Element node ``e * nn + a`` grouped by node, in element order.
    indptr : (n + 1,) int64, indices : (nnz,) int32
        CSR of the (n, n) node graph, columns sorted.
    """

    n_nodes: int
    occ_ptr: np.ndarray
    occ: np.ndarray
    indptr: np.ndarray
    indices: np.ndarray

    @classmethod
    def of(cls, mesh: TetMesh) -> RowPlan | None:
        """The plan of ``mesh``, or None when its DOF-level CSR would not fit int32."""
        n, (n_e, nn) = mesh.n_nodes, mesh.tets.shape
        if 3 * n >= _I32_MAX or n_e * nn >= _I32_MAX:
            return None
        occ_ptr, occ = np.empty(n + 1, dtype=np.int64), np.empty(n_e * nn, dtype=np.int64)
        indptr = np.empty(n + 1, dtype=np.int64)
        nnz = _rows.node_rows(mesh.tets, nn, n, occ_ptr, occ, indptr)
        if 9 * nnz >= _I32_MAX:
            return None
        indices = np.empty(nnz, dtype=np.int32)
        _rows.node_columns(mesh.tets, nn, occ_ptr, occ, indptr, indices)
        return cls(n, occ_ptr, occ, indptr, indices)

    @property
    def nnz_blocks(self) -> int:
        return int(self.indices.size)


def _csr(n: int, nnz: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return np.empty(nnz), np.empty(nnz, dtype=np.int32), np.empty(n + 1, dtype=np.int32)


def row_matrices(
    mesh: TetMesh, plan: RowPlan, reference: tuple[np.ndarray, np.ndarray, np.ndarray],
    material: Material | None, rho: float | None,
) -> tuple[sp.csr_matrix | None, sp.csr_matrix | None]:
    """K [N/m] (when ``material``) and M [kg] (when ``rho``) of a straight-sided mesh.

    ``reference`` is :func:`~flexarm.fe.kernels.reference_rule`: the reference gradients
    (q, nn, 3) at the points of a rule exact for the stiffness, its weights (q,), and the
    integrals ``N[a, b]`` (nn, nn) of the shape products.
    The DOF index is ``3*node + component``; both matrices have sorted indices.

    Examples
    --------
    >>> from flexarm.fe.material import MATERIALS
    >>> from flexarm.fe.kernels import reference_rule
    >>> mesh = TetMesh.box(divisions=(1, 1, 1))
    >>> if available():
    ...     K, M = row_matrices(mesh, RowPlan.of(mesh), reference_rule(mesh),
    ...                         MATERIALS["steel"], 1000.0)
    ...     print(K.shape, round(float(M.sum()) / 3, 9))
    ... else:
    ...     print((24, 24), 1000.0)
    (24, 24) 1000.0
    """
    (grads, weights), N = reference
    nn = mesh.tets.shape[1]
    lam, mu = (material.lame_lambda, material.lame_mu) if material is not None else (0.0, 0.0)
    mass = np.ascontiguousarray(N * (rho if rho is not None else 0.0))
    n3, nnz = 3 * plan.n_nodes, plan.nnz_blocks
    k_arrays = _csr(n3, 9 * nnz) if material is not None else (None,) * 3
    m_arrays = _csr(n3, 3 * nnz) if rho is not None else (None,) * 3
    _rows.fill(mesh.points, mesh.tets, nn, plan.occ_ptr, plan.occ, plan.indptr, plan.indices,
               grads, weights, lam, mu, mass, *k_arrays, *m_arrays)
    out = []
    for arrays in (k_arrays, m_arrays):
        if arrays[0] is None:
            out.append(None)
            continue
        A = sp.csr_matrix(arrays, shape=(n3, n3))
        A.has_sorted_indices = True  # node columns ascend, DOF columns 3 c + j with them
        out.append(A)
    return out[0], out[1]
