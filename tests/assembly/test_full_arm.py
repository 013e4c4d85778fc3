"""The full-FE arm through the arm analyses: the same answers as the full-FE reference,
Craig-Bampton converging to it, the FRF exact at 0 Hz, the weight of the links."""

import numpy as np
import pytest

from flexarm.assembly.analyses import (
    frf,
    gravity_sag,
    modes,
    natural_frequencies,
    tcp_compliance,
)
from flexarm.assembly.build import BuildOptions
from flexarm.assembly.flexible import flexible_arm
from flexarm.assembly.full_arm import FullFEArm, full_arm
from flexarm.assembly.full_fe import full_fe_analysis

from ..box_arm import box_mesher

GRAVITY = np.array([0.0, 0.0, -9.80665])


@pytest.fixture(scope="module")
def arms(box_robot):
    full = full_arm(box_robot, BuildOptions(), n_modes=8, mesher=box_mesher)
    cb = flexible_arm(box_robot, BuildOptions("cb", 20), mesher=box_mesher)
    return full, cb


def test_same_answers_as_the_full_fe_reference(box_robot, arms):
    full, _ = arms
    q = box_robot.pose("P2")
    ref = full_fe_analysis(full.arm, full.bodies, q, 8)
    np.testing.assert_allclose(tcp_compliance(full, q), ref.C, rtol=1e-10, atol=1e-22)
    np.testing.assert_allclose(natural_frequencies(full, q), ref.freq_hz, rtol=1e-9)


def test_cb_converges_to_it_in_every_analysis(box_robot, arms):
    full, cb = arms
    q = box_robot.pose("P1")
    f_full, f_cb = natural_frequencies(full, q), natural_frequencies(cb, q)[:8]
    assert np.all(f_cb >= f_full * (1 - 1e-9)) and np.abs(f_cb / f_full - 1).max() < 1e-4
    np.testing.assert_allclose(np.diag(tcp_compliance(cb, q)), np.diag(tcp_compliance(full, q)),
                               rtol=1e-8)
    np.testing.assert_allclose(gravity_sag(cb, q), gravity_sag(full, q), rtol=1e-3, atol=1e-12)
    m_full, m_cb = modes(full, q), modes(cb, q)
    np.testing.assert_allclose(m_full.energy, m_cb.energy[:, :8], atol=2e-3)
    np.testing.assert_allclose(m_full.damping, m_cb.damping[:8], atol=1e-4)


def test_frf_is_exact_at_zero_and_close_below_the_kept_modes(box_robot, arms):
    full, cb = arms
    q = box_robot.pose("P1")
    f1 = natural_frequencies(full, q)[0]
    f = np.array([0.0, 0.3 * f1, 0.9 * f1])
    H_full, H_cb = frf(full, q, f), frf(cb, q, f)
    np.testing.assert_allclose(H_full[0].real, tcp_compliance(full, q), rtol=1e-10, atol=1e-22)
    assert np.abs(H_full[:, 1, 1] / H_cb[:, 1, 1] - 1).max() < 1e-3


def test_weight_and_joint_energies_are_physical(box_robot, arms):
    full, _ = arms
    q = box_robot.pose("P1")
    md = modes(full, q)
    assert md.freq_hz.shape == (8,) and np.all(np.diff(md.freq_hz) >= 0)
    assert np.all(md.energy >= -1e-12) and np.all(md.energy.sum(axis=0) <= 1 + 1e-9)
    sag = gravity_sag(full, q)
    assert sag[2] < 0  # the arm droops under its own weight
    # linear in g
    np.testing.assert_allclose(gravity_sag(full, q, 2 * GRAVITY), 2 * sag, rtol=1e-12)


def test_keeps_a_few_factorisations(box_robot, arms):
    full, _ = arms
    q0 = box_robot.pose("P1")
    for k in range(6):
        tcp_compliance(full, q0 + 0.01 * k)
    assert isinstance(full, FullFEArm) and len(full._poses) <= 4
