"""ComplianceReport (flexarm/studies/compliance.py) in a notebook: repr and table."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly import emodel
from flexarm.robot import load_robot
from flexarm.studies.compliance import compliance_report


@pytest.fixture(scope="module")
def report():
    robot = load_robot()
    return compliance_report(emodel(robot), robot.pose("P1"), force=500.0)


def test_repr_states_deflections_and_sag(report):
    text = repr(report)
    assert len(text) < 300 and "\n" not in text
    defl = text.split("deflection under 500 N: ")[1].split(" mm;")[0].split(", ")
    assert [d.split()[0] for d in defl] == ["x", "y", "z"]
    assert [float(d.split()[1]) for d in defl] == pytest.approx(1e3 * report.deflection,
                                                                rel=1e-3)
    assert f"weakest {report.weakest};" in text
    err = float(text.split("error up to ")[1].split(" %")[0])
    assert err == pytest.approx(100 * np.abs(report.error_diag).max(), rel=1e-2)
    sag = text.split("gravity sag ")[1].removesuffix(" mm)").split(", ")
    assert [float(s.split()[1]) for s in sag] == pytest.approx(1e3 * report.sag[:3],
                                                               rel=1e-3)


def test_dataframe_one_row_per_direction(report):
    pytest.importorskip("pandas")
    f = report.to_dataframe().set_index("direction")
    assert f.index.tolist() == ["x", "y", "z"]
    C = f[["C_x_m_per_N", "C_y_m_per_N", "C_z_m_per_N"]].to_numpy()
    assert np.array_equal(C, report.C[:3, :3])
    K = f[["K_x_N_per_m", "K_y_N_per_m", "K_z_N_per_m"]].to_numpy()
    assert np.array_equal(K, report.K_full)
    assert np.array_equal(f["K_diag_N_per_m"], np.diag(report.K_diag))
    # deflection [mm] = 1e3 * force [N] * compliance [m/N], an independent product
    assert np.allclose(f["deflection_mm"], 1e3 * f["force_N"] * np.diag(C), rtol=1e-14)
    assert np.allclose(f["sag_mm"], 1e3 * report.sag[:3], rtol=1e-15)
    assert np.array_equal(f["error_diag"], report.error_diag)
    assert f["deflection_mm"].idxmax() == report.weakest


def test_csv_has_one_unit_per_column_and_the_whole_matrix(report, tmp_path):
    path = report.write_csv(tmp_path / "compliance.csv")
    head = path.read_text().splitlines()[0].split(",")
    rows = np.loadtxt(path, delimiter=",", skiprows=1, usecols=range(1, 13))
    assert head[0] == "axis" and len(head) == 13
    units = {"u_F": "m_per_N", "rot_F": "rad_per_N", "u_M": "m_per_Nm", "rot_M": "rad_per_Nm"}
    for name in head[1:]:
        kind = "_".join(name.split("_")[1:3])[:-1]  # C_u_Fx_m_per_N -> u_F
        assert name.endswith("_" + units[kind]), name
    C = np.block([[rows[:, 0:3], rows[:, 6:9]], [rows[:, 3:6], rows[:, 9:12]]])
    np.testing.assert_allclose(C, report.C, rtol=1e-9, atol=0)


def test_a_pose_outside_the_limits_is_refused_as_on_the_command_line():
    robot = load_robot()
    with pytest.raises(ValueError, match=r"pose: joint_3 = -200 deg is outside its limits"):
        compliance_report(emodel(robot), np.radians([0, 20, -200, 0, 0, 0]))
