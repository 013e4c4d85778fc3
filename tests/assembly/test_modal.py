"""Arm modes (flexarm/assembly/modal.py) in a notebook: short repr, table per mode."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly import emodel
from flexarm.assembly.analyses import modes
from flexarm.assembly.modal import Modes
from flexarm.robot import load_robot


@pytest.fixture(scope="module")
def arm_modes():
    robot = load_robot()
    return robot, modes(emodel(robot), robot.pose("P1"))


def test_repr_states_count_and_ranges(arm_modes):
    _, m = arm_modes
    text = repr(m)
    assert len(text) < 300 and "\n" not in text
    assert text.startswith(f"Modes({len(m.freq_hz)} modes, ")
    lo, hi = text.split(", ")[1].removesuffix(" Hz").split("–")
    assert (float(lo), float(hi)) == pytest.approx((m.freq_hz.min(), m.freq_hz.max()),
                                                   rel=1e-3)
    zeta = text.split("damping ")[1].split(" %")[0].split("–")  # one figure if all equal
    zlo, zhi = zeta[0], zeta[-1]
    assert float(zlo) == pytest.approx(100 * m.damping.min(), rel=2e-3)
    assert float(zhi) == pytest.approx(100 * m.damping.max(), rel=2e-3)
    assert f"{m.shapes.shape[0]} coordinates, {m.energy.shape[0]} joints)" in text


def test_dataframe_matches_the_mode_energy_columns(arm_modes):
    robot, m = arm_modes
    f = m.to_dataframe(robot.joint_names)
    shares = [f"energy_share_{n}" for n in robot.joint_names]
    assert f.columns.tolist() == ["mode", "f_Hz", "zeta", *shares]
    assert f["mode"].tolist() == list(range(1, len(m.freq_hz) + 1))
    assert np.array_equal(f["f_Hz"].to_numpy(), m.freq_hz)
    assert np.array_equal(f["zeta"].to_numpy(), m.damping)
    assert np.array_equal(f[shares].to_numpy(), m.energy.T)
    assert m.to_dataframe().columns[3] == "energy_share_joint_1"  # joints count from 1
    with pytest.raises(ValueError, match="must name 6 joints, got 2"):
        m.to_dataframe(["a", "b"])


def test_text_keeps_full_joint_names():
    # URDF joints are named "joint_a1" or "shoulder_pan_joint": never cut to their tail
    m = Modes(np.array([7.5, 16.0]), np.eye(3, 2), np.zeros((6, 2)), np.array([0.02, 0.03]),
              np.array([[0.9, 0.2], [0.1, 0.8]]), ["a", "b"])
    header, row, _ = m.text(["joint_a1", "shoulder_pan_joint"]).splitlines()
    assert header.split()[3:] == ["joint_a1", "shoulder_pan_joint"]
    # each share right-aligned under its name
    assert row.index("0.900") + 5 == header.index("joint_a1") + len("joint_a1")
    assert row.rindex("0.100") + 5 == len(header)
