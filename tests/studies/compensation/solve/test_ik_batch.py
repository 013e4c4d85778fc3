import numpy as np

from flexarm.robot.kinematics import tcp_frame
from flexarm.robot.quaternions import quat_from_matrix, quat_to_matrix
from flexarm.studies.compensation.solve.ik_batch import (
    displaced,
    newton_ik,
    pose_errors,
    rotation_matrices,
    rotation_vectors,
)


def test_log_and_exp_maps_invert_each_other_up_to_pi():
    rng = np.random.default_rng(0)
    axes = rng.standard_normal((200, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    angles = np.r_[rng.uniform(0, np.pi - 1e-6, 197), 0.0, 1e-12, np.pi - 1e-9]
    v = axes * angles[:, None]
    R = rotation_matrices(v)
    assert np.allclose(R @ np.swapaxes(R, -1, -2), np.eye(3), atol=1e-14)
    assert np.allclose(np.linalg.det(R), 1.0)
    assert np.abs(rotation_vectors(R) - v).max() < 1e-7  # pi itself is two-valued
    # the same rotation as the quaternion of the axis and angle (an independent formula)
    q = np.c_[np.cos(angles / 2), axes * np.sin(angles / 2)[:, None]]
    assert np.allclose(R, quat_to_matrix(q), atol=1e-14)


def test_pose_errors_undo_displaced():
    rng = np.random.default_rng(1)
    T = np.tile(np.eye(4), (20, 1, 1))
    T[:, :3, :3] = quat_to_matrix(quat_from_matrix(rotation_matrices(rng.normal(0, 1, (20, 3)))))
    T[:, :3, 3] = rng.normal(0, 1, (20, 3))
    d = rng.normal(0, 1e-3, (20, 6))
    assert np.abs(pose_errors(T, displaced(T, d)) - d).max() < 1e-15


def test_newton_ik_reaches_every_pose_from_a_far_seed(robot):
    rng = np.random.default_rng(2)
    q = np.radians([0, 40, 0, 20, 50, 10]) + rng.uniform(-0.4, 0.4, (300, 6))
    T = tcp_frame(robot.chain, q)
    sol, err = newton_ik(robot.chain, T, np.tile(np.radians([0, 40, 0, 20, 50, 10]), (300, 1)))
    assert err.max() < 1e-11
    assert np.abs(tcp_frame(robot.chain, sol) - T).max() < 1e-11
    assert np.abs(sol - q).max() < 1e-8  # the seed's branch is the one q lies on
