import numpy as np
import pytest

from flexarm.fe import InterfaceError, TetMesh
from flexarm.reduction.interfaces import (
    CylinderRegion,
    NodeSetRegion,
    axis_frame,
    interfaces,
    parse_cylinder,
    select_region,
)

MESH = TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2))
A = CylinderRegion("a", (0, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)
B = CylinderRegion("b", (0.4, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)


def test_cylinder_selects_end_face():
    nodes = select_region(MESH, A)
    assert nodes.size == 9
    assert np.all(MESH.points[nodes, 0] == 0.0)


def test_ring_radius_range_and_interior_nodes():
    ring = CylinderRegion("r", (0, 0.02, 0.02), (1, 0, 0), 0.015, 0.04, 1e-6)
    assert select_region(MESH, ring).size == 8  # the centre node is excluded
    thick = CylinderRegion("t", (0.2, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 0.001)
    assert select_region(MESH, thick, surface_only=False).size == 9
    assert select_region(MESH, thick, surface_only=True).size == 8


def test_interfaces_positions_and_frames():
    ifs = interfaces(MESH, [A, B])
    assert [i.name for i in ifs] == ["a", "b"]
    assert np.allclose(ifs[1].position, [0.4, 0.02, 0.02])
    F = ifs[0].frame
    assert np.allclose(F.T @ F, np.eye(3)) and np.isclose(np.linalg.det(F), 1.0)
    assert np.allclose(F[:, 2], [1, 0, 0])


def test_axis_frame_rejects_zero():
    with pytest.raises(ValueError, match="non-zero"):
        axis_frame([0, 0, 0])


def test_empty_region_named():
    far = CylinderRegion("far", (5, 5, 5), (1, 0, 0), 0.0, 0.01, 0.01)
    with pytest.raises(InterfaceError, match="region 'far' is empty: no surface nodes"):
        interfaces(MESH, [A, far])


def test_overlap_named():
    wide = CylinderRegion("wide", (0, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 0.06)
    with pytest.raises(InterfaceError, match="region 'wide' overlaps region 'a': 9 shared"):
        interfaces(MESH, [A, wide])


def test_too_few_nodes():
    mesh = MESH.with_node_sets({"pair": [0, 1]})
    with pytest.raises(InterfaceError, match="region 'pair': 2 nodes, need at least 3"):
        interfaces(mesh, [NodeSetRegion("pair")])


def test_collinear_nodes():
    edge = np.flatnonzero((MESH.points[:, 1] == 0) & (MESH.points[:, 2] == 0))
    mesh = MESH.with_node_sets({"edge": edge})
    with pytest.raises(InterfaceError, match="region 'edge': its 9 nodes are collinear"):
        interfaces(mesh, [NodeSetRegion("edge")])


def test_interior_nodes_rejected_when_surface_only():
    inner = np.flatnonzero(np.isclose(MESH.points[:, 0], 0.2))
    mesh = MESH.with_node_sets({"mid": inner})
    with pytest.raises(InterfaceError, match="region 'mid': 1 of 9 nodes are not on the surface"):
        interfaces(mesh, [NodeSetRegion("mid")])
    assert interfaces(mesh, [NodeSetRegion("mid")], surface_only=False)[0].nodes.size == 9


def test_unknown_node_set_and_duplicates_and_none():
    with pytest.raises(InterfaceError, match="region 'hub': the mesh has no node set 'hub'"):
        interfaces(MESH, [NodeSetRegion("hub")])
    with pytest.raises(InterfaceError, match="'a' is repeated"):
        interfaces(MESH, [A, A])
    with pytest.raises(InterfaceError, match="at least one interface"):
        interfaces(MESH, [])


def test_bad_cylinder_geometry():
    with pytest.raises(InterfaceError, match="region 'x': need 0 <= r_min < r_max"):
        CylinderRegion("x", (0, 0, 0), (1, 0, 0), 0.05, 0.01, 0.01)
    with pytest.raises(InterfaceError, match="region 'x': the axis is the zero vector"):
        CylinderRegion("x", (0, 0, 0), (0, 0, 0), 0.0, 0.01, 0.01)


def test_parse_cylinder():
    c = parse_cylinder("hub:0,0,0.1,0,0,2,0.05,0.01")
    assert c.name == "hub" and c.r_min == 0.0 and c.r_max == 0.05 and c.axis == (0, 0, 1)
    ring = parse_cylinder("ring:0,0,0,1,0,0,0.02,0.05,0.01")
    assert (ring.r_min, ring.r_max, ring.half_width) == (0.02, 0.05, 0.01)
    with pytest.raises(ValueError, match="NAME:cx,cy,cz,ax,ay,az,r,w"):
        parse_cylinder("hub:1,2,3")


def _hollow_cube():
    """The unit cube in 3 x 3 x 3 cells with the centre cell's tetrahedra removed: a
    solid with one closed cavity (its wall: the 8 nodes of the centre cell)."""
    from dataclasses import replace

    cube = TetMesh.box((3.0, 3.0, 3.0), (3, 3, 3))
    centroids = cube.points[cube.tets].mean(axis=1)
    keep = ~np.all((centroids > 1.0) & (centroids < 2.0), axis=1)
    return replace(cube, tets=cube.tets[keep])


def test_a_seat_takes_no_node_of_a_cavity_wall():
    cube = _hollow_cube()
    # 4^3 - 2^3 = 56 nodes on the outer skin; the cavity wall adds the 8 inner ones
    assert cube.boundary_nodes().size == 64 and cube.boundary_nodes(outer=True).size == 56
    through = CylinderRegion("z", (1.5, 1.5, 1.5), (0, 0, 1), 0.0, 0.8, 1.6)
    nodes = select_region(cube, through)
    assert nodes.size == 8  # the 4 nodes of each end face inside r < 0.8; none inside
    assert set(np.abs(cube.points[nodes, 2] - 1.5).round(6)) == {1.5}
