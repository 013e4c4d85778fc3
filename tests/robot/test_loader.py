"""load_robot: None gives the shipped demo arm, a path is read by its extension (str or Path,
same robot as the demo file), unknown extensions and missing files are refused."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot import Robot, load_robot
from flexarm.robot.demo_arm import demo_robot_path
from flexarm.robot.formats import toml as robot_toml


def test_default_is_the_demo_arm(demo_robot):
    r = load_robot()
    assert isinstance(r, Robot)
    assert r.name == "flexarm demo arm (IRB 4600-60/2.05 class)"
    assert r.joint_names == tuple(f"joint_{i}" for i in range(1, 7)) and len(r.links) == 7
    assert r.source == demo_robot_path().resolve()
    assert r.joint_names == demo_robot.joint_names


def test_path_is_read_by_extension(tmp_path, demo_robot):
    path = tmp_path / "copy.toml"
    robot_toml.write(path, demo_robot)
    for source in (path, str(path)):
        r = load_robot(source)
        assert r.source == path.resolve()
        assert r.joint_names == demo_robot.joint_names
        for a, b in zip(r.joints, demo_robot.joints, strict=True):
            assert a.model == b.model and a.emodel == b.emodel
        np.testing.assert_allclose(r.pose("P3"), demo_robot.pose("P3"), atol=1e-12)
        assert r.links[2].mesh == demo_robot.links[2].mesh


def test_refusals(tmp_path):
    with pytest.raises(ValueError, match=r"robot\.yaml: unknown robot description extension "
                                         r"'\.yaml' \(known: \.toml, \.urdf\)"):
        load_robot(tmp_path / "robot.yaml")
    with pytest.raises(FileNotFoundError):
        load_robot(tmp_path / "missing.toml")
