"""The shipped demo arm: reproducible CAD, masses, kinematics of DESIGN §4."""

import numpy as np
import pytest

from flexarm.robot.demo_arm import demo_robot_path, generate


def test_regenerates_byte_identical(tmp_path):
    shipped = demo_robot_path().parent
    generate(tmp_path)
    files = sorted(p.relative_to(shipped) for p in shipped.rglob("*") if p.is_file())
    assert len(files) == 8
    for rel in files:
        assert (tmp_path / rel).read_bytes() == (shipped / rel).read_bytes(), rel


def test_meshes_are_closed_castings(demo_robot):
    import trimesh

    for lk in demo_robot.links:
        m = trimesh.load(lk.mesh, force="mesh")
        assert m.is_watertight and m.is_volume, lk.name
        assert 300 <= len(m.faces) <= 5000, lk.name
        # hollow: the solid fills well under half its convex hull (except the solid disc)
        if lk.name != "turning_disc":
            assert m.volume < 0.5 * m.convex_hull.volume, lk.name


def test_design_kinematics(demo_robot):
    o = np.array([j.origin for j in demo_robot.joints])
    assert np.allclose(o, [[0, 0, 0.495], [0.175, 0, 0], [0, 0, 0.9], [0, 0, 0.175],
                           [0.96, 0, 0], [0.135, 0, 0]])
    lim = np.degrees([[j.lower, j.upper] for j in demo_robot.joints])
    assert np.allclose(lim, [[-180, 180], [-90, 150], [-180, 75], [-400, 400], [-125, 120],
                             [-400, 400]])


def test_total_mass_surface(demo_robot):
    from flexarm.assembly.emodel import total_mass

    assert total_mass(demo_robot, method="surface") == pytest.approx(425, rel=0.03)


def test_joint_seat_regions_catch_mesh_nodes(demo_robot):
    import trimesh

    for lk in demo_robot.links:
        v = trimesh.load(lk.mesh, force="mesh").vertices
        for name, reg in lk.regions.items():
            assert reg.contains(v).sum() >= 8, (lk.name, name)
