"""Modal damping per pose: stored in the robot file by ``fit-damping --method modal``,
read back, and used by the FRF at that pose (half-power bandwidth = 2 zeta f)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from flexarm.assembly.analyses import frf, modes
from flexarm.cli import main
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.formats import read as read_robot
from flexarm.robot.formats import write as write_robot
from flexarm.validation.data.formats import write_modal
from flexarm.validation.dynamic.pose_damping import damped_frf, pose_damping, store_modal_damping
from flexarm.validation.lab.virtual_lab import run_lab
from flexarm.validation.models import validation_models

from ..helpers import lab_damping


@pytest.fixture(scope="module")
def base():
    return load_demo_robot()


@pytest.fixture(scope="module")
def arm(base):
    return validation_models(base).arm


def _half_power(f: np.ndarray, mag: np.ndarray) -> tuple[float, float]:
    """(peak frequency, half-power bandwidth) [Hz] of the peak of ``mag`` on the grid
    ``f`` (crossings of peak / sqrt 2 by linear interpolation)."""
    k = int(np.argmax(mag))
    level = mag[k] / np.sqrt(2)
    lo = np.flatnonzero(mag[:k] < level)[-1]
    hi = k + np.flatnonzero(mag[k:] < level)[0]
    f_lo = np.interp(level, mag[lo:lo + 2], f[lo:lo + 2])
    f_hi = np.interp(level, mag[hi - 1:hi + 1][::-1], f[hi - 1:hi + 1][::-1])
    return float(f[k]), float(f_hi - f_lo)


def test_stored_ratios_round_trip_through_the_robot_file(base, tmp_path):
    data = lab_damping(base, seed=0, n_modes=6)
    res = store_modal_damping(data, base)
    assert set(res.robot.modal_damping) == {"P1", "P2", "P3"} and not res.added_poses
    path = write_robot(tmp_path / "modal.toml", res.robot)
    assert "[modal_damping.P1]" in path.read_text()
    back = read_robot(path)
    assert back.modal_damping == res.robot.modal_damping
    for p in ("P1", "P2", "P3"):
        rows = np.flatnonzero(data.poses == p)
        freq, zeta = back.modal_damping[p]
        np.testing.assert_array_equal(freq, data.freq_hz[rows])
        np.testing.assert_array_equal(zeta, data.damping_ratio[rows])
    assert "zeta_stored" in res.text() and "3 pose(s)" in res.text()


def test_a_new_pose_is_added_and_a_clash_is_refused(base):
    data = lab_damping(base, seed=0, n_modes=4)
    renamed = replace(data, poses=np.where(data.poses == "P2", "rig_2", data.poses))
    res = store_modal_damping(renamed, base)
    assert res.added_poses == ("rig_2",)
    np.testing.assert_allclose(res.robot.pose("rig_2"), base.pose("P2"))
    mixed = replace(data, poses=np.where(data.poses == "P2", "P1", data.poses))
    with pytest.raises(ValueError, match="rows of pose 'P1' hold different joint angles"):
        store_modal_damping(mixed, base)
    moved = replace(base, poses={**base.poses, "P2": base.pose("P3").tolist()})
    with pytest.raises(ValueError, match="pose 'P2' has other joint angles"):
        store_modal_damping(data, moved)
    with pytest.raises(ValueError, match="no pose 'P9'"):
        replace(base, modal_damping={"P9": ((8.0,), (0.02,))})


def test_frf_peak_at_the_stored_pose_has_the_stored_damping(base, arm):
    """Mode 1 at P1 stored with zeta = 0.06 (the joints give it about 0.02): the
    half-power bandwidth of the TCP receptance peak is 2 zeta f within 3 %, with the
    stored ratio; the joint-law FRF at P1 and the FRF at P2 (nothing stored) keep the
    model's ratio by the same measure."""
    q = base.pose("P1")
    md = modes(arm, q)
    f1, z_model = md.freq_hz[0], md.damping[0]
    robot = replace(base, modal_damping={"P1": ((1.02 * f1,), (0.06,))})
    axis = int(np.argmax(np.abs(md.tcp_shapes[:3, 0])))  # the mode-1 direction
    f = np.linspace(0.7 * f1, 1.3 * f1, 6001)
    for H, zeta in ((damped_frf(robot, arm, q, f), 0.06), (frf(arm, q, f), z_model)):
        fp, bw = _half_power(f, np.abs(H[:, axis, axis]))
        assert bw / fp == pytest.approx(2 * zeta, rel=0.03)
    zeta = pose_damping(robot, arm, q)
    assert zeta[0] == 0.06 and np.array_equal(zeta[1:], md.damping[1:])
    assert pose_damping(robot, arm, base.pose("P2")) is None
    q2 = base.pose("P2")
    np.testing.assert_array_equal(damped_frf(robot, arm, q2, f), frf(arm, q2, f))


def test_cli_fit_damping_modal_writes_the_table(base, tmp_path, capsys):
    lab = run_lab(base, poses="P1,P2", loads="0:100:100", dirs="z", modal=True, n_modes=4)
    modal = write_modal(tmp_path / "modal.csv", lab.shapes)
    out = tmp_path / "modal.toml"
    assert main(["fit-damping", str(modal), "--method", "modal", "-o", str(out)]) == 0
    assert "zeta_stored" in capsys.readouterr().out
    back = read_robot(out)
    assert set(back.modal_damping) == {"P1", "P2"}
    np.testing.assert_allclose(back.modal_damping["P1"][1],
                               lab.shapes.damping_ratio[lab.shapes.poses == "P1"], rtol=1e-6)


def test_compare_with_frf_data_uses_the_stored_damping(base, arm, tmp_path):
    """``compare`` on FRF data at P1: with the robot's stored ratios its predictions are
    the stored-damping FRF's (to 1e-12), and they differ from the joint-law FRF by more
    than 10 % at the first resonance."""
    from flexarm.validation.data.formats import write_frf
    from flexarm.validation.workflow import compare

    from ..helpers import frf_data

    data = frf_data(arm, base)
    md = modes(arm, base.pose("P1"))
    robot = replace(base, modal_damping={"P1": (tuple(md.freq_hz[:2]), (0.06, 0.05))})
    path = write_robot(tmp_path / "r.toml", robot)
    stored = compare(write_frf(tmp_path / "frf.csv", data), path)
    plain = compare(data, base)
    H = damped_frf(robot, arm, base.pose("P1"), data.freq_hz[:40])[:, 1, 1]
    np.testing.assert_allclose(stored.predicted[:40], H, rtol=1e-12)
    k = int(np.argmin(np.abs(data.freq_hz[:40] - md.freq_hz[0])))
    assert abs(stored.predicted[k] / plain.predicted[k]) < 0.9
