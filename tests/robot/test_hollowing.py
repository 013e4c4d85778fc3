"""Hollowing every link of a robot: shell masses in closed form, the wall matched to a mass,
links too thin for the wall kept solid, regions kept."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import trimesh

from flexarm.fe import MATERIALS
from flexarm.robot import Joint, JointModel, Link, Region, Robot
from flexarm.robot.hollowing import hollow_links

STEEL = MATERIALS["steel"]


def _boxes(folder, sizes):
    links = []
    for name, (a, b, c) in sizes.items():
        path = folder / f"{name}.stl"
        trimesh.creation.box((a, b, c)).export(path)
        links.append(Link(name, path, STEEL, regions={
            "j1": Region((0, 0, c / 2), (0, 0, 1), 0.0, 0.05, 0.005)}))
    joint = Joint("j1", links[0].name, links[1].name, (0, 0, 0.2), (0, 0, 1), -3, 3,
                  JointModel(1e5))
    return Robot("boxes", tuple(links), (joint,))


def _shell(a, b, c, t):
    return a * b * c - (a - 2 * t) * (b - 2 * t) * (c - 2 * t)


def test_given_wall_gives_the_closed_form_shell_mass(tmp_path):
    robot = _boxes(tmp_path, {"base": (0.4, 0.3, 0.2), "arm": (0.6, 0.1, 0.1)})
    hollowed, report = hollow_links(robot, 0.01, out_dir=tmp_path / "shells")
    for row, (a, b, c) in zip(report.links, ((0.4, 0.3, 0.2), (0.6, 0.1, 0.1)), strict=True):
        assert row.solid_mass == pytest.approx(STEEL.rho * a * b * c, rel=1e-6)  # float32 STL
        assert row.shell_mass == pytest.approx(STEEL.rho * _shell(a, b, c, 0.01), rel=1e-6)
        assert all(0 < r < 1 for r in row.bending) and not row.is_solid
    for old, new in zip(robot.links, hollowed.links, strict=True):
        assert new.mesh != old.mesh and new.mesh.parent == (tmp_path / "shells").resolve()
        assert new.regions == old.regions
        assert trimesh.load(new.mesh).is_watertight
    assert "10.0 mm walls (given)" in report.text()


def test_auto_wall_matches_the_mass_and_thin_links_stay_solid(tmp_path):
    robot = _boxes(tmp_path, {"base": (0.4, 0.3, 0.2), "plate": (0.3, 0.3, 0.02)})
    target = STEEL.rho * (_shell(0.4, 0.3, 0.2, 0.015) + 0.3 * 0.3 * 0.02)
    _, report = hollow_links(robot, "auto", mass_kg=target, out_dir=tmp_path)
    assert report.wall == pytest.approx(0.015, rel=1e-7)
    assert report.matched_mass == target
    assert [r.is_solid for r in report.links] == [False, True]
    assert "stays solid" in report.text()


def test_auto_needs_the_mass_and_the_wall_must_be_positive(tmp_path):
    robot = _boxes(tmp_path, {"base": (0.4, 0.3, 0.2), "arm": (0.6, 0.1, 0.1)})
    with pytest.raises(ValueError, match="needs the robot's mass"):
        hollow_links(robot, "auto")
    with pytest.raises(ValueError, match="positive length"):
        hollow_links(robot, -0.01)


def test_a_refused_derived_cad_names_the_users_file_as_the_urdf_writes_it(tmp_path):
    """An open mesh at flexarm's derived path (a merged link): the refusal names the file
    the URDF gave, never the derived one."""
    from flexarm.fe.errors import MeshError

    robot = _boxes(tmp_path, {"base": (0.4, 0.3, 0.2), "arm": (0.6, 0.1, 0.1)})
    derived = tmp_path / "arm-0123abcd.stl"
    box = trimesh.creation.box((0.6, 0.1, 0.1))
    trimesh.Trimesh(box.vertices, box.faces[:-2]).export(derived)  # one facet open
    robot = dataclasses.replace(robot, links=(
        robot.links[0], dataclasses.replace(robot.links[1], mesh=derived)))
    user = "package://maker_support/meshes/collision/forearm.stl"
    with pytest.raises(MeshError) as info:
        hollow_links(robot, 0.01, out_dir=tmp_path / "shells",
                     sources={"arm": (user,)})
    message = str(info.value)
    assert message.startswith(f"{user}: ") and str(derived) not in message
    assert derived.name not in message


def test_a_shell_that_does_not_read_back_is_refused_naming_the_link_and_its_file(
        tmp_path, monkeypatch):
    """The read-back check of a written shell: one message naming the link and the user's
    file, and nothing left in the folder."""
    import flexarm.robot.hollowing as hollowing
    from flexarm.fe.errors import MeshError

    robot = _boxes(tmp_path, {"base": (0.4, 0.3, 0.2), "arm": (0.6, 0.1, 0.1)})
    written = []

    def broken(mesh, folder, name):  # the shell as a disk fault would leave it: open
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{name}-shell.stl"
        trimesh.Trimesh(mesh.vertices, mesh.faces[:-2]).export(path)
        written.append(path)
        return path

    monkeypatch.setattr(hollowing, "write_derived", broken)
    with pytest.raises(MeshError) as info:
        hollow_links(robot, 0.01, out_dir=tmp_path / "shells",
                     sources={"base": ("../meshes/base.stl",)})
    message = str(info.value)
    assert message.startswith("links.base (../meshes/base.stl): hollowed to 10.0 mm walls "
                              "it does not read back closed (")
    assert "-shell.stl" not in message and not written[0].exists()


def test_overlapping_cad_bodies_weigh_once_and_hollow_to_one_clean_shell(tmp_path):
    """A link whose STL is two closed boxes that overlap (as the UR10's wrist meshes):
    its solid and its wall count the overlap once, and the shell read back from its file
    is one outer skin and one cavity that cross nowhere."""
    from flexarm.meshes import load_surface
    from flexarm.meshes.self_intersections import crossings

    robot = _boxes(tmp_path, {"base": (0.4, 0.3, 0.2), "arm": (0.2, 0.1, 0.1)})
    two = trimesh.util.concatenate([trimesh.creation.box((0.2, 0.1, 0.1)),
                                    trimesh.creation.box((0.2, 0.1, 0.1)).apply_translation(
                                        (0.1, 0.05, 0.0))])
    two.export(robot.links[1].mesh)
    hollowed, report = hollow_links(robot, 0.01, out_dir=tmp_path / "shells")
    union = 2 * 0.2 * 0.1 * 0.1 - 0.1 * 0.05 * 0.1
    assert report.links[1].solid_mass == pytest.approx(STEEL.rho * union, rel=1e-6)
    shell = load_surface(hollowed.links[1].mesh)
    assert shell.is_volume and shell.body_count == 2
    assert len(crossings(shell.vertices, shell.faces)[1]) == 0
    assert report.links[1].shell_mass == pytest.approx(STEEL.rho * float(shell.volume),
                                                       rel=1e-6)
    # the cavity: both boxes eroded by 10 mm, united, plus t^2 (1 - pi/4) along the two
    # reflex edges (80 mm inside); the level set rounds its edges by about 1 %
    cavity = 2 * 0.18 * 0.08 * 0.08 - 0.08 * 0.03 * 0.08 + 2 * 0.08 * 1e-4 * (1 - np.pi / 4)
    assert report.links[1].shell_mass == pytest.approx(STEEL.rho * (union - cavity),
                                                       rel=2e-2)
