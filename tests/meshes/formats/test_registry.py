"""The registry of the volume-mesh formats."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe.errors import ReadError
from flexarm.fe.formats import FormatRegistry
from flexarm.fe.mesh import TetMesh
from flexarm.meshes import formats
from flexarm.meshes.formats import msh, npz, vtk, vtu


def test_every_module_registered():
    reg = formats.registry
    assert reg.extensions() == (".msh", ".npz", ".vtk", ".vtu")
    for ext, module in [(".msh", msh), (".npz", npz), (".vtk", vtk), (".vtu", vtu)]:
        fmt = reg.find(f"a/b/part{ext.upper()}")
        assert fmt.read is module.read and fmt.write is module.write
    assert reg.find("part.stl") is None


def test_register_new_extension_round_trip(tmp_path):
    reg = FormatRegistry("volume mesh")
    reg.register("npz-alias", (".TETS",), npz.read, npz.write)
    path = reg.write(tmp_path / "a.tets", TetMesh.unit_tet())
    np.testing.assert_array_equal(reg.read(path).tets, [[0, 1, 2, 3]])


def test_registry_errors_name_the_file_and_the_choices(tmp_path):
    reg = FormatRegistry("volume mesh")
    reg.register("npz", (".npz",), npz.read, npz.write)
    reg.register("ro", (".ro",), read=npz.read)
    with pytest.raises(ValueError, match=r"a\.xyz: unknown volume mesh extension '\.xyz' "
                                         r"\(known: \.npz\)"):
        reg.write(tmp_path / "a.xyz", TetMesh.unit_tet())
    with pytest.raises(ValueError, match=r"cannot write volume mesh files of format ro "
                                         r"\(can write: \.npz\)"):
        reg.write(tmp_path / "a.ro", TetMesh.unit_tet())
    with pytest.raises(ValueError, match="format must be one of npz, ro, got 'vtu'"):
        reg.format_of(tmp_path / "a.npz", "vtu")
    with pytest.raises(FileNotFoundError):
        reg.read(tmp_path / "missing.npz")
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(ReadError, match=r"bad\.npz: cannot read it as a npz volume mesh"):
        reg.read(tmp_path / "bad.npz")
