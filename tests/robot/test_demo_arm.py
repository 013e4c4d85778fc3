"""The shipped demo arm: reproducible CAD, masses, kinematics of DESIGN §4."""

import numpy as np
import pytest

from flexarm.robot.demo_arm import demo_robot_path, generate


def test_regenerates_byte_identical(tmp_path):
    # the CAD and the robot file; the pinned tetrahedra are data (fTetWild differs per run)
    shipped = demo_robot_path().parent
    generate(tmp_path)
    files = sorted(p.relative_to(shipped) for p in shipped.rglob("*")
                   if p.is_file() and p.parent.name != "tets")
    assert len(files) == 8
    for rel in files:
        assert (tmp_path / rel).read_bytes() == (shipped / rel).read_bytes(), rel
    assert sorted(p.name for p in (shipped / "tets").iterdir()) == sorted(
        f"{lk}_{h}mm.vtu" for lk in ("base", "frame", "lower_arm", "arm_housing", "tube_shaft",
                                      "tilt_housing", "turning_disc") for h in (30, 45, 60))


def test_pinned_meshes_fill_the_cad_and_serve_every_analysis(demo_robot):
    from flexarm.assembly.build import link_mesh
    from flexarm.meshes import load_surface, read_volume_mesh
    from flexarm.robot.demo_arm import PINNED_SIZES

    for lk in demo_robot.links:
        cad = load_surface(lk.mesh).volume
        for h in PINNED_SIZES:
            pinned = read_volume_mesh(lk.volume_meshes[h])
            mesh = link_mesh(lk, h)
            np.testing.assert_array_equal(mesh.points, pinned.points)
            np.testing.assert_array_equal(mesh.tets, pinned.tets)
            # fTetWild's envelope keeps the solid to a fraction of a per cent
            assert pinned.volumes().sum() == pytest.approx(cad, rel=0.01), (lk.name, h)
            assert pinned.volumes().min() > 0


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
