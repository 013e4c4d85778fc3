# ruff: noqa: E501
import math

import numpy as np
import pytest
import tomllib

from flexarm.fe.errors import ReadError
from flexarm.robot.demo_arm import demo_robot_path
from flexarm.robot.formats import toml as robot_toml
from flexarm.robot.formats.toml import from_dict


@pytest.fixture
def demo_data():
    with open(demo_robot_path(), "rb") as f:
        return tomllib.load(f)


def build(data):
    return from_dict(data, demo_robot_path().parent)


def test_demo_loads(demo_robot):
    assert len(demo_robot.joints) == 6 and len(demo_robot.links) == 7
    assert demo_robot.poses["P1"][1] == pytest.approx(math.radians(52))
    assert demo_robot.joints[1].lower == pytest.approx(math.radians(-90))
    assert demo_robot.links[1].mesh.is_file()
    assert set(demo_robot.links[2].regions) == {"joint_2", "joint_3"}


def test_write_read_round_trip(demo_robot, tmp_path):
    path = tmp_path / "sub" / "robot.toml"
    robot_toml.write(path, demo_robot)
    back = robot_toml.read(path)
    assert back.joint_names == demo_robot.joint_names
    assert back.links[3].mesh == demo_robot.links[3].mesh
    for a, b in zip(back.joints, demo_robot.joints, strict=True):
        assert a.model == b.model and a.origin == b.origin
        assert a.lower == pytest.approx(b.lower, abs=1e-15)
    for k in demo_robot.poses:
        assert np.allclose(back.poses[k], demo_robot.poses[k], atol=1e-12)
    assert back.links[1].lumped == demo_robot.links[1].lumped
    assert back.links[1].regions == demo_robot.links[1].regions


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda d: d["joints"][1].update(parent="nolink"), "joints.joint_2.parent: unknown link 'nolink'"),
        (lambda d: d["joints"][2].update(axis=[0, 1.1, 0]), "joints.joint_3.axis must be a unit vector"),
        (lambda d: d["joints"][0].update(limits_deg=[90, -90]), "joints.joint_1.limits reversed"),
        (lambda d: d["links"][2].update(mesh="meshes/missing.stl"), "links.lower_arm.mesh: file not found: 'meshes/missing.stl'"),
        (lambda d: d["joints"][1]["model"].update(torsion=-3e6), "joints.joint_2.model.torsion must be > 0"),
        (lambda d: d["joints"][0]["model"].update(tilt=-1.0), "joints.joint_1.model.tilt must be > 0"),
        (lambda d: d["poses"].update(P9=[0, 170, 0, 0, 0, 0]), "poses.P9: joint_2 = 170 deg outside limits"),
        (lambda d: d["links"][3].update(material="cheese"), "links.arm_housing.material: unknown material 'cheese'"),
        (lambda d: d["joints"][3]["model"].update(torsoin=1.0), "joints.joint_4.model: unknown key 'torsoin'"),
        (lambda d: d["joints"][4].update(child="base"), "joints.joint_5.child must be 'tilt_housing'"),
        (lambda d: d["links"][1]["lumped"][0].update(mass=-2.0), "mass must be >= 0 kg, got -2.0"),
        (lambda d: d["base"].update(support="floating"), "base.support must be clamped|spring, got 'floating'"),
    ],
)
def test_validation_messages(demo_data, edit, message):
    edit(demo_data)
    with pytest.raises(ValueError) as exc:
        build(demo_data)
    assert message in str(exc.value)


def test_read_error_names_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('format_version = 1\n[[joints]]\nname = "j"\n')
    with pytest.raises(ReadError, match="bad.toml"):
        robot_toml.read(bad)


def test_pose_lookup(demo_robot):
    with pytest.raises(ValueError, match="unknown pose 'P7'"):
        demo_robot.pose("P7")
    assert np.allclose(demo_robot.pose([0.1] * 6), 0.1)


def test_spring_base(demo_data):
    demo_data["base"] = {"support": "spring", "stiffness": [1e9, 1e9, 1e9, 1e8, 1e8, 1e8]}
    r = build(demo_data)
    from flexarm.assembly.analyses import tcp_compliance
    from flexarm.assembly.emodel import emodel

    arm = emodel(r, method="surface")
    assert arm.layout["n"] == 18
    q = r.pose("P1")
    demo_data["base"] = {"support": "clamped"}
    C_clamped = tcp_compliance(emodel(build(demo_data), method="surface"), q)
    C_spring = tcp_compliance(arm, q)
    assert np.all(np.diag(C_spring) > np.diag(C_clamped))
