"""Meshes written by meshio and read back give bit-identical K and M."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import MATERIALS, TetMesh, assemble
from flexarm.meshes import read_volume_mesh, write_volume_mesh


@pytest.mark.parametrize("ext", [".vtu", ".msh", ".vtk", ".npz"])
@pytest.mark.parametrize("order", [1, 2])
def test_written_mesh_gives_identical_matrices(tmp_path, ext, order):
    rng = np.random.default_rng(4)
    box = TetMesh.box((0.4, 0.1, 0.08), (8, 2, 2))
    # Irregular points (a real mesh is not a lattice), still positively oriented.
    pts = box.points + rng.uniform(-0.004, 0.004, box.points.shape)
    mesh = TetMesh(pts, box.tets).check()
    mesh = mesh.to_tet10() if order == 2 else mesh
    path = tmp_path / f"part{ext}"
    write_volume_mesh(path, mesh)
    back = read_volume_mesh(path)
    K0, M0 = assemble(mesh, MATERIALS["steel"])
    K1, M1 = assemble(back, MATERIALS["steel"])
    for A, B in ((K0, K1), (M0, M1)):
        assert np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
        assert np.array_equal(A.data, B.data)
