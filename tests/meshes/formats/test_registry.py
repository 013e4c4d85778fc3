"""The extension registry of the volume-mesh formats."""

from __future__ import annotations

import numpy as np

from flexarm.fe.mesh import TetMesh
from flexarm.meshes import formats
from flexarm.meshes.formats import msh, npz, vtk, vtu


def test_every_module_registered():
    assert formats.extensions() == (".msh", ".npz", ".vtk", ".vtu")
    for ext, module in [(".msh", msh), (".npz", npz), (".vtk", vtk), (".vtu", vtu)]:
        fmt = formats.format_for(f"a/b/part{ext.upper()}")
        assert fmt.read is module.read and fmt.write is module.write
    assert formats.format_for("part.stl") is None


def test_register_new_extension(tmp_path, monkeypatch):
    from flexarm.meshes.formats import _registry

    monkeypatch.setattr(_registry, "_formats", dict(_registry._formats))
    formats.register_format("npz-alias", (".TETS",), npz.read, npz.write)
    path = tmp_path / "a.tets"
    formats.format_for(path).write(path, TetMesh.unit_tet())
    np.testing.assert_array_equal(npz.read(path).tets, [[0, 1, 2, 3]])
