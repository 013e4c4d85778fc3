"""build_arm warns once, naming the joints, when a robot's joint stiffness is a placeholder
(a URDF import); a robot with given stiffness builds silently."""

from __future__ import annotations

import warnings
from dataclasses import replace

import pytest

from flexarm.assembly.arm import build_arm


def test_placeholder_stiffness_warns_once_naming_the_joints(demo_robot):
    joints = tuple(replace(j, model=replace(j.model, source="placeholder")) if i in (1, 4) else j
                   for i, j in enumerate(demo_robot.joints))
    robot = replace(demo_robot, joints=joints)
    with pytest.warns(UserWarning) as caught:
        build_arm(robot)
    assert len(caught) == 1
    msg = str(caught[0].message)
    assert msg.startswith(f"robot '{robot.name}': joints joint_2, joint_5 have placeholder "
                          "stiffness (not measured); identify it with `flexarm diagnose ")
    assert "\n" not in msg and caught[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build_arm(demo_robot)


def test_one_placeholder_joint_is_named_in_the_singular(demo_robot):
    joints = (replace(demo_robot.joints[0], model=replace(demo_robot.joints[0].model,
                                                          source="placeholder")),
              *demo_robot.joints[1:])
    with pytest.warns(UserWarning, match="^robot '.*': joint joint_1 has placeholder stiffness"):
        build_arm(replace(demo_robot, joints=joints))
