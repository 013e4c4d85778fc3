"""Statics of the two-link arm against hand statics: joint moments M_j = M + (p - p_j) x F +
sum (c_i - p_j) x m_i g in the joint basis, their sign (u = J tau / k), payloads, body masses,
joint screws, series references and relative deflections with backlash and hardening laws."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.analyses import GRAVITY, tcp_compliance
from flexarm.assembly.bodies import Body
from flexarm.assembly.examples import two_link_arm
from flexarm.assembly.nonlinear import Backlash, Hardening
from flexarm.assembly.statics import (
    body_masses,
    joint_moments,
    joint_screws,
    relative_deflection,
    series_starts,
)
from flexarm.robot.kinematics import jacobian

K1, K2, L, MASS = 1e4, 2e4, 1.0, 10.0


def _rz(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def hand_moments(q, force, moment, payload=0.0, gravity=True):
    """Joint moments in (axis z, radial x_link, radial y_link) of the planar two-link arm."""
    q1, q2 = q
    e1, e12 = np.array([np.cos(q1), np.sin(q1), 0]), np.array([np.cos(q1 + q2),
                                                               np.sin(q1 + q2), 0])
    p1, p2, tip = np.zeros(3), L * e1, L * e1 + L * e12
    weights = [(L / 2 * e1, MASS), (p2 + L / 2 * e12, MASS)] if gravity else [None, None]
    out = []
    for j, (pj, theta) in enumerate([(p1, q1), (p2, q1 + q2)]):
        M = np.asarray(moment, float) + np.cross(tip - pj, force)
        for i in range(j, 2):
            if weights[i] is not None:
                M = M + np.cross(weights[i][0] - pj, weights[i][1] * GRAVITY)
        M = M + np.cross(tip - pj, payload * GRAVITY)
        E = _rz(theta)[:, [2, 0, 1]]  # joint basis of a z axis: (z, x, y) of the link frame
        out.append(E.T @ M)
    return np.array(out)


@pytest.mark.parametrize("q", [(0.0, 0.0), (0.4, -1.1), (2.0, 2.5)])
def test_joint_moments_are_hand_statics(q):
    arm = two_link_arm(K1, K2, L, MASS)
    F, Mo = np.array([30.0, -120.0, 45.0]), np.array([2.0, -3.0, 5.0])
    np.testing.assert_allclose(joint_moments(arm, q, F, Mo), hand_moments(q, F, Mo), atol=1e-10)
    np.testing.assert_allclose(joint_moments(arm, q, F, gravity=False),
                               hand_moments(q, F, np.zeros(3), gravity=False), atol=1e-10)
    np.testing.assert_allclose(
        joint_moments(arm, q, np.zeros(3), gravity=False, extra_masses=[(2, 4.0, [L, 0, 0])]),
        hand_moments(q, np.zeros(3), np.zeros(3), payload=4.0, gravity=False), atol=1e-10)


def test_joint_moments_batched_and_signed_like_the_springs():
    """u = C w = J diag(1/k) tau: a positive torque turns the joint by +tau / k."""
    arm = two_link_arm(K1, K2, L, MASS)
    rng = np.random.default_rng(3)
    Q = rng.uniform(-np.pi, np.pi, size=(6, 2))
    F = rng.normal(size=(6, 3)) * 100
    tau = joint_moments(arm, Q, F, gravity=False)
    assert tau.shape == (6, 2, 3)
    for k in range(6):
        np.testing.assert_allclose(tau[k], hand_moments(Q[k], F[k], np.zeros(3), gravity=False),
                                   atol=1e-10)
    u = np.einsum("nij,nj->ni", tcp_compliance(arm, Q)[:, :, :3], F)
    J = jacobian(arm.chain, Q)
    np.testing.assert_allclose(u, np.einsum("nij,nj->ni", J, tau[:, :, 0] / [K1, K2]),
                               atol=1e-14)


def test_body_masses():
    m, c = body_masses(two_link_arm(mass=7.0, length=2.0))
    np.testing.assert_allclose(m, [1.0, 7.0, 7.0], rtol=1e-14)
    np.testing.assert_allclose(c, [[0, 0, 0], [1.0, 0, 0], [1.0, 0, 0]], atol=1e-14)


def test_body_masses_of_a_two_node_body():
    """Point masses m_a, m_b at two nodes: mass m_a + m_b at their weighted centre."""
    arm = two_link_arm()
    M = np.zeros((13, 13))
    M[0:3, 0:3] = 2.0 * np.eye(3)
    M[6:9, 6:9] = 6.0 * np.eye(3)
    M[12, 12] = 1.0  # a modal DOF does not count
    nodes = [[0.2, 0.1, 0.0], [1.0, 0.5, -0.4]]
    G = np.zeros((6, 13))
    G[:, 6:12] = np.eye(6)
    body = Body("flex", M, np.zeros((13, 13)), nodes, {"tcp": G})
    flex = type(arm)(arm.chain, (arm.bodies[0], arm.bodies[1], body), arm.joints,
                     arm.joint_points)
    m, c = body_masses(flex)
    assert m[2] == pytest.approx(8.0, rel=1e-14)
    np.testing.assert_allclose(c[2], (2.0 * np.array(nodes[0]) + 6.0 * np.array(nodes[1])) / 8,
                               atol=1e-14)


def test_joint_screws():
    arm = two_link_arm()
    Q = np.array([[0.3, -0.8], [1.0, 2.0]])
    S = joint_screws(arm, Q)
    assert S.shape == (2, 2, 3, 6)
    np.testing.assert_allclose(S[:, :, 0, :], np.swapaxes(jacobian(arm.chain, Q), -1, -2),
                               atol=1e-15)
    q1, q2 = Q[0]
    tip = L * np.array([np.cos(q1) + np.cos(q1 + q2), np.sin(q1) + np.sin(q1 + q2), 0.0])
    p2 = L * np.array([np.cos(q1), np.sin(q1), 0.0])
    x2 = _rz(q1 + q2)[:, 0]  # radial1 of joint 2: the link-2 x axis
    np.testing.assert_allclose(S[0, 1, 1], np.r_[np.cross(x2, tip - p2), x2], atol=1e-15)


def test_series_starts():
    np.testing.assert_array_equal(series_starts(["a", "a", "b", "b", "b", "a", "a"]),
                                  [0, 0, 2, 2, 2, 5, 5])
    assert series_starts([]).size == 0


def test_relative_deflection_with_laws_by_hand():
    """q = 0: F_y at the tip loads joint 1 by 2 L F_y and joint 2 by L F_y (gravity along the
    axes adds nothing).  Hardening on joint 1, backlash on joint 2 crossing zero torque."""
    arm = two_link_arm(K1, K2, L, MASS)
    hard, play = Hardening(100.0, 5e-5), Backlash(2e-4)
    fy = np.array([-60.0, -20.0, 30.0, 90.0])
    F = np.column_stack([np.zeros(4), fy, np.zeros(4)])
    q = np.zeros((4, 2))
    d = relative_deflection(arm, q, F, None, ["s"] * 4, {0: [hard], 1: [play]})
    tau1, tau2 = 2 * L * fy, L * fy
    delta1 = tau1 / K1 + hard.deflection(tau1)
    delta2 = tau2 / K2 + play.deflection(tau2)
    uy = 2 * L * delta1 + L * delta2
    np.testing.assert_allclose(d, np.column_stack([np.zeros(4), uy - uy[0], np.zeros(4)]),
                               atol=1e-15)
    # two series: each one relative to its own first reading
    q2 = np.array([[0.0, np.pi / 2]] * 2 + [[0.0, 0.0]] * 2)
    F2 = np.array([[0, 10.0, 0], [0, 50.0, 0], [0, 0, 0], [0, -40.0, 0]])
    d2 = relative_deflection(arm, q2, F2, None, ["a", "a", "b", "b"], {0: [hard]})
    # pose (0, pi/2): tip at (L, L); F_y gives tau1 = L F_y, tau2 = 0; u = delta1 (-L, L, 0)
    t = L * np.array([10.0, 50.0])
    delta = t / K1 + hard.deflection(t)
    np.testing.assert_allclose(d2[1], (delta[1] - delta[0]) * np.array([-L, L, 0]), atol=1e-15)
    tau1, tau2 = 2 * L * -40.0, L * -40.0  # pose 0 again, reference unloaded
    uy = 2 * L * (tau1 / K1 + hard.deflection(tau1)) + L * tau2 / K2
    assert d2[3, 1] == pytest.approx(uy, rel=1e-12)
    np.testing.assert_array_equal(d2[[0, 2]], 0.0)


def test_moments_per_distinct_pose_are_bit_for_bit_those_of_repeated_poses():
    from flexarm.assembly.statics import distinct_poses

    arm = two_link_arm()
    rng = np.random.default_rng(4)
    q = np.repeat(rng.uniform(-1, 1, (5, 2)), rng.integers(1, 9, 5), axis=0)
    q = np.r_[q, q[:3]]  # a pose again after others
    force, moment = rng.normal(size=(len(q), 3)) * 100, rng.normal(size=(len(q), 3))
    uq, index = distinct_poses(q)
    ref_uq, ref_index = np.unique(q, axis=0, return_inverse=True)
    assert uq.tobytes() == ref_uq.tobytes() and index.tolist() == ref_index.ravel().tolist()
    by_pose = joint_moments(arm, uq, force, moment, pose_index=index)
    assert by_pose.tobytes() == joint_moments(arm, q, force, moment).tobytes()
