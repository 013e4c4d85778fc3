"""The arm-level steps: E-model pose table and joint maps (fast, on the surface-mass
E-model), and both steps whole (slow: every link is meshed)."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.robot import load_robot
from flexarm.studies.compliance import compliance_report
from flexarm.studies.demo_models import (
    POSES,
    _bode,
    _emodel_poses,
    _joint_map,
    emodel_step,
    flexible_step,
)


@pytest.fixture(scope="module")
def emodel_arm():
    return build_arm(load_robot(), ArmSpec(mass="surface"))


def test_emodel_pose_rows_come_from_the_compliance_report(emodel_arm):
    rows, table, figures = _emodel_poses(emodel_arm)
    assert [r[0] for r in rows] == list(POSES) and all(len(r) == 14 for r in rows)
    rep = compliance_report(emodel_arm.model, emodel_arm.robot.pose("P1"))
    np.testing.assert_array_equal(rows[0][7:10], rep.deflection * 1e3)
    assert rows[0][10] == rep.weakest == "y"
    assert figures["emodel_P1_defl_800N_y_mm"] == rows[0][8]
    assert table[0].startswith("| P1 | ") and " | Y | " in table[0]


def test_bode_csv_is_the_plotted_curve(emodel_arm, tmp_path, figures):
    line = _bode(tmp_path / "emodel_bode_P1", emodel_arm, "P1")
    csv = tmp_path / "emodel_bode_P1" / "frf.csv"
    head = csv.read_text().splitlines()[0].split(",")
    d = dict(zip(head, np.loadtxt(csv, delimiter=",", skiprows=1).T, strict=True))
    amp = figures["frf_bode.png"].axes[0]
    for curve, name in zip(amp.get_lines(), "xyz", strict=True):
        h = d[f"re_H{name}{name}_m_per_N"] + 1j * d[f"im_H{name}{name}_m_per_N"]
        np.testing.assert_allclose(curve.get_xdata(), d["freq_Hz"], rtol=1e-9)
        np.testing.assert_allclose(curve.get_ydata(), np.abs(h) * 1e6, rtol=1e-9)
    # the low end of the curve (0.5 Hz, well below f1) is the compliance the pose table
    # reports, in mm/kN: quasi-static amplification 1/(1 - (f/f1)^2) is under 1 %
    C = compliance_report(emodel_arm.model, emodel_arm.robot.pose("P1")).C
    assert amp.get_lines()[1].get_ydata()[0] == pytest.approx(C[1, 1] * 1e6, rel=1e-2)
    assert amp.get_title() == "E-model TCP receptance at P1"
    assert "emodel_bode_P1/frf_bode.png" in line and "emodel_bode_P1/frf.csv" in line


def test_joint_map_writes_csv_and_heat_maps(emodel_arm, tmp_path, figures):
    share_y, lines = _joint_map(tmp_path, emodel_arm, "m", 3)
    # every heat map names the model and the pose, and marks the pose
    for k in ("Kxx", "Kyy", "Kzz", "f1"):
        ax = figures[f"map_{k}_heat.png"].axes[0]
        assert ax.get_title().startswith("E-model ") and ax.get_title().endswith(" at P1")
        assert "pose P1" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert 0.0 <= share_y <= 1.0
    assert len((tmp_path / "m.csv").read_text().splitlines()) == 1 + 3 * 3
    assert lines == [f"  - ![map_{k}_heat](m/map_{k}_heat.png)"
                     for k in ("Kxx", "Kyy", "Kzz", "f1")]


@pytest.mark.slow
def test_emodel_and_flexible_steps(tmp_path):
    emodel = emodel_step(tmp_path, lambda s: None)
    flexible = flexible_step(tmp_path, lambda s: None)
    assert 5.0 < emodel.figures["emodel_P1_defl_800N_y_mm"] < 7.0
    # flexible links only add compliance
    for pose in POSES:
        assert (flexible.figures[f"flexible_{pose}_defl_800N_y_mm"]
                > emodel.figures[f"emodel_{pose}_defl_800N_y_mm"])
    assert len((tmp_path / "build.csv").read_text().splitlines()) == 1 + 7
    assert len((tmp_path / "emodel_map.csv").read_text().splitlines()) == 1 + 60 * 60
    assert "arm coordinates" in "\n".join(flexible.lines)
