import dataclasses
import re

import numpy as np
import pytest

from flexarm.assembly.analyses import modes, tcp_compliance
from flexarm.assembly.bodies import Body, rigid_transport
from flexarm.assembly.examples import two_link_arm
from flexarm.assembly.system import system_matrices
from flexarm.robot.joints import JointModel
from flexarm.robot.kinematics import jacobian


def torsion_only(arm):
    return dataclasses.replace(arm, joints=tuple(JointModel(torsion=j.torsion)
                                                 for j in arm.joints))


def test_compliance_equals_J_Kinv_JT_random_poses(demo_robot):
    """Acceptance: torsion-only joints, rigid links: C = J K^-1 J^T to 1e-10."""
    from flexarm.assembly.emodel import emodel

    arm = torsion_only(emodel(demo_robot, method="surface"))
    k = np.array([j.torsion for j in arm.joints])
    rng = np.random.default_rng(7)
    Q = rng.uniform(demo_robot.lower, demo_robot.upper, size=(50, 6))
    C = tcp_compliance(arm, Q)
    J = jacobian(demo_robot.chain, Q)
    C_ref = np.einsum("mij,j,mkj->mik", J, 1 / k, J)
    rel = np.abs(C - C_ref).max(axis=(1, 2)) / np.abs(C_ref).max(axis=(1, 2))
    assert rel.max() < 1e-10


def test_batched_equals_single(demo_robot):
    from flexarm.assembly.emodel import emodel

    arm = emodel(demo_robot, method="surface")
    Q = np.stack([demo_robot.pose(p) for p in ("P1", "P2", "P3")])
    Cb = tcp_compliance(arm, Q)
    for i, q in enumerate(Q):
        assert np.allclose(Cb[i], tcp_compliance(arm, q), rtol=1e-13, atol=0)


def test_rigid_bearing_direction_is_limit_of_stiff_spring():
    """Exact elimination == the limit of a finite bearing spring (no penalty)."""
    arm = two_link_arm()
    q = [0.3, -0.6]
    C_rigid = tcp_compliance(arm, q)
    stiff = dataclasses.replace(arm, joints=tuple(
        JointModel(torsion=j.torsion, tilt=1e12, radial=1e14, axial=1e14) for j in arm.joints))
    C_stiff = tcp_compliance(stiff, q)
    assert np.abs(C_stiff - C_rigid).max() < 1e-6 * np.abs(C_rigid).max()
    assert system_matrices(stiff, q).K.shape == (12, 12)
    assert system_matrices(arm, q).K.shape == (2, 2)


def test_two_link_pendulum_frequency():
    """Link 1 locked (stiff k1): link 2 a rod on a torsion spring, f = sqrt(k/(m L^2/3))/2pi."""
    arm = two_link_arm(k1=1e12, k2=2e4, mass=10.0, length=1.0)
    f = modes(arm, [0.0, 0.4]).freq_hz[0]
    assert abs(f - np.sqrt(2e4 / (10.0 / 3)) / (2 * np.pi)) < 1e-6 * f


def test_flexible_body_in_assembly():
    """A two-node body with a real K (a spring between its nodes) is assembled in series."""
    base = two_link_arm()
    b2 = base.bodies[2]
    # link 2 as two nodes (proximal at 0, distal at L=1) joined by a torsion spring about z
    kz = 5e4
    K = np.zeros((12, 12))
    K[5, 5] = K[11, 11] = kz
    K[5, 11] = K[11, 5] = -kz
    # make the rest of the body stiff but finite: translational/rotational springs
    for d in (0, 1, 2, 3, 4):
        K[d, d] = K[6 + d, 6 + d] = 1e12
        K[d, 6 + d] = K[6 + d, d] = -1e12
    M = np.eye(12) * 1e-3
    M[:6, :6] += b2.M
    G_tip = np.zeros((6, 12))
    G_tip[:, 6:] = np.eye(6)
    body = Body("link_2_flex", M, K, [[0, 0, 0], [1.0, 0, 0]], {"tcp": G_tip})
    arm = dataclasses.replace(base, bodies=(base.bodies[0], base.bodies[1], body))
    q = [0.2, 0.5]
    C = tcp_compliance(arm, q)
    # torsion springs in series at the tip node: rotation about z compliance 1/k1 + 1/k2 + 1/kz
    assert abs(C[5, 5] - (1 / 1e4 + 1 / 2e4 + 1 / kz)) < 1e-9
    # y-compliance of the tip = J-based formula with the extra spring at joint 2's location
    J = jacobian(base.chain, q)
    Cref = J @ np.diag([1 / 1e4, 1 / 2e4]) @ J.T
    assert C[5, 5] > Cref[5, 5]


def test_rigid_transport():
    A = rigid_transport([1.0, 0, 0])
    assert np.allclose(A @ [0, 0, 0, 0, 0, 1.0], [0, 1, 0, 0, 0, 1])


def test_a_pose_outside_the_joint_limits_is_refused_naming_the_joint():
    arm = dataclasses.replace(two_link_arm(), joint_limits=np.radians([[-170, 170], [-90, 90]]))
    arm.check_pose(np.radians([10, 90]))  # on the limit
    for q, text in (([0, 95], "joint_2 = 95 deg is outside its limits [-90, 90] deg"),
                    ([[0, 0], [-171, 0]], "joint_1 = -171 deg is outside its limits")):
        with pytest.raises(ValueError, match=re.escape(f"pose: {text}")):
            arm.check_pose(np.radians(q))
    with pytest.raises(ValueError, match="joint_1 = nan deg is not a finite angle"):
        two_link_arm().check_pose([np.nan, 0])
    with pytest.raises(ValueError, match=re.escape("joint_limits must be (2, 2)")):
        dataclasses.replace(two_link_arm(), joint_limits=[[0, 1]])
