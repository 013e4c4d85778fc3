"""The per-rank pieces of the distributed assembly that need no MPI: element slices and
their matrices add up to the global assembly; ownership ranges cover every row once."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from flexarm.fe import MATERIALS, TetMesh, assemble
from flexarm.fe.petsc_assembly import element_owners, local_matrices, ownership_bounds


def _scatter(part, n):
    """A slice's matrices placed into the global (n, n) numbering."""
    P = sp.csr_matrix((np.ones(part.dofs.size), (part.dofs, np.arange(part.dofs.size))),
                      shape=(n, part.dofs.size))
    return P @ part.K @ P.T, P @ part.M @ P.T


@pytest.mark.parametrize("order, ranks", [(1, 3), (2, 2), (2, 5)])
def test_slices_add_up_to_the_global_matrices(order, ranks):
    rng = np.random.default_rng(3)
    box = TetMesh.box((0.6, 0.2, 0.1), (6, 3, 2))
    pts = box.points.copy()
    inner = np.all((pts > 1e-9) & (pts < np.array([0.6, 0.2, 0.1]) - 1e-9), axis=1)
    pts[inner] += rng.uniform(-0.01, 0.01, (int(inner.sum()), 3))
    mesh = TetMesh(pts, box.tets)
    mesh = mesh.to_tet10() if order == 2 else mesh
    steel = MATERIALS["steel"]
    K, M = assemble(mesh, steel)
    owners = element_owners(mesh, ranks)
    counts = np.bincount(owners, minlength=ranks)
    assert counts.max() - counts.min() <= 1  # equal shares
    K_sum = sp.csr_matrix(K.shape)
    M_sum = sp.csr_matrix(M.shape)
    for r in range(ranks):
        Kr, Mr = _scatter(local_matrices(mesh, steel, np.flatnonzero(owners == r)), mesh.n_dofs)
        K_sum, M_sum = K_sum + Kr, M_sum + Mr
    assert abs(K_sum - K).max() <= 1e-12 * abs(K).max()
    assert abs(M_sum - M).max() <= 1e-12 * abs(M).max()


def test_empty_slice_and_bounds():
    mesh = TetMesh.box(divisions=(2, 1, 1))
    part = local_matrices(mesh, MATERIALS["steel"], np.zeros(0, dtype=int))
    assert part.dofs.size == 0 and part.K.shape == (0, 0)
    for n, size in ((10, 3), (7, 7), (1000, 6)):
        b = ownership_bounds(n, size)
        assert b[0] == 0 and b[-1] == n and np.all(np.diff(b) >= n // size)
