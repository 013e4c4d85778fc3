"""Joint models: the diagonal spring (axial, radial, radial, torsion, tilt, tilt2) with rigid
directions eliminated, seen at the joint as the compliance E diag(1/k) E^T in the joint basis;
Rayleigh damping alpha/(2 omega) + beta omega/2; validation messages; joint_basis."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from flexarm.assembly.analyses import tcp_compliance
from flexarm.assembly.bodies import rigid_body
from flexarm.assembly.system import ArmModel
from flexarm.fe.mass_properties import MassProperties
from flexarm.robot.joints import DOF_NAMES, JointModel, joint_basis
from flexarm.robot.kinematics import Chain

INF = math.inf


def exact(message: str) -> str:
    return "^" + re.escape(message) + "$"


def test_stiffness_vector_and_free_dofs():
    jm = JointModel(torsion=5e5, tilt=2e7, radial=3e8, axial=4e8, tilt2=1e7)
    np.testing.assert_array_equal(jm.stiffness, [4e8, 3e8, 3e8, 5e5, 2e7, 1e7])
    assert jm.free_dofs.tolist() == list(range(6)) and jm.tilt_2 == 1e7
    assert DOF_NAMES == ("axial", "radial1", "radial2", "torsion", "tilt1", "tilt2")
    torsion_only = JointModel(torsion=5e5)
    assert torsion_only.free_dofs.tolist() == [3]
    np.testing.assert_array_equal(torsion_only.stiffness, [INF, INF, INF, 5e5, INF, INF])
    radial = JointModel(torsion=INF, radial=1e9)
    assert radial.free_dofs.tolist() == [1, 2] and radial.free_stiffness.tolist() == [1e9, 1e9]
    assert JointModel(torsion=1.0, tilt=2.0).tilt_2 == 2.0  # tilt2 defaults to tilt


@pytest.mark.parametrize("kwargs, message", [
    ({"torsion": 0.0}, "joint torsion stiffness must be > 0 (or inf for rigid), got 0.0"),
    ({"torsion": 1.0, "radial": -1.0}, "joint radial stiffness must be > 0 (or inf for rigid), "
                                       "got -1.0"),
    ({"torsion": 1.0, "tilt": 1.0, "tilt2": 0.0}, "joint tilt2 stiffness must be > 0 (or inf "
                                                  "for rigid), got 0.0"),
    ({"torsion": 1.0, "tilt": 1e7, "tilt2": INF}, "joint tilt and tilt2 must both be finite or "
                                                  "both rigid, got 10000000.0 and inf"),
    ({"torsion": 1.0, "tilt2": 1e7}, "joint tilt and tilt2 must both be finite or both rigid, "
                                     "got inf and 10000000.0"),
    ({"torsion": 1.0, "damping_ratio": 1.0}, "joint damping_ratio must be in [0, 1), got 1.0"),
    ({"torsion": 1.0, "rayleigh": (0.1, -1e-4)}, "joint rayleigh (alpha, beta) must be >= 0, "
                                                 "got (0.1, -0.0001)"),
])
def test_validation(kwargs, message):
    with pytest.raises(ValueError, match=exact(message)):
        JointModel(**kwargs)


def test_damping_ratio_constant_or_rayleigh():
    omega = np.array([[1.0, 10.0], [100.0, 1000.0]])
    np.testing.assert_array_equal(JointModel(torsion=1.0, damping_ratio=0.04).ratio(omega),
                                  np.full((2, 2), 0.04))
    alpha, beta = 2.0, 1e-4
    jm = JointModel(torsion=1.0, rayleigh=(2, 1e-4))
    assert jm.rayleigh == (2.0, 1e-4) and isinstance(jm.rayleigh[0], float)
    np.testing.assert_allclose(jm.ratio(omega), alpha / (2 * omega) + beta * omega / 2,
                               rtol=1e-15)
    # minimum sqrt(alpha beta) at omega = sqrt(alpha / beta)
    w0 = math.sqrt(alpha / beta)
    assert jm.ratio(w0) == pytest.approx(math.sqrt(alpha * beta), rel=1e-14)
    assert np.isfinite(jm.ratio(0.0))


@pytest.mark.parametrize("axis", [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.48, -0.6, 0.64],
                                  [-1e-3, 0.0, -1.0]])
def test_joint_basis_is_right_handed_and_deterministic(axis):
    B = joint_basis(axis)
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    np.testing.assert_allclose(B.T @ B, np.eye(3), atol=1e-15)
    assert np.linalg.det(B) == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_allclose(B[:, 0], a, atol=1e-15)
    # radial1 comes from the coordinate axis least aligned with the joint axis
    helper = np.eye(3)[np.argmin(np.abs(a))]
    assert B[:, 1] @ helper > 0 and abs(B[:, 1] @ np.cross(a, helper)) < 1e-15
    np.testing.assert_allclose(joint_basis(np.asarray(axis) * 3.0), B, atol=1e-15)


def _one_joint_arm(jm: JointModel, axis) -> ArmModel:
    """A joint at the origin; the 'TCP' is the joint point itself on the child."""
    chain = Chain(origins=[[0.0, 0.0, 0.0]], axes=[axis], parents=[0])
    mp = MassProperties(1.0, np.zeros(3), np.eye(3))
    bodies = (rigid_body("base", mp, [0, 0, 0], {"j": [0, 0, 0]}),
              rigid_body("link", mp, [0, 0, 0], {"tcp": [0, 0, 0]}))
    return ArmModel(chain, bodies, (jm,), ("j",))


@pytest.mark.parametrize("jm", [
    JointModel(torsion=5e5, tilt=2e7, radial=3e8, axial=4e8, tilt2=1e7),
    JointModel(torsion=5e5),
    JointModel(torsion=5e5, tilt=2e7),
    JointModel(torsion=INF, radial=3e8),
])
def test_spring_seen_at_the_joint(jm):
    """TCP compliance at the joint point = blockdiag(B, B) diag(1/k) blockdiag(B, B)^T,
    torsion about the axis, zero in rigid directions; the system has only the free DOFs."""
    axis = np.array([0.0, 0.6, 0.8])
    arm = _one_joint_arm(jm, axis)
    assert arm.layout["n"] == len(jm.free_dofs)
    np.testing.assert_array_equal(arm.spring_stiffness(), np.diag(jm.free_stiffness))
    E = np.kron(np.eye(2), joint_basis(axis))
    expected = E @ np.diag(1.0 / jm.stiffness) @ E.T
    C = tcp_compliance(arm, [0.0])
    np.testing.assert_allclose(C, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    if np.isfinite(jm.torsion):
        assert axis @ C[3:, 3:] @ axis == pytest.approx(1 / jm.torsion, rel=1e-12)
    # the joint's spring does not change when the joint turns (torsion and axial on the axis)
    Ct = tcp_compliance(arm, [0.7])
    np.testing.assert_allclose(E[:, [0, 3]].T @ Ct @ E[:, [0, 3]],
                               E[:, [0, 3]].T @ expected @ E[:, [0, 3]], rtol=1e-12, atol=1e-20)


def test_stiffness_source_is_a_mark_not_a_spring():
    """``source`` says where the values come from; it never changes what the joint is."""
    given, guess = JointModel(torsion=1e6), JointModel(torsion=1e6, source="placeholder")
    assert given.source == "given" and not given.is_placeholder and guess.is_placeholder
    assert given == guess and np.array_equal(given.stiffness, guess.stiffness)
    with pytest.raises(ValueError, match="^joint stiffness source must be one of given, "
                                         "placeholder, got 'guessed'$"):
        JointModel(torsion=1e6, source="guessed")
