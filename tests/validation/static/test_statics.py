"""Nonlinear joint laws and the statically exact joint loads / relative deflections."""

from __future__ import annotations

import numpy as np

from flexarm.assembly.analyses import GRAVITY
from flexarm.assembly.nonlinear import Backlash, Hardening, Hysteresis
from flexarm.assembly.statics import joint_moments, relative_deflection
from flexarm.assembly.system import system_matrices


def test_backlash_step_at_sign_change():
    d = Backlash(2e-4).deflection([-5.0, -1.0, 1.0, 5.0])
    assert np.allclose(np.diff(d), [0, 2e-4, 0])


def test_hardening_piecewise_linear():
    h = Hardening.from_stiffness(1e5, 2e5, 100.0)
    tau = np.array([0.0, 50.0, 100.0, 400.0])
    total = tau / 2e5 + h.deflection(tau)
    slopes = np.diff(total) / np.diff(tau)
    assert np.allclose(slopes, [1e-5, 1e-5, 5e-6])


def test_hysteresis_monotonic_invisible_cycle_visible():
    h = Hysteresis(1e-4, radius=20.0)
    up = np.linspace(0, 500, 6)
    assert np.ptp(h.deflection(up)) == 0.0
    cycle = np.r_[up, up[-2::-1]]
    d = h.deflection(cycle)
    assert np.isclose(d[-1] - d[0], 1e-4)


def test_joint_moments_equal_generalised_gravity_forces(demo):
    robot, arm = demo
    q = robot.pose("P1")
    tau = joint_moments(arm, q, np.zeros(3))
    sm = system_matrices(arm, q)
    f = np.zeros(arm.layout["n"])
    for i, (T, b) in enumerate(zip(sm.T, arm.bodies, strict=True)):
        R = np.kron(np.eye(2), sm.frames[i, :3, :3])
        f += T.T @ (R @ b.M @ R.T) @ np.r_[GRAVITY, 0, 0, 0]
    names = arm.coordinate_names
    for j in range(6):
        assert np.isclose(tau[j, 0], f[names.index(f"joint_{j + 1}.torsion")], atol=1e-6)
    assert np.isclose(tau[1, 1], f[names.index("joint_2.tilt1")], atol=1e-6)


def test_relative_deflection_linear_and_backlash(demo):
    robot, arm = demo
    q = np.tile(robot.pose("P2"), (9, 1))
    F = np.zeros((9, 3))
    F[:, 2] = np.arange(9) * 100.0
    lin = relative_deflection(arm, q, F, None, ["s"] * 9)
    assert np.allclose(lin[0], 0) and np.allclose(np.diff(lin[:, 2], 2), 0, atol=1e-12)
    nl = relative_deflection(arm, q, F, None, ["s"] * 9, {1: [Backlash(1e-4)]})
    tau2 = joint_moments(arm, q, F)[:, 1, 0]
    flip = np.flatnonzero(np.diff(np.sign(tau2)))[0]  # joint-2 torque reverses near 400 N
    jump = np.diff(np.linalg.norm(nl - lin, axis=1))
    assert 300 <= F[flip, 2] <= 500 and jump[flip] > 0.5 * np.abs(jump).max() > 0
