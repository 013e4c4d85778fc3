"""TetMesh: sizes and volumes of boxes, outward boundary faces (divergence theorem gives V),
boundary nodes against the box surface, copies (scaled, translated, node sets), Tet4 <-> Tet10."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import TET10_EDGES, TetMesh

DIVS = [(1, 1, 1), (3, 2, 1), (2, 3, 4)]


def _on_box_surface(points, lo, hi):
    return np.any(np.isclose(points, lo) | np.isclose(points, hi), axis=1)


@pytest.mark.parametrize("divs", DIVS)
def test_box_sizes_and_volumes(divs):
    size = np.array([0.9, 0.4, 0.6])
    mesh = TetMesh.box(size, divs, origin=(1.0, 2.0, -3.0))
    nx, ny, nz = divs
    assert mesh.n_nodes == (nx + 1) * (ny + 1) * (nz + 1)
    assert mesh.n_tets == 6 * nx * ny * nz and mesh.n_dofs == 3 * mesh.n_nodes
    vol = mesh.volumes()
    np.testing.assert_allclose(vol, np.prod(size / divs) / 6, rtol=1e-12)
    np.testing.assert_allclose(mesh.bounds(), [[1.0, 2.0, -3.0], [1.9, 2.4, -2.4]], rtol=1e-15)
    assert mesh.check() is mesh


@pytest.mark.parametrize("divs", DIVS)
@pytest.mark.parametrize("order", [1, 2])
def test_boundary_faces_are_outward_and_enclose_the_volume(divs, order):
    """Divergence theorem: V = 1/3 sum over faces of (area normal . centroid)."""
    size = np.array([0.9, 0.4, 0.6])
    mesh = TetMesh.box(size, divs, order=order, origin=(-0.2, 0.1, 0.3))
    nx, ny, nz = divs
    faces = mesh.boundary_faces()
    assert faces.shape == (4 * (nx * ny + ny * nz + nx * nz), 3)
    p = mesh.points[faces]
    area_normal = 0.5 * np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert np.sum(area_normal * p.mean(axis=1)) / 3 == pytest.approx(np.prod(size), rel=1e-12)
    centre = np.array([-0.2, 0.1, 0.3]) + size / 2
    assert np.all(np.einsum("ij,ij->i", area_normal, p.mean(axis=1) - centre) > 0)
    np.testing.assert_allclose(area_normal.sum(axis=0), 0.0, atol=1e-15)  # closed surface


@pytest.mark.parametrize("order", [1, 2])
def test_boundary_nodes_are_the_nodes_on_the_box_surface(order):
    mesh = TetMesh.box((1.0, 0.5, 0.5), (3, 2, 2), order=order)
    expected = np.flatnonzero(_on_box_surface(mesh.points, 0.0, [1.0, 0.5, 0.5]))
    np.testing.assert_array_equal(mesh.boundary_nodes(), expected)
    if order == 1:
        assert expected.size == 4 * 3 * 3 - 2 * 1 * 1


def test_unit_tet_and_copies():
    t = TetMesh.unit_tet().with_node_sets({"a": [0, 1], "b": [3]})
    assert t.volumes().tolist() == [1 / 6]
    s = t.scaled(1e-3)
    assert s.volumes()[0] == pytest.approx(1e-9 / 6, rel=1e-14)
    np.testing.assert_array_equal(s.tets, t.tets)
    moved = t.translated([1.0, -2.0, 0.5])
    np.testing.assert_array_equal(moved.points - t.points, [[1.0, -2.0, 0.5]] * 4)
    assert moved.volumes()[0] == pytest.approx(1 / 6, rel=1e-14)
    assert set(moved.node_sets) == {"a", "b"}
    merged = t.with_node_sets({"b": [2], "c": [1]})
    assert {k: v.tolist() for k, v in merged.node_sets.items()} == {"a": [0, 1], "b": [2],
                                                                     "c": [1]}
    assert t.node_sets["b"].tolist() == [3]  # the original keeps its sets


def test_arrays_are_read_only():
    mesh = TetMesh.box(divisions=(1, 1, 1)).with_node_sets({"s": [0]})
    for arr in (mesh.points, mesh.tets, mesh.node_sets["s"]):
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 1
    with pytest.raises(TypeError):
        mesh.node_sets["new"] = np.array([1])


def test_points_must_be_n_by_3():
    with pytest.raises(ValueError, match=r"points must be \(n, 3\), got \(4, 2\)"):
        TetMesh(np.zeros((4, 2)), [[0, 1, 2, 3]])


def test_tet10_mid_nodes_sit_on_the_vtk_edges():
    base = TetMesh.box((1.0, 2.0, 3.0), (2, 1, 1)).with_node_sets({"end": [0, 1, 2]})
    mesh = base.to_tet10()
    assert mesh.order == 2 and mesh.tets.shape == (12, 10)
    p = mesh.points
    expected = 0.5 * (p[mesh.tets[:, TET10_EDGES[:, 0]]] + p[mesh.tets[:, TET10_EDGES[:, 1]]])
    np.testing.assert_allclose(p[mesh.tets[:, 4:]], expected, rtol=1e-15)
    np.testing.assert_array_equal(mesh.corner_nodes, np.arange(base.n_nodes))
    np.testing.assert_array_equal(mesh.corner_tets, base.tets)
    np.testing.assert_allclose(mesh.volumes(), base.volumes())
    assert mesh.to_tet10() is mesh and base.to_tet4() is base
    back = mesh.to_tet4()
    np.testing.assert_array_equal(back.points, base.points)
    np.testing.assert_array_equal(back.tets, base.tets)
    assert back.node_sets["end"].tolist() == [0, 1, 2]


def test_to_tet4_renumbers_and_drops_mid_nodes_from_sets():
    mesh = TetMesh.box(divisions=(1, 1, 1), order=2)
    # reorder nodes: mid-edge nodes first, so that corners must be renumbered
    perm = np.r_[np.arange(8, mesh.n_nodes), np.arange(8)]
    inv = np.argsort(perm)
    shuffled = TetMesh(mesh.points[perm], inv[mesh.tets],
                       {"mixed": [inv[0], inv[8], inv[7]]})  # corner, mid, corner
    t4 = shuffled.to_tet4()
    assert t4.n_nodes == 8 and t4.order == 1
    np.testing.assert_allclose(t4.volumes(), mesh.to_tet4().volumes())
    np.testing.assert_array_equal(np.sort(t4.points[t4.node_sets["mixed"]], axis=0),
                                  np.sort(mesh.points[[0, 7]], axis=0))


@pytest.mark.parametrize("order", [1, 2])
def test_repr_is_one_short_line_with_the_mesh_figures(order):
    mesh = TetMesh.box((0.9, 0.4, 0.6), (12, 6, 8), order=order, origin=(0.1, -0.2, 0.0))
    mesh = mesh.with_node_sets({f"set{k}": [k] for k in range(9)})
    text = repr(mesh)
    assert len(text) < 300 and "\n" not in text and "array" not in text
    assert text.startswith(f"TetMesh(Tet{4 if order == 1 else 10}, {mesh.n_nodes} nodes, "
                           f"{mesh.n_tets} elements, box ")
    box = text.split("box ")[1].split(" m,")[0]
    bounds = [[float(v) for v in b.strip("[]").split(", ")] for b in box.split(" x ")]
    assert np.allclose(np.array(bounds).T, mesh.bounds(), rtol=1e-4)
    volume = float(text.split("volume ")[1].split(" m^3")[0])
    assert volume == pytest.approx(0.9 * 0.4 * 0.6, rel=1e-4)
    assert "node sets set0, set1, set2, set3, … (+5)" in text
    assert mesh == mesh and mesh != TetMesh.box((0.9, 0.4, 0.6), (12, 6, 8))  # identity ==
