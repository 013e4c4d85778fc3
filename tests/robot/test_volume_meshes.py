"""A link's volume meshes read from files: TOML slot, order promotion, refusals."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flexarm.assembly.build import link_mesh
from flexarm.fe.mesh import TetMesh
from flexarm.meshes import write_volume_mesh
from flexarm.robot.formats import toml as robot_toml
from flexarm.robot.volume_meshes import pinned_mesh


def _box_link(robot, tmp_path, mesh: TetMesh, name="frame.vtu"):
    """The demo arm's frame link with ``mesh`` pinned at 20 mm (CAD check switched off)."""
    path = tmp_path / name
    write_volume_mesh(path, mesh)
    lk = dataclasses.replace(robot.links[1], mesh=None, volume_meshes={0.02: path})
    return lk, path


def test_pinned_file_is_used_at_its_size_only(demo_robot, tmp_path):
    box = TetMesh.box((0.4, 0.1, 0.1), (8, 2, 2))
    lk, _ = _box_link(demo_robot, tmp_path, box)
    mesh = link_mesh(lk, 0.02 * (1 + 1e-12))
    np.testing.assert_array_equal(mesh.points, box.points)
    np.testing.assert_array_equal(mesh.tets, box.tets)
    assert pinned_mesh(lk, 0.03) is None
    with pytest.raises(ValueError, match="links.frame: no mesh"):
        link_mesh(lk, 0.03)


def test_tet4_file_serves_tet10_by_straight_mid_side_nodes(demo_robot, tmp_path):
    box = TetMesh.box((0.4, 0.1, 0.1), (8, 2, 2))
    lk, _ = _box_link(demo_robot, tmp_path, box)
    tet10 = link_mesh(lk, 0.02, order=2)
    assert tet10.order == 2 and tet10.n_tets == box.n_tets
    np.testing.assert_allclose(tet10.volumes().sum(), 0.4 * 0.1 * 0.1, rtol=1e-12)
    # the mid-side node of every edge is the mean of its corners
    p = tet10.points[tet10.tets]
    np.testing.assert_allclose(p[:, 4], (p[:, 0] + p[:, 1]) / 2, atol=1e-15)


def test_tet10_file_is_refused_for_tet4_models(demo_robot, tmp_path):
    lk, _ = _box_link(demo_robot, tmp_path, TetMesh.box((0.4, 0.1, 0.1), (4, 1, 1), order=2))
    with pytest.raises(ValueError, match=r"links.frame.volume_meshes.'0.02': frame.vtu holds "
                                         r"Tet10 elements, the model asks for element_order = 1"):
        link_mesh(lk, 0.02)


def test_mesh_of_another_solid_is_refused(demo_robot, tmp_path):
    # the base link's pinned mesh given to the frame: volumes differ by far more than 5 %
    frame, base = demo_robot.links[1], demo_robot.links[0]
    lk = dataclasses.replace(frame, volume_meshes={0.03: base.volume_meshes[0.03]})
    with pytest.raises(ValueError, match=r"links.frame.volume_meshes.'0.03': base_30mm.vtu "
                                         r"holds .* m\^3 of tetrahedra but the CAD encloses"):
        link_mesh(lk, 0.03)
    # in millimetres it would be 1e9 times the CAD's volume: refused the same way
    metres = link_mesh(base, 0.03)
    mm = TetMesh(metres.points * 1e3, metres.tets)
    path = tmp_path / "base_mm.vtu"
    write_volume_mesh(path, mm)
    with pytest.raises(ValueError, match="not a mesh of this link in metres"):
        link_mesh(dataclasses.replace(base, volume_meshes={0.03: path}), 0.03)


def test_mesh_of_a_link_of_like_volume_is_refused_by_its_extent(demo_robot):
    # lower_arm's CAD encloses 11 % more than arm_housing's: the volume alone would pass
    lower, housing = demo_robot.links[2], demo_robot.links[3]
    lk = dataclasses.replace(housing, volume_meshes={0.03: lower.volume_meshes[0.03]})
    with pytest.raises(ValueError, match=r"links.arm_housing.volume_meshes.'0.03': "
                                         r"lower_arm_30mm.vtu reaches [\d.]+ mm past or short "
                                         r"of the CAD's bounding box: not a mesh of this link"):
        link_mesh(lk, 0.03)


def test_a_coarse_mesh_that_loses_its_chords_is_accepted(demo_robot, tmp_path):
    # the turning disc's pinned mesh with its volume cut by 12 % about its centroid
    # direction-wise (as coarse chords cut a curved part) but its extreme points kept
    disc = demo_robot.links[6]
    mesh = link_mesh(disc, 0.03)
    keep = mesh.points.copy()
    centre = mesh.points.mean(axis=0)
    hull = np.isin(np.arange(mesh.n_nodes), np.unique(np.concatenate([
        np.argmin(mesh.points, axis=0), np.argmax(mesh.points, axis=0)])))
    shrunk = np.where(hull[:, None], keep, centre + (keep - centre) * 0.96)
    path = tmp_path / "disc_coarse.vtu"
    write_volume_mesh(path, TetMesh(shrunk, mesh.tets))
    lost = 1.0 - TetMesh(shrunk, mesh.tets).volumes().sum() / mesh.volumes().sum()
    assert 0.08 < lost < 0.25
    pinned = link_mesh(dataclasses.replace(disc, volume_meshes={0.03: path}), 0.03)
    np.testing.assert_array_equal(pinned.points, shrunk)


def test_toml_slot_round_trips_and_names_bad_entries(demo_robot, tmp_path):
    robot_toml.write(tmp_path / "r.toml", demo_robot)
    back = robot_toml.read(tmp_path / "r.toml")
    for a, b in zip(back.links, demo_robot.links, strict=True):
        assert a.volume_meshes == b.volume_meshes
    data = robot_toml.to_dict(demo_robot, tmp_path)
    data["links"][2]["volume_meshes"] = {"0.03": "nowhere.vtu"}
    with pytest.raises(ValueError, match=r"links.lower_arm.volume_meshes.'0.03': file not "
                                         r"found: 'nowhere.vtu'"):
        robot_toml.from_dict(data, tmp_path, source=None)
    data["links"][2]["volume_meshes"] = {"fine": str(demo_robot.links[2].volume_meshes[0.03])}
    with pytest.raises(ValueError, match="key 'fine' must be a tet edge length in metres"):
        robot_toml.from_dict(data, tmp_path, source=None)


def test_a_second_process_checks_the_pinned_meshes_without_reading_the_cad(tmp_path):
    """The CAD extents and volumes that the unit and pinned-mesh checks compare with are
    cached by the file's bytes: the first process on an empty cache reads the STL files
    (trimesh), the next one builds the demo E-model from its pinned meshes without them."""
    import os
    import subprocess
    import sys

    script = ("import sys\n"
              "from flexarm.robot import load_robot\n"
              "from flexarm.assembly.emodel import emodel\n"
              "emodel(load_robot(), method='tets')\n"
              "print('trimesh' in sys.modules)\n")
    env = dict(os.environ, FLEXARM_CACHE=str(tmp_path / "cache"))
    seen = [subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                           text=True, check=True).stdout.split()[-1] for _ in range(2)]
    assert seen == ["True", "False"]
