import numpy as np
import pytest

from flexarm.robot.ik import IKConfig, ik, ik_analytic, ik_dls, is_spherical_wrist_arm
from flexarm.robot.kinematics import (
    Chain,
    jacobian,
    joint_to_motor,
    link_frames,
    motor_to_joint,
    tcp_frame,
)

# IRB 4600-60/2.05 DH table (Craig's modified convention is not used; classic DH)
D1, A1, A2, A3, D4, D6 = 0.495, 0.175, 0.900, 0.175, 0.960, 0.135


def irb_chain(tool=None):
    return Chain(
        origins=[[0, 0, D1], [A1, 0, 0], [0, 0, A2], [0, 0, A3], [D4, 0, 0], [D6, 0, 0]],
        axes=[[0, 0, 1], [0, 1, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]],
        parents=range(6),
        tool=np.eye(4) if tool is None else tool,
    )


def dh(theta, d, a, alpha):
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],
                     [0, sa, ca, d], [0, 0, 0, 1.0]])


def dh_flange(q):
    """Flange position of the IRB 4600 from its classic DH table.

    DH angles: theta = (q1, q2 - 90, q3, q4, q5, q6 + 180) (URDF zero has the lower arm
    vertical; DH zero has it along x_1), d = (d1, 0, 0, d4, 0, d6),
    a = (a1, a2, a3, 0, 0, 0), alpha = (-90, 0, -90, 90, -90, 0) deg.
    """
    th = np.array(q, dtype=float) + np.radians([0, -90, 0, 0, 0, 180])
    d = [D1, 0, 0, D4, 0, D6]
    a = [A1, A2, A3, 0, 0, 0]
    al = np.radians([-90, 0, -90, 90, -90, 0])
    T = np.eye(4)
    for i in range(6):
        T = T @ dh(th[i], d[i], a[i], al[i])
    return T


def random_q(rng, n):
    lo = np.radians([-180, -90, -180, -180, -125, -180])
    hi = np.radians([180, 150, 75, 180, 120, 180])
    return rng.uniform(lo, hi, size=(n, 6))


def test_fk_matches_dh_table_200_poses():
    rng = np.random.default_rng(1)
    Q = random_q(rng, 200)
    ch = irb_chain()
    P = tcp_frame(ch, Q)[:, :3, 3]
    P_dh = np.array([dh_flange(q)[:3, 3] for q in Q])
    assert np.abs(P - P_dh).max() < 1e-12


def test_fk_matches_origin_table(demo_robot):
    """Batched FK == chaining the shipped origins one pose at a time (DESIGN §4 table)."""
    rng = np.random.default_rng(2)
    Q = random_q(rng, 200)
    ch = demo_robot.chain
    F = link_frames(ch, Q)
    origins = np.array([j.origin for j in demo_robot.joints])
    for k in (0, 57, 199):
        T = np.eye(4)
        for j in range(6):
            c, s = np.cos(Q[k, j]), np.sin(Q[k, j])
            ax = np.array(demo_robot.joints[j].axis)
            S = np.array([[0, -ax[2], ax[1]], [ax[2], 0, -ax[0]], [-ax[1], ax[0], 0]])
            step = np.eye(4)
            step[:3, :3] = np.eye(3) + s * S + (1 - c) * S @ S
            step[:3, 3] = origins[j]
            T = T @ step
            assert np.abs(F[k, j + 1] - T).max() < 1e-12
    # wrist centre from the DH table, for all 200
    assert np.abs(F[:, 5, :3, 3] - np.array([dh_flange(q)[:3, 3] - D6 * dh_flange(q)[:3, 2]
                                             for q in Q])).max() < 1e-12


def test_zero_pose_flange():
    P = tcp_frame(irb_chain(), np.zeros(6))[:3, 3]
    assert np.allclose(P, [A1 + D4 + D6, 0, D1 + A2 + A3], atol=1e-15)


def test_jacobian_vs_finite_differences():
    rng = np.random.default_rng(3)
    tool = np.eye(4)
    tool[:3, 3] = [0.15, 0.02, -0.03]
    ch = irb_chain(tool)
    for q in random_q(rng, 5):
        J = jacobian(ch, q)
        h = 1e-6
        for j in range(6):
            dq = np.zeros(6)
            dq[j] = h
            Tp, Tm = tcp_frame(ch, q + dq), tcp_frame(ch, q - dq)
            v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
            dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ tcp_frame(ch, q)[:3, :3].T
            w = np.array([dR[2, 1], dR[0, 2], dR[1, 0]])
            assert np.allclose(J[:3, j], v, atol=1e-8)
            assert np.allclose(J[3:, j], w, atol=1e-8)


def test_ik_round_trip_all_configurations(demo_robot):
    ch = demo_robot.chain
    assert is_spherical_wrist_arm(ch)
    rng = np.random.default_rng(4)
    worst, n = 0.0, 0
    for q in random_q(rng, 200):
        T = tcp_frame(ch, q)
        for cfg in IKConfig.all():
            qs = ik_analytic(ch, T, cfg)
            if np.isnan(qs).any():
                continue
            worst = max(worst, np.abs(tcp_frame(ch, qs) - T).max())
            n += 1
        # the branch nearest the original angles is the original (mod 2 pi on 4, 6)
        q_back = ik(ch, T, q_near=q)
        assert np.abs(tcp_frame(ch, q_back)[:3, 3] - T[:3, 3]).max() < 1e-9
    assert n > 800 and worst < 1e-9


def test_ik_configurations_differ(demo_robot):
    ch = demo_robot.chain
    T = tcp_frame(ch, demo_robot.pose("P1"))
    up = ik_analytic(ch, T, IKConfig(elbow="up"))
    down = ik_analytic(ch, T, IKConfig(elbow="down"))
    flip = ik_analytic(ch, T, IKConfig(wrist="flip"))
    assert not np.allclose(up, down) and np.sign(flip[4]) != np.sign(up[4])
    assert np.allclose(ik(ch, T, q_near=demo_robot.pose("P1")), demo_robot.pose("P1"))


def test_ik_dls_general_chain():
    ch = Chain(origins=[[0, 0, 0.3], [0.1, 0.05, 0.2], [0.0, 0, 0.5], [0.4, 0, 0.1],
                        [0.3, 0.02, 0], [0.1, 0, 0]],
               axes=[[0, 0, 1], [0, 1, 0], [0, 1, 0], [1, 0, 0], [0, 0.6, 0.8], [1, 0, 0]],
               parents=range(6))
    assert not is_spherical_wrist_arm(ch)
    q = np.array([0.3, 0.2, -0.4, 0.5, 0.3, -0.2])
    q_found = ik_dls(ch, tcp_frame(ch, q), q + 0.1)
    assert np.abs(tcp_frame(ch, q_found) - tcp_frame(ch, q)).max() < 1e-9


def test_motor_joint_round_trip():
    C = np.array([[1.0, 0, 0], [0.1, 1.0, 0], [0.05, 0.2, 1.0]])
    ch = Chain(origins=np.zeros((6, 3)), axes=np.tile([0, 0, 1.0], (6, 1)), parents=range(6),
               gear_ratios=[120, 150, 120, 80, 80, 50], wrist_coupling=C)
    q = np.array([0.1, -0.2, 0.3, 0.4, -0.5, 0.6])
    m = joint_to_motor(ch, q)
    assert m[0] == pytest.approx(12.0) and m[4] == pytest.approx(80 * (0.1 * 0.4 - 0.5))
    assert np.allclose(motor_to_joint(ch, m), q, atol=1e-14)
