"""Inverse kinematics: every solution reproduces the given TCP frame under forward kinematics
(branches, joint limits, turns of joints 4/6, the wrist singularity, DLS), pose_error against the
rotation vector of a known rotation, and the refusals (reach, chain shape, convergence)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flexarm.fe.errors import ConvergenceError
from flexarm.robot.ik import IKConfig, ik, ik_analytic, ik_dls, is_spherical_wrist_arm, pose_error
from flexarm.robot.kinematics import Chain, axis_angle_matrix, tcp_frame

ORIGINS = [[0, 0, 0.495], [0.175, 0, 0], [0, 0, 0.9], [0, 0, 0.175], [0.96, 0, 0],
           [0.135, 0, 0]]
AXES = [[0, 0, 1], [0, 1, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]]


def _chain(**kw):
    args = {"origins": ORIGINS, "axes": AXES, "parents": range(6)} | kw
    return Chain(**args)


def _close(chain, q, T, tol=1e-9):
    return np.abs(tcp_frame(chain, q) - T).max() < tol


def test_pose_error_is_translation_and_rotation_vector():
    rng = np.random.default_rng(0)
    current = np.eye(4)
    current[:3, :3] = axis_angle_matrix([0.0, 0.6, 0.8], 1.1)
    current[:3, 3] = [0.3, -0.2, 1.0]
    for angle in (0.0, 1e-7, 0.4, 2.5):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        target = current.copy()
        target[:3, :3] = axis_angle_matrix(axis, angle) @ current[:3, :3]
        target[:3, 3] += [0.01, 0.0, -0.02]
        e = pose_error(current, target)
        np.testing.assert_allclose(e[:3], [0.01, 0.0, -0.02], atol=1e-15)
        np.testing.assert_allclose(e[3:], angle * axis, atol=1e-12)


def test_ik_config_branches():
    configs = IKConfig.all()
    assert len(configs) == len(set(configs)) == 8
    assert IKConfig() == IKConfig("front", "up", "noflip")


def test_every_branch_reproduces_the_pose(demo_robot):
    ch = demo_robot.chain
    rng = np.random.default_rng(1)
    for q in rng.uniform(demo_robot.lower, demo_robot.upper, size=(20, 6)):
        T = tcp_frame(ch, q)
        found = 0
        for cfg in IKConfig.all():
            qs = ik_analytic(ch, T, cfg)
            if np.isnan(qs).any():
                continue
            found += 1
            assert _close(ch, qs, T)
            assert np.all(np.abs(qs) <= np.pi)
            assert (qs[4] >= 0) == (cfg.wrist == "noflip")
        assert found >= 2  # at least the two wrist branches of one arm branch


def test_joint_limits_pick_another_branch(demo_robot):
    """P1 has q5 < 0; with q5 >= 0.1 rad required the noflip branch must be chosen."""
    ch, q1 = demo_robot.chain, demo_robot.pose("P1")
    T = tcp_frame(ch, q1)
    lower = demo_robot.lower.copy()
    lower[4] = 0.1
    q = ik(ch, T, q_near=q1, lower=lower, upper=demo_robot.upper)
    assert _close(ch, q, T) and q[4] >= 0.1
    assert np.all(q >= lower) and np.all(q <= demo_robot.upper)
    # it is the feasible branch nearest P1 (joints 4 and 6 on their nearest turn)
    candidates = []
    for cfg in IKConfig.all():
        c = ik_analytic(ch, T, cfg)
        if not np.isnan(c).any() and c[4] >= 0.1:
            c[[3, 5]] += 2 * np.pi * np.round((q1[[3, 5]] - c[[3, 5]]) / (2 * np.pi))
            candidates.append(c)
    assert len(candidates) == 2
    best = min(candidates, key=lambda c: np.sum((c - q1) ** 2))
    np.testing.assert_allclose(q, best, atol=1e-12)
    with pytest.raises(ValueError, match=r"out of reach \(or outside the joint limits\)"):
        ik(ch, T, q_near=q1, lower=np.full(6, 2.0), upper=np.full(6, 3.0))


def test_fixed_config_and_extra_turns_of_joints_4_and_6(demo_robot):
    ch, q1 = demo_robot.chain, demo_robot.pose("P1")
    T = tcp_frame(ch, q1)
    near = q1 + [0, 0, 0, 2 * np.pi, 0, -2 * np.pi]
    q = ik(ch, T, q_near=near, lower=demo_robot.lower, upper=demo_robot.upper)
    np.testing.assert_allclose(q, near, atol=1e-9)  # 372 deg and -371 deg: within +-400
    cfg = IKConfig("front", "up", "flip")
    q = ik(ch, T, config=cfg)
    assert _close(ch, q, T)
    np.testing.assert_allclose(q, ik_analytic(ch, T, cfg), atol=1e-12)


def test_wrist_singularity_keeps_q4_zero():
    """q5 = 0: only q4 + q6 is defined; the closed form returns q4 = 0, q6 = q4 + q6."""
    ch = _chain()
    q = np.array([0.2, 0.3, -0.1, 0.5, 0.0, 0.4])
    T = tcp_frame(ch, q)
    qs = ik_analytic(ch, T, IKConfig("front", "down", "noflip"))
    if not _close(ch, qs, T):  # the other elbow branch holds the pose
        qs = ik_analytic(ch, T, IKConfig("front", "up", "noflip"))
    assert _close(ch, qs, T)
    assert qs[3] == 0.0 and qs[4] == pytest.approx(0.0, abs=1e-12)
    assert qs[5] == pytest.approx(0.9, abs=1e-12)


def test_out_of_reach_gives_nan_and_refusal():
    ch = _chain()
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 1.0]
    assert np.isnan(ik_analytic(ch, T)).all()
    with pytest.raises(ValueError, match="target TCP frame is out of reach"):
        ik(ch, T)


@pytest.mark.parametrize("change", [
    {"origins": [*ORIGINS[:4], [0.96, 0, 0.05], ORIGINS[5]]},  # wrist centre offset
    {"origin_R": np.array([np.eye(3)] * 5 + [axis_angle_matrix([1, 0, 0], 0.1)])},
    {"tcp_body": 5},
])
def test_non_spherical_chains_go_through_dls(change):
    ch = _chain(**change)
    assert not is_spherical_wrist_arm(ch)
    q = np.array([0.3, 0.2, -0.4, 0.5, 0.3, -0.2])
    T = tcp_frame(ch, q)
    with pytest.raises(ValueError, match="needs a spherical-wrist 6R arm; use ik_dls"):
        ik_analytic(ch, T)
    if ch.tcp_body == 6:
        assert _close(ch, ik(ch, T, q_near=q + 0.05), T)


def test_five_joint_chain_is_not_spherical():
    ch = Chain(origins=ORIGINS[:5], axes=AXES[:5], parents=range(5))
    assert not is_spherical_wrist_arm(ch)


def test_dls_convergence_error():
    ch = _chain()
    q = np.array([0.3, 0.2, -0.4, 0.5, 0.3, -0.2])
    with pytest.raises(ConvergenceError, match=r"ik_dls: pose error .* after 2 steps"):
        ik_dls(ch, tcp_frame(ch, q), q + 0.5, max_iter=2)
    np.testing.assert_array_equal(ik_dls(ch, tcp_frame(ch, q), q), q)  # already there


def test_demo_tool_offset_is_honoured(demo_robot):
    """The closed form removes the tool (150 mm, rotated 90 deg) before solving."""
    ch = demo_robot.chain
    bare = dataclasses.replace(ch, tool=np.eye(4))
    q = demo_robot.pose("P3")
    T = tcp_frame(ch, q)
    qs = ik(ch, T, q_near=q)
    np.testing.assert_allclose(tcp_frame(bare, qs), tcp_frame(bare, q), atol=1e-9)
