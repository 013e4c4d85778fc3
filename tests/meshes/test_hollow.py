"""Hollowed CAD hulls: exact shell volumes, closed shells, solid parts kept solid."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from flexarm.fe.errors import MeshError
from flexarm.meshes import hollow_link_surface, load_surface, tetrahedralize
from flexarm.meshes.hollow import hollow_surface

IRB_COLLISION = Path("/work/shared/data/irb4600/meshes/collision")
IRB_LINKS = sorted(IRB_COLLISION.glob("*.stl")) if IRB_COLLISION.is_dir() else []


def _moved(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """The mesh turned about no coordinate axis and moved off the origin."""
    transform = np.eye(4)
    transform[:3, :3] = Rotation.from_euler("xyz", [0.3, 0.7, 1.1]).as_matrix()
    transform[:3, 3] = [1.0, -2.0, 0.5]
    return mesh.copy().apply_transform(transform)


def _box_shell(size, t) -> float:
    size = np.asarray(size, dtype=float)
    return float(np.prod(size) - np.prod(size - 2 * t))


def _assert_closed_shell(shell, surface):
    """Watertight, outward, two or more bodies, the input surface first and unchanged."""
    mesh = shell.mesh
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    n_v, n_f = len(surface.vertices), len(surface.faces)
    np.testing.assert_array_equal(mesh.vertices[:n_v], surface.vertices)
    np.testing.assert_array_equal(mesh.faces[:n_f], surface.faces)
    inner = trimesh.Trimesh(mesh.vertices, mesh.faces[n_f:], process=False)
    assert inner.volume < 0  # the cavity faces point into the cavity
    assert mesh.volume == pytest.approx(surface.volume - shell.cavity.volume, rel=1e-12)


@pytest.mark.parametrize("t", [0.001, 0.02, 0.1, 0.149])
def test_cube_shell_volume_is_exact(t):
    a = 0.3
    shell = hollow_surface(trimesh.creation.box((a, a, a)), t)
    assert shell.method == "convex" and not shell.is_solid
    assert shell.volume == pytest.approx(a**3 - (a - 2 * t) ** 3, rel=1e-9)


def test_turned_box_shell_is_exact_and_closed():
    box = _moved(trimesh.creation.box((0.5, 0.2, 0.1)))
    shell = hollow_surface(box, 0.015)
    assert shell.method == "convex"
    assert shell.volume == pytest.approx(_box_shell((0.5, 0.2, 0.1), 0.015), rel=1e-9)
    _assert_closed_shell(shell, box)
    assert shell.mesh.body_count == 2 and len(shell.cavity.vertices) == 8


def test_hexagonal_prism_shell_is_exact():
    r, h, t = 0.1, 0.3, 0.02
    prism = _moved(trimesh.creation.cylinder(radius=r, height=h, sections=6))
    apothem = r * np.cos(np.pi / 6)  # a hexagon's area is 2 sqrt(3) apothem^2
    exact = 2 * np.sqrt(3) * (apothem**2 * h - (apothem - t) ** 2 * (h - 2 * t))
    shell = hollow_surface(prism, t)
    assert shell.volume == pytest.approx(exact, rel=1e-9)
    _assert_closed_shell(shell, prism)


def test_cavity_is_the_box_shrunk_by_the_wall():
    box = trimesh.creation.box((0.4, 0.2, 0.1))
    shell = hollow_surface(box, 0.01)
    np.testing.assert_allclose(shell.cavity.bounds, box.bounds + [[0.01] * 3, [-0.01] * 3],
                               atol=1e-15)


def test_wall_at_the_inscribed_radius_keeps_the_part_solid():
    box = trimesh.creation.box((0.4, 0.2, 0.1))
    almost = hollow_surface(box, 0.0499)
    assert not almost.is_solid
    assert almost.volume == pytest.approx(_box_shell((0.4, 0.2, 0.1), 0.0499), rel=1e-9)
    for t in (0.05, 0.2):
        solid = hollow_surface(box, t)
        assert solid.is_solid and solid.method == "solid" and solid.cavity is None
        assert solid.mesh is box and solid.volume == pytest.approx(0.008, rel=1e-12)


@pytest.mark.parametrize("t", [0.0, -0.01, np.nan, np.inf])
def test_wall_must_be_a_positive_length(t):
    with pytest.raises(ValueError, match="positive length"):
        hollow_surface(trimesh.creation.box((0.1, 0.1, 0.1)), t)


def test_open_surface_is_refused():
    box = trimesh.creation.box((0.1, 0.1, 0.1))
    box.update_faces([True] * 10 + [False] * 2)
    with pytest.raises(MeshError, match="open"):
        hollow_surface(box, 0.01)


def _l_shape(scale=0.1) -> trimesh.Trimesh:
    """An L-section bar: [0,2]x[0,1] u [0,1]x[0,2] in x, y, 1 deep in z, times ``scale``."""
    from manifold3d import Manifold

    union = (Manifold.cube((2.0, 1.0, 1.0)) + Manifold.cube((1.0, 2.0, 1.0))).to_mesh64()
    vertices = np.array(union.vert_properties)[:, :3] * scale
    return trimesh.Trimesh(vertices, np.array(union.tri_verts, dtype=np.int64), process=False)


def _l_shell_volume(t, scale=0.1) -> float:
    """Exact: the section eroded by t (a quarter disc of radius t stays off the concave
    corner) times the depth less two walls."""
    s = t / scale
    section = 2 * (2 - 2 * s) * (1 - 2 * s) - (1 - 2 * s) ** 2 + s**2 * (1 - np.pi / 4)
    return scale**3 * (3 - section * (1 - 2 * s))


def test_non_convex_l_shape_is_eroded():
    surface = _moved(_l_shape())
    shell = hollow_surface(surface, 0.01)
    assert shell.method == "erosion"
    _assert_closed_shell(shell, surface)
    # the ball swept along the concave edge is an inscribed polyhedron: the fillet there
    # comes out slightly thinner, never thicker (1.1e-4 of the volume here)
    assert shell.volume == pytest.approx(_l_shell_volume(0.01), rel=5e-4)
    assert shell.volume < _l_shell_volume(0.01)


def test_cast_link_is_eroded_to_one_genus_2_skin():
    link = hollow_link_surface(segments=12)  # 15 mm walls, two bores, a hand hole
    shell = hollow_surface(link, 0.005)
    assert shell.method == "erosion"
    _assert_closed_shell(shell, link)
    assert shell.cavity.body_count == 1 and shell.cavity.euler_number == -2
    assert 0.95 * link.area * 0.005 < shell.volume < link.area * 0.005


@pytest.mark.skipif(not IRB_LINKS, reason="shared IRB 4600 data not present")
@pytest.mark.parametrize("path", IRB_LINKS, ids=lambda p: p.stem)
def test_irb4600_links_hollow_to_a_10mm_shell(path):
    t = 0.010
    surface = load_surface(path)
    shell = hollow_surface(surface, t, name=path.name)
    assert shell.method == "convex"
    _assert_closed_shell(shell, surface)
    # Inner parallel body: V = A t - M t^2 + O(t^3), M = int of mean curvature
    # = 1/2 sum(edge length * angle between the face normals).
    edges = np.diff(surface.vertices[surface.face_adjacency_edges], axis=1)[:, 0]
    mean_curvature = 0.5 * (surface.face_adjacency_angles * np.linalg.norm(edges, axis=1)).sum()
    area = surface.area
    assert 0.75 * area * t < shell.volume < area * t
    assert shell.volume == pytest.approx(area * t - mean_curvature * t**2, rel=0.05)


def test_tet_mesh_of_a_hollow_box_has_the_shell_volume():
    shell = hollow_surface(trimesh.creation.box((0.2, 0.1, 0.06)), 0.01)
    tets = tetrahedralize(shell.mesh, 0.01, cache=False, name="hollow box")
    assert tets.volumes().sum() == pytest.approx(shell.volume, rel=5e-3)
    assert tets.volumes().sum() == pytest.approx(_box_shell((0.2, 0.1, 0.06), 0.01), rel=5e-3)


def test_irb_shells_stay_closed_through_an_stl_file():
    """Offset planes of nearly coplanar facets meet in corner clusters: merged, the cavity
    survives a float32 STL round trip (a file reader merges vertices)."""
    import io

    for path in IRB_LINKS:
        shell = hollow_surface(load_surface(path), 0.016).mesh
        back = trimesh.load(io.BytesIO(shell.export(file_type="stl")), file_type="stl")
        assert back.is_watertight, path.name
        assert back.volume == pytest.approx(shell.volume, rel=1e-6)
