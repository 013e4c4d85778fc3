"""Vectorised assembly of stiffness and consistent mass matrices into CSR.

The public face of three parts: the element kernels (:mod:`flexarm.fe.kernels`), which
evaluate all elements and quadrature points of a chunk at once and give an
``(n_elem, 3*nn, 3*nn)`` stack (``element_stiffness``); the node-level sparsity pattern
(:mod:`flexarm.fe.sparsity`, ``NodePattern``), computed once per mesh; and, here, the
loop that scatter-adds the element blocks into the pattern slots chunk by chunk, in
place; the pattern turns the slot values into CSR with sorted indices and no
duplicates.  DOF index is ``3*node + component``.  The result is deterministic: every
sum runs in a fixed order.

Straight-sided meshes (every Tet4 mesh, and Tet10 with mid-edge midpoints) take the
compiled row-by-row path of :mod:`flexarm.fe.rows` when it is built: K and M in one pass
that writes the CSR arrays directly.  The NumPy path above is the fallback, and the path
for curved elements; both give the same matrices to rounding.
"""

from __future__ import annotations

import logging
import time
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from . import rows
from .kernels import (
    element_mass,
    element_stiffness,
    element_type,
    is_affine,
    mass_kernel,
    reference_rule,
    stiffness_blocks,
    stiffness_kernel,
)
from .material import Material
from .mesh import TetMesh
from .sparsity import NodePattern, scatter_add, touched_zeros

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


class _Assembler:
    """Per-mesh cache (pattern, chunks, affinity); the numerics are in kernels and sparsity."""

    def __init__(self, mesh: TetMesh):
        # NaN points or inverted elements would assemble silently into a matrix with
        # NaNs or negative diagonal terms: refuse them here, for every API caller
        fast = rows.available() and mesh.n_tets > 0
        self.mesh = mesh.check(volumes=rows.corner_volumes(mesh) if fast else None)

    @cached_property
    def pattern(self) -> NodePattern:
        return NodePattern.of(self.mesh)

    @cached_property
    def plan(self) -> rows.RowPlan | None:
        """The compiled row plan, or None where the NumPy path assembles."""
        if not (rows.available() and self.affine):
            return None
        return rows.RowPlan.of(self.mesh)

    def by_rows(self, material: Material | None, rho: float | None):
        """K and/or M by the compiled row path (the caller checked ``plan``)."""
        return rows.row_matrices(self.mesh, self.plan, reference_rule(self.mesh),
                                 material, rho)

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
        if self.plan is not None:
            return self.by_rows(material, None)[0]
        pat = self.pattern
        blocks = touched_zeros((pat.nnz_blocks, 9))
        nn = self.mesh.tets.shape[1]
        buffer = np.zeros(nn * nn * min(self.chunk_size, self.mesh.n_tets) * 9)
        for ch in self.chunks():
            Kb = stiffness_kernel(self.mesh, material, ch, self.affine, buffer)
            scatter_add(blocks, self._chunk_slots(ch), Kb.reshape(-1, 9))
        return pat.block_matrix(blocks)

    def mass(self, rho: float) -> sp.csr_matrix:
        if self.plan is not None:
            return self.by_rows(None, rho)[1]
        pat = self.pattern
        values = touched_zeros((pat.nnz_blocks, 1))
        for ch in self.chunks():
            Me = mass_kernel(self.mesh, rho, ch, self.affine)
            scatter_add(values, self._chunk_slots(ch), Me.reshape(-1, 1))
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
    """Stiffness and consistent mass (K [N/m], M [kg]) sharing one sparsity computation.

    Raises :class:`~flexarm.fe.errors.MeshError` (count and first element) for a mesh
    with no elements, NaN or infinite coordinates, inverted or zero-volume elements,
    as :func:`stiffness_matrix` and :func:`mass_matrix` do.

    Examples
    --------
    >>> from flexarm.fe.material import MATERIALS
    >>> mesh = TetMesh.box(divisions=(1, 1, 1))
    >>> flipped = TetMesh(mesh.points, mesh.tets[:, [1, 0, 2, 3]])
    >>> assemble(flipped, MATERIALS["steel"])
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.MeshError: mesh: 6 inverted tetrahedra (first: element 0)
    """
    t0 = time.perf_counter()
    log.info("assembling %d Tet%d elements", mesh.n_tets, 4 if mesh.order == 1 else 10)
    asm = _Assembler(mesh)
    if asm.plan is not None:
        K, M = asm.by_rows(material, material.rho)  # one pass over the rows for both
    else:
        K, M = asm.stiffness(material), asm.mass(material.rho)
    log.info("assembled K, M: %d DOF in %.2f s", K.shape[0], time.perf_counter() - t0)
    return K, M
