"""The size rule for placeholder joint stiffness, against the published figures its
docstring cites (numbers only: no robot file is read here)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexarm.robot.demo_arm import JOINTS
from flexarm.robot.kinematics import Chain, link_frames
from flexarm.robot.placeholder_stiffness import (
    R_ANCHOR,
    RobotSize,
    mid_workspace_pose,
    placeholder_stiffness,
    reach,
)

#: the demo arm of the IRB 4600 class, whose springs reproduce the thesis's figures
DEMO = np.array([k for _, k, *_ in JOINTS])


def test_irb4600_size_gives_the_demo_arm_springs():
    k = np.array(placeholder_stiffness(RobotSize(425.0, 2.05)).torsion)
    # joints 2-3 7 % above the demo's 4e6 N m/rad, every share the demo's
    assert np.abs(k / DEMO - 1).max() < 0.08
    assert k[1] == pytest.approx(9.80665 * 425 * 2.05 / 2 / 1e-3)


def test_kr_class_figure_within_a_factor_three():
    # Klimchik (2011) via Zhao (2020): 1.52e-7 rad/(N m) about a KR 240-2-class axis
    k = placeholder_stiffness(RobotSize(1250.0, 2.7)).torsion[1]
    assert 1.0 < k * 1.52e-7 < 3.0  # the rule is 2.5 x stiffer


def test_band_scales_with_reach_and_holds_the_anchor():
    irb = placeholder_stiffness(RobotSize(425.0, R_ANCHOR))
    assert irb.band_hz == pytest.approx((10.0 / 1.5, 15.0))
    kr = placeholder_stiffness(RobotSize(1250.0, 2.7))
    assert np.mean(kr.band_hz) == pytest.approx(np.mean(irb.band_hz) * math.sqrt(2.05 / 2.7))
    assert kr.robot_class == irb.robot_class == "industrial"


def test_efforts_set_the_shares_of_joints_3_on():
    ur10 = placeholder_stiffness(RobotSize(28.9, 1.2, (330, 330, 150, 56, 56, 56), "datasheet"))
    k = np.array(ur10.torsion)
    assert k[2] / k[1] == pytest.approx(150 / 330) and k[5] / k[1] == pytest.approx(56 / 330)
    assert k[0] / k[1] == pytest.approx(0.1625)  # joint 1 keeps the lateral share
    assert ur10.robot_class == "lightweight" and "URDF efforts" in ur10.text()
    # an effort missing on one joint (0 in the file): the shares are the demo's
    half = placeholder_stiffness(RobotSize(28.9, 1.2, (330, 330, 150, 56, 56, 0)))
    assert half.size.effort is None and half.torsion[2] == half.torsion[1]


def test_bad_size_is_one_error():
    with pytest.raises(ValueError, match="mass > 0 kg and a reach > 0 m"):
        placeholder_stiffness(RobotSize(0.0, 1.0))


def _arm(q2_sign: float = 1.0) -> Chain:
    return Chain(origins=[[0, 0, 0.5], [0.2, 0, 0], [0, 0, 0.8], [0.3, 0, 0], [0.4, 0, 0],
                          [0.1, 0, 0]],
                 axes=[[0, 0, 1], [0, q2_sign, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]],
                 parents=[0, 1, 2, 3, 4, 5])


LOWER, UPPER = [-3, -2, -3, -3, -2, -3], [3, 2, 3, 3, 2, 3]


def test_reach_and_mid_pose_of_a_planar_arm():
    ch = _arm()
    assert reach(ch, LOWER, UPPER) == pytest.approx(1.7, abs=2e-3)
    q = mid_workspace_pose(ch, LOWER, UPPER)
    F = link_frames(ch, q)
    wrist, elbow = F[5, :3, 3], F[3, :3, 3]
    assert wrist[0] == pytest.approx(0.6 * 1.7, abs=0.05) and wrist[2] == pytest.approx(0.5,
                                                                                        abs=0.05)
    assert elbow[2] > 0.5  # elbow up
    # a joint-2 axis flipped in the file: the same pose in space
    q_flip = mid_workspace_pose(_arm(-1.0), LOWER, UPPER)
    assert link_frames(_arm(-1.0), q_flip)[5, :3, 3] == pytest.approx(wrist, abs=0.06)


def test_reach_is_limited_by_the_joint_limits():
    # joint 2 cannot lean forward past upright: the wrist reaches 0.2 + 0.7 only
    assert reach(_arm(), [-3, -2, -3, -3, -2, -3], [3, 0, 0, 3, 2, 3]) < 1.7 - 0.3
