"""read_volume_mesh / write_volume_mesh: exact round trips, errors, atomic writes."""

from __future__ import annotations

import re

import meshio
import numpy as np
import pytest

from flexarm.fe.errors import MeshError, ReadError
from flexarm.fe.mesh import TetMesh
from flexarm.meshes import read_volume_mesh, write_volume_mesh

from .conftest import jiggled_box

EXTENSIONS = [".vtu", ".msh", ".vtk", ".npz"]


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("ext", EXTENSIONS)
def test_round_trip_is_exact(tmp_path, ext, order):
    mesh = jiggled_box(order)
    path = tmp_path / f"part{ext}"
    write_volume_mesh(path, mesh)
    back = read_volume_mesh(path)
    assert back.points.dtype == np.float64 and back.points.dtype.isnative
    np.testing.assert_array_equal(back.points, mesh.points)  # bitwise
    np.testing.assert_array_equal(back.tets, mesh.tets)
    assert back.node_sets.keys() == mesh.node_sets.keys()
    for name, ids in mesh.node_sets.items():
        np.testing.assert_array_equal(back.node_sets[name], np.sort(ids))
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary left


def test_real_tetwild_mesh_round_trips(tmp_path, bar_tets):
    for ext in (".vtu", ".msh"):
        for mesh in (bar_tets, bar_tets.to_tet10()):
            write_volume_mesh(tmp_path / f"bar{ext}", mesh)
            back = read_volume_mesh(tmp_path / f"bar{ext}")
            np.testing.assert_array_equal(back.points, mesh.points)
            np.testing.assert_array_equal(back.tets, mesh.tets)


def test_msh_is_gmsh41_binary(tmp_path):
    path = tmp_path / "part.msh"
    write_volume_mesh(path, jiggled_box(1))
    assert path.read_bytes().startswith(b"$MeshFormat\n4.1 1 8\n")


def test_gmsh_tet10_node_order_differs_from_vtk_at_nodes_8_9(tmp_path):
    """Pin meshio's permutation: Gmsh stores edge (2,3) before edge (1,3)."""
    from flexarm.meshes.formats._meshio import to_meshio

    mesh = TetMesh.unit_tet().to_tet10()
    path = tmp_path / "ascii.msh"
    meshio.write(path, to_meshio(mesh, cell_dtype=np.uint64), file_format="gmsh", binary=False)
    text = path.read_text()
    element = text.split("$Elements\n")[1].splitlines()[2].split()
    gmsh_nodes = np.array(element[1:], dtype=int) - 1  # 1-based in the file
    p = mesh.points
    np.testing.assert_array_equal(p[gmsh_nodes[8]], (p[2] + p[3]) / 2)
    np.testing.assert_array_equal(p[gmsh_nodes[9]], (p[1] + p[3]) / 2)
    np.testing.assert_array_equal(gmsh_nodes, mesh.tets[0, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]])


def test_missing_file(tmp_path):
    path = tmp_path / "none.vtu"
    with pytest.raises(ReadError, match=f"^{re.escape(str(path))}: no such file$"):
        read_volume_mesh(path)


def test_unknown_extension(tmp_path):
    path = tmp_path / "part.xyz"
    path.write_text("1 2 3")
    supported = re.escape("(supported: .msh, .npz, .vtk, .vtu)")
    with pytest.raises(ReadError, match=f"part.xyz: cannot read '.xyz' volume meshes {supported}"):
        read_volume_mesh(path)
    with pytest.raises(ValueError, match=f"cannot write '.xyz' volume meshes {supported}"):
        write_volume_mesh(path, TetMesh.unit_tet())


@pytest.mark.parametrize("ext, fmt", [(".vtu", "vtu"), (".msh", "gmsh"), (".npz", "npz")])
def test_corrupt_file(tmp_path, ext, fmt):
    path = tmp_path / f"bad{ext}"
    path.write_bytes(b"\x00\x13garbage\xff" * 40)
    with pytest.raises(ReadError, match=f"^{re.escape(str(path))}: cannot read it as {fmt}: "):
        read_volume_mesh(path)


def test_npz_without_our_format_key(tmp_path):
    path = tmp_path / "other.npz"
    np.savez(path, points=np.zeros((4, 3)))
    with pytest.raises(ReadError, match="other.npz: not a flexarm mesh archive"):
        read_volume_mesh(path)


def test_file_without_tetrahedra(tmp_path):
    path = tmp_path / "skin.vtu"
    points = np.eye(3)
    meshio.write(path, meshio.Mesh(points, [("triangle", np.array([[0, 1, 2]]))]))
    with pytest.raises(
        MeshError, match=f"^{re.escape(str(path))}: no tetrahedra .* in the file \\(triangle\\)$"
    ):
        read_volume_mesh(path)


def test_mixed_cells_keep_tets_only(tmp_path):
    mesh = jiggled_box(1)
    points = np.vstack([mesh.points, [[5.0, 5.0, 5.0]]])  # a node only a vertex cell uses
    n = mesh.n_nodes
    cells = [
        ("vertex", np.array([[n]])),
        ("tetra", mesh.tets),
        ("triangle", mesh.boundary_faces()),
    ]
    mask = np.zeros(n + 1, dtype=np.uint8)
    mask[[0, 1, n]] = 1
    path = tmp_path / "mixed.vtu"
    meshio.write(path, meshio.Mesh(points, cells, point_data={"set:base": mask}))
    back = read_volume_mesh(path)
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.tets, mesh.tets)
    np.testing.assert_array_equal(back.node_sets["base"], [0, 1])


def test_mixed_orders_rejected(tmp_path):
    tet10 = TetMesh.unit_tet().to_tet10()
    path = tmp_path / "mixed.vtu"
    cells = [("tetra", tet10.tets[:, :4]), ("tetra10", tet10.tets)]
    meshio.write(path, meshio.Mesh(tet10.points, cells))
    with pytest.raises(MeshError, match="mixes tetra and tetra10 cells"):
        read_volume_mesh(path)


@pytest.mark.parametrize("ext", [".vtu", ".msh", ".vtk"])
def test_failed_write_leaves_nothing(tmp_path, monkeypatch, ext):
    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(meshio, "write", broken)
    path = tmp_path / f"part{ext}"
    with pytest.raises(RuntimeError, match="disk full"):
        write_volume_mesh(path, jiggled_box(2))
    assert list(tmp_path.iterdir()) == []
    path.write_text("old")
    with pytest.raises(RuntimeError, match="disk full"):
        write_volume_mesh(path, jiggled_box(2))
    assert path.read_text() == "old" and list(tmp_path.iterdir()) == [path]


def test_failed_npz_write_leaves_nothing(tmp_path, monkeypatch):
    def broken(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez", broken)
    with pytest.raises(OSError, match="disk full"):
        write_volume_mesh(tmp_path / "part.npz", jiggled_box(1))
    assert list(tmp_path.iterdir()) == []
