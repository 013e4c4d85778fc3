"""Quaternions: rotation matrices against Rodrigues' formula, the matrix round trip with w >= 0,
Hamilton product rules, intrinsic x-y-z angles = Rx Ry Rz, quat_angle against the trace formula,
and SLERP midpoints (half the rotation about the same axis), all broadcast over leading axes."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.kinematics import axis_angle_matrix
from flexarm.robot.quaternions import (
    quat_angle,
    quat_conjugate,
    quat_from_intrinsic_xyz,
    quat_from_matrix,
    quat_multiply,
    quat_normalize,
    quat_to_matrix,
    slerp,
)


def _axis_angle_quat(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.r_[np.cos(angle / 2), np.sin(angle / 2) * axis]


@pytest.fixture(scope="module")
def quats():
    return quat_normalize(np.random.default_rng(0).normal(size=(2, 5, 4)))


def test_matrix_is_rodrigues():
    rng = np.random.default_rng(1)
    for _ in range(20):
        axis, angle = rng.normal(size=3), rng.uniform(-np.pi, np.pi)
        q = _axis_angle_quat(axis, angle)
        np.testing.assert_allclose(quat_to_matrix(q),
                                   axis_angle_matrix(axis / np.linalg.norm(axis), angle),
                                   atol=1e-14)
        np.testing.assert_allclose(quat_to_matrix(-3.5 * q), quat_to_matrix(q), atol=1e-15)


def test_round_trip_batched_with_nonnegative_w(quats):
    R = quat_to_matrix(quats)
    assert R.shape == (2, 5, 3, 3)
    back = quat_from_matrix(R)
    assert back.shape == (2, 5, 4) and np.all(back[..., 0] >= 0)
    np.testing.assert_allclose(back, np.where(quats[..., :1] < 0, -quats, quats), atol=1e-13)
    with pytest.raises(ValueError, match=r"rotation matrices must be \(\.\.\., 3, 3\)"):
        quat_from_matrix(np.eye(4))


def test_hamilton_product_rules(quats):
    a, b, c = quats[0, 0], quats[0, 1], quats[0, 2]
    np.testing.assert_allclose(quat_multiply(quat_multiply(a, b), c),
                               quat_multiply(a, quat_multiply(b, c)), atol=1e-15)
    np.testing.assert_allclose(quat_multiply([1, 0, 0, 0], a), a, atol=0)
    assert not np.allclose(quat_multiply(a, b), quat_multiply(b, a))
    # i j = k, j k = i, k i = j
    i, j, k = np.eye(4)[1:]
    np.testing.assert_array_equal(quat_multiply(i, j), k)
    np.testing.assert_array_equal(quat_multiply(j, k), i)
    np.testing.assert_array_equal(quat_multiply(k, i), j)
    # batched: (2, 5) x (5,) broadcast
    prod = quat_multiply(quats, quats[1])
    np.testing.assert_allclose(prod[0, 3], quat_multiply(quats[0, 3], quats[1, 3]), atol=0)
    # the conjugate is the inverse rotation: R(q*) = R(q)^T
    np.testing.assert_allclose(quat_to_matrix(quat_conjugate(quats)),
                               np.swapaxes(quat_to_matrix(quats), -1, -2), atol=1e-15)


def test_intrinsic_xyz_is_rx_ry_rz():
    angles = np.array([[30.0, -45.0, 60.0], [170.0, 10.0, -95.0]])
    q = quat_from_intrinsic_xyz(angles)
    assert q.shape == (2, 4)
    for qq, (a, b, c) in zip(q, np.radians(angles), strict=True):
        expected = (axis_angle_matrix([1, 0, 0], a) @ axis_angle_matrix([0, 1, 0], b)
                    @ axis_angle_matrix([0, 0, 1], c))
        np.testing.assert_allclose(quat_to_matrix(qq), expected, atol=1e-14)
    with pytest.raises(ValueError, match=r"angles must be \(\.\.\., 3\)"):
        quat_from_intrinsic_xyz([1.0, 2.0])


def test_angle_is_the_trace_formula_and_sign_blind(quats):
    a, b = quats[0], quats[1]
    Ra, Rb = quat_to_matrix(a), quat_to_matrix(b)
    trace = np.einsum("...ij,...ij->...", Ra, Rb)  # tr(Ra^T Rb)
    expected = np.arccos(np.clip((trace - 1) / 2, -1, 1))
    np.testing.assert_allclose(quat_angle(a, b), expected, atol=1e-7)
    np.testing.assert_allclose(quat_angle(a, -b), quat_angle(a, b), atol=0)
    assert quat_angle(a[0], a[0]) == pytest.approx(0.0, abs=2e-8)


def test_slerp_midpoint_is_half_the_rotation():
    """From q0 to q0 * rot(n, theta): the midpoint is q0 * rot(n, theta / 2)."""
    rng = np.random.default_rng(2)
    for _ in range(10):
        q0 = quat_normalize(rng.normal(size=4))
        n, theta = rng.normal(size=3), rng.uniform(0.1, 3.0)
        q1 = quat_multiply(q0, _axis_angle_quat(n, theta))
        mid = slerp(q0, q1, 0.5)
        expected = quat_multiply(q0, _axis_angle_quat(n, theta / 2))
        np.testing.assert_allclose(quat_angle(mid, expected), 0.0, atol=1e-7)
        quarter = slerp(q0, q1, [0.25, 0.75])
        np.testing.assert_allclose(quat_angle(q0, quarter), [theta / 4, 3 * theta / 4],
                                   atol=1e-9)


def test_slerp_takes_the_shorter_way_and_broadcasts(quats):
    """A 300 deg turn about z is reached the short way: the midpoint is -30 deg about z."""
    q1 = _axis_angle_quat([0, 0, 1], np.radians(300))
    mid = slerp([1, 0, 0, 0], q1, 0.5)
    np.testing.assert_allclose(quat_to_matrix(mid), axis_angle_matrix([0, 0, 1], np.radians(-30)),
                               atol=1e-14)
    t = np.linspace(0, 1, 5)[:, None] * np.ones((1, 5))  # (5, 5) against quats[0] (5, 4)
    out = slerp(quats[0], quats[1], t)
    assert out.shape == (5, 5, 4)
    np.testing.assert_allclose(out[2, 3], slerp(quats[0, 3], quats[1, 3], 0.5), atol=1e-15)
