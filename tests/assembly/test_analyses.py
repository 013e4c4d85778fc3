"""Analyses of the two-link arm against hand formulas: compliance sum (r_j^2 / k_j), natural
frequencies of the planar manipulator inertia matrix, modal damping as the energy-weighted joint
ratios, undamped FRF = G (K - w^2 M)^-1 G^T, gravity sag from hand statics, eq. 3.12 inversion."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flexarm.assembly.analyses import (
    diagonal_compliance,
    frf,
    gravity_sag,
    identify_stiffness,
    modes,
    natural_frequencies,
    stiffness_from_load_cases,
    tcp_compliance,
)
from flexarm.assembly.examples import two_link_arm
from flexarm.assembly.system import system_matrices
from flexarm.robot.joints import JointModel

K1, K2, L, MASS = 1e4, 2e4, 1.0, 10.0


def manipulator_mass(q2: float, m: float = MASS, length: float = L) -> np.ndarray:
    """Planar two-rod inertia matrix (rods of mass m, length L, I_c = m L^2 / 12)."""
    Ic, lc, c2 = m * length**2 / 12, length / 2, np.cos(q2)
    m22 = Ic + m * lc**2
    m12 = m22 + m * length * lc * c2
    m11 = 2 * Ic + m * (lc**2 + length**2 + lc**2 + 2 * length * lc * c2)
    return np.array([[m11, m12], [m12, m22]])


def hand_frequencies(q2: float) -> np.ndarray:
    lam = np.linalg.eigvals(np.linalg.solve(manipulator_mass(q2), np.diag([K1, K2])))
    return np.sort(np.sqrt(lam.real)) / (2 * np.pi)


def test_tcp_compliance_by_hand():
    """At q = (0, 0) the TCP is at 2L: C_yy = (2L)^2/k1 + L^2/k2, C_y,rz = 2L/k1 + L/k2."""
    C = tcp_compliance(two_link_arm(), [0.0, 0.0])
    assert C[1, 1] == pytest.approx(4 * L**2 / K1 + L**2 / K2, rel=1e-13)
    assert C[1, 5] == pytest.approx(2 * L / K1 + L / K2, rel=1e-13)
    assert C[5, 5] == pytest.approx(1 / K1 + 1 / K2, rel=1e-13)
    assert np.abs(C[[0, 2, 3, 4]]).max() == 0.0  # planar arm: no x, z or tilt motion
    # folded back (q2 = pi): the TCP is at the base, joint 1 cannot move it
    Cf = tcp_compliance(two_link_arm(), [0.4, np.pi])
    assert Cf[0, 0] + Cf[1, 1] == pytest.approx(L**2 / K2, rel=1e-12)


def test_natural_frequencies_of_the_manipulator_inertia():
    arm = two_link_arm()
    q = np.array([[0.0, 0.0], [0.3, 0.7], [-1.0, 2.0], [2.5, -1.2]])
    f = natural_frequencies(arm, q)
    assert f.shape == (4, 2)
    for fi, qi in zip(f, q, strict=True):
        np.testing.assert_allclose(fi, hand_frequencies(qi[1]), rtol=1e-12)
    np.testing.assert_allclose(natural_frequencies(arm, q, chunk=1), f, rtol=1e-14)
    np.testing.assert_allclose(system_matrices(arm, q[1]).M, manipulator_mass(0.7), rtol=1e-13)


def test_modes_are_normalised_and_damped_by_the_joints():
    arm = dataclasses.replace(two_link_arm(), joints=(
        JointModel(torsion=K1, damping_ratio=0.01),
        JointModel(torsion=K2, rayleigh=(3.0, 2e-4))))
    q = [0.2, 0.9]
    md = modes(arm, q)
    sm = system_matrices(arm, q)
    Phi, w = md.shapes, md.omega
    np.testing.assert_allclose(Phi.T @ sm.M @ Phi, np.eye(2), atol=1e-12)
    np.testing.assert_allclose(Phi.T @ sm.K @ Phi, np.diag(w**2), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(md.tcp_shapes, sm.G_tcp @ Phi, atol=1e-15)
    assert np.all(Phi[np.argmax(np.abs(Phi), axis=0), [0, 1]] > 0)  # sign convention
    energy = np.array([K1, K2])[:, None] * Phi**2 / w**2  # share of each joint
    np.testing.assert_allclose(md.energy, energy, rtol=1e-12)
    zeta = energy[0] * 0.01 + energy[1] * (3.0 / (2 * w) + 2e-4 * w / 2)
    np.testing.assert_allclose(md.damping, zeta, rtol=1e-12)
    assert md.coordinate_names == ["joint_1.torsion", "joint_2.torsion"]
    lines = md.text(["joint_1", "joint_2"]).splitlines()
    assert len(lines) == 3 and f"{md.freq_hz[1]:10.3f}" in lines[2]


def test_undamped_frf_is_the_dynamic_stiffness_inverse():
    arm = two_link_arm()
    q = [0.1, 1.1]
    sm = system_matrices(arm, q)
    f = np.array([0.0, 1.0, 3.3, 20.0])
    H = frf(arm, q, f, damping=0.0)
    assert H.shape == (4, 6, 6)
    for Hk, fk in zip(H, f, strict=True):
        w = 2 * np.pi * fk
        ref = sm.G_tcp @ np.linalg.solve(sm.K - w**2 * sm.M, sm.G_tcp.T)
        np.testing.assert_allclose(Hk, ref, rtol=1e-10, atol=1e-12 * np.abs(ref).max())
    # with damping the receptance at resonance is finite and mostly imaginary
    fr = modes(arm, q).freq_hz[0]
    Hr = frf(arm, q, [fr])[0]
    assert abs(Hr[1, 1].imag) > 10 * abs(Hr[1, 1].real)


def test_gravity_sag_by_hand():
    """Gravity along -y at q = 0: joint torques -2 m g L and -m g L/2 turn the rods."""
    g = 9.81
    sag = gravity_sag(two_link_arm(), [0.0, 0.0], [0.0, -g, 0.0])
    d1, d2 = -2 * MASS * g * L / K1, -MASS * g * (L / 2) / K2
    np.testing.assert_allclose(sag, [0, 2 * L * d1 + L * d2, 0, 0, 0, d1 + d2], atol=1e-15)
    # the default gravity (-z) is along the joint axes: no sag at all
    np.testing.assert_allclose(gravity_sag(two_link_arm(), [[0.3, 0.2]] * 2), 0.0, atol=1e-18)


def test_stiffness_from_load_cases_inverts_eq_3_12():
    rng = np.random.default_rng(4)
    A = rng.normal(size=(3, 3))
    K = A @ A.T + 3 * np.eye(3)
    F = np.array([[800.0, 0, 0], [100.0, 700.0, 0], [0.0, -50.0, 900.0]])
    X = np.linalg.solve(K, F.T).T  # row k: displacement of load case k
    np.testing.assert_allclose(stiffness_from_load_cases(F, X), K, rtol=1e-12)
    with pytest.raises(ValueError, match="dependent displacements"):
        stiffness_from_load_cases(F, np.array([[1.0, 0, 0], [2.0, 0, 0], [0, 0, 1.0]]))
    with pytest.raises(ValueError, match=r"forces and displacements must be \(3, 3\)"):
        stiffness_from_load_cases(F[:2], X)


def test_identify_stiffness_default_load_cases(demo_robot):
    from flexarm.assembly.emodel import emodel

    arm = emodel(demo_robot, method="surface")
    q = demo_robot.pose("P2")
    C = tcp_compliance(arm, q)[:3, :3]
    rep = identify_stiffness(arm, q)
    np.testing.assert_array_equal(rep.forces, 800.0 * np.eye(3))
    np.testing.assert_allclose(rep.displacements, 800.0 * C.T, rtol=1e-14)
    np.testing.assert_allclose(rep.K_diag, np.diag(1 / np.diag(C)), rtol=1e-14)
    x_diag = 800.0 * np.diag(np.diag(C))
    np.testing.assert_allclose(rep.error_diag, np.linalg.norm(x_diag - 800.0 * C, axis=1)
                               / np.linalg.norm(800.0 * C, axis=1), rtol=1e-9)
    Cb = np.stack([tcp_compliance(arm, q)] * 2)
    np.testing.assert_array_equal(diagonal_compliance(Cb)[1], np.diag(np.diag(C)))
