"""Pose-batched fast paths: constant K, TCP map, M(q), and the inverse-form eigen-solve."""

import numpy as np
import pytest

from flexarm.assembly.analyses import _generalized_eigh, natural_frequencies, tcp_compliance
from flexarm.assembly.batched import (
    constant_stiffness,
    fast_tcp_compliance,
    has_constant_stiffness,
    mass_matrix,
    tcp_map,
)
from flexarm.assembly.build import BuildOptions
from flexarm.assembly.emodel import emodel
from flexarm.assembly.flexible import flexible_arm
from flexarm.assembly.system import system_matrices

from ..box_arm import box_mesher


def _assembled_compliance(arm, Q):
    sm = system_matrices(arm, Q)
    C = sm.G_tcp @ np.linalg.solve(sm.K, np.swapaxes(sm.G_tcp, -1, -2))
    return sm, 0.5 * (C + np.swapaxes(C, -1, -2))


@pytest.fixture(scope="module", params=["emodel_demo", "cb_box", "guyan_box"])
def arm_and_robot(request, demo_robot, box_robot):
    if request.param == "emodel_demo":
        return emodel(demo_robot, method="surface"), demo_robot
    method = request.param.split("_")[0]
    return flexible_arm(box_robot, BuildOptions(method, 6), mesher=box_mesher), box_robot


def test_fast_path_equals_assembly(arm_and_robot):
    """K is pose-independent; TCP compliance, TCP map and M match the full assembly."""
    arm, robot = arm_and_robot
    assert has_constant_stiffness(arm)
    Q = np.random.default_rng(4).uniform(robot.lower, robot.upper, (9, len(robot.lower)))
    sm, C_ref = _assembled_compliance(arm, Q)
    assert np.array_equal(sm.K, np.broadcast_to(constant_stiffness(arm), sm.K.shape))
    C = fast_tcp_compliance(arm, Q)
    assert np.abs(C - C_ref).max() <= 1e-10 * np.abs(C_ref).max()
    np.testing.assert_allclose(tcp_compliance(arm, Q), C, rtol=0, atol=0)
    G = tcp_map(arm, Q)
    assert np.abs(G - sm.G_tcp).max() <= 1e-12 * np.abs(sm.G_tcp).max()
    M = mass_matrix(arm, Q)
    assert np.abs(M - sm.M).max() <= 1e-12 * np.abs(sm.M).max()
    C0 = fast_tcp_compliance(arm, Q[0])  # unbatched pose
    np.testing.assert_allclose(C0, C[0], rtol=1e-13, atol=1e-13 * np.abs(C0).max())


def test_pose_blocks_and_batch_shapes(arm_and_robot):
    """More poses than one block, in a (2, k) batch: every pose equals its own evaluation."""
    from flexarm.assembly.batched import POSE_CHUNK

    arm, robot = arm_and_robot
    k = POSE_CHUNK + 7
    Q = np.random.default_rng(6).uniform(robot.lower, robot.upper, (2, k, len(robot.lower)))
    C = fast_tcp_compliance(arm, Q)
    assert C.shape == (2, k, 6, 6)
    for a, b in [(0, 0), (0, POSE_CHUNK), (1, k - 1)]:
        ref = _assembled_compliance(arm, Q[a, b][None])[1][0]
        assert np.abs(C[a, b] - ref).max() <= 1e-10 * np.abs(ref).max()
    assert np.abs(C - np.swapaxes(C, -1, -2)).max() == 0.0  # symmetric by construction


def test_frequencies_batched_equal_single_poses(arm_and_robot):
    arm, robot = arm_and_robot
    Q = np.random.default_rng(5).uniform(robot.lower, robot.upper, (3, 2, len(robot.lower)))
    f = natural_frequencies(arm, Q, chunk=4)
    assert f.shape == (3, 2, arm.layout["n"])
    sm = system_matrices(arm, Q[1, 1])
    lam = np.linalg.eigvals(np.linalg.solve(sm.M, sm.K)).real
    np.testing.assert_allclose(f[1, 1], np.sqrt(np.sort(lam)) / (2 * np.pi), rtol=1e-8)


def test_inverse_form_eigh_keeps_lowest_mode_of_stiff_system():
    """A soft spring (1 N/m) in series with a 1e14 N/m one: lambda_1 to 1e-12."""
    k1, k2 = 1.0, 1e14
    K = np.array([[k1 + k2, -k2], [-k2, k2]])
    M = np.array([[1.0, 0.3], [0.3, 2.0]])
    a = np.linalg.det(M)
    b = -(K[0, 0] * M[1, 1] + K[1, 1] * M[0, 0] - 2 * K[0, 1] * M[0, 1])
    lam2 = (-b + np.sqrt(b * b - 4 * a * k1 * k2)) / (2 * a)
    exact = np.array([k1 * k2 / (a * lam2), lam2])  # product of the roots = det K / det M
    lam, Phi = _generalized_eigh(K, M)
    np.testing.assert_allclose(lam, exact, rtol=1e-12)
    np.testing.assert_allclose(Phi.T @ M @ Phi, np.eye(2), atol=1e-12)
    res = K @ Phi - M @ Phi * lam  # backward error, relative to |K|
    assert np.abs(res).max() <= 1e-14 * np.abs(K).max()
    # the Cholesky-of-M form alone loses the lowest mode here
    Li = np.linalg.inv(np.linalg.cholesky(M))
    lam_m = np.linalg.eigvalsh(Li @ K @ Li.T)
    assert abs(lam_m[0] / exact[0] - 1) > 1e-6
