"""Joint damping fitted to modal damping from the virtual lab, and the robot file round trip."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from flexarm.assembly.analyses import modes
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.formats import read as read_robot
from flexarm.robot.formats import write as write_robot
from flexarm.validation.dynamic.damping_fit import fit_damping, robot_with_damping
from flexarm.validation.models import validation_models

from ..helpers import lab_damping

TRUE = np.array([0.01, 0.03, 0.02, 0.05, 0.04, 0.06])


@pytest.fixture(scope="module")
def base():
    return load_demo_robot()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_joint_dampers_are_recovered_within_10pct(base, seed):
    """Ratios 1-6 % per joint hidden in the lab, 3 % noise on each identified ratio:
    the per-joint fit wins the AICc and gets every joint within 10 % (20 seeds: worst
    5.1 %)."""
    res = fit_damping(lab_damping(robot_with_damping(base, TRUE), seed), base)
    assert res.method == "joints"
    assert res.seen.all()
    np.testing.assert_allclose(res.joint_ratios["joints"], TRUE, rtol=0.10)
    assert res.rms("joints") < 0.05 < res.rms("constant")
    got = [j.emodel.damping_ratio if j.emodel is not None else j.model.damping_ratio
           for j in res.robot.joints]
    np.testing.assert_allclose(got, res.joint_ratios["joints"], rtol=0, atol=0)


def test_rayleigh_law_and_constant_ratio_are_picked_when_they_hold(base):
    """A Rayleigh law in every joint gives back its alpha and beta; one ratio for all
    joints is not over-fitted by the per-joint fit (AICc)."""
    ray = fit_damping(lab_damping(robot_with_damping(base, TRUE, (2.0, 4e-4)), 3), base)
    assert ray.method == "rayleigh"
    np.testing.assert_allclose(ray.rayleigh, (2.0, 4e-4), rtol=0.10)
    const = fit_damping(lab_damping(robot_with_damping(base, [0.025] * 6), 4), base)
    assert const.method == "constant"
    np.testing.assert_allclose(const.joint_ratios["constant"], 0.025, rtol=0.03)


def test_fitted_robot_round_trips_through_toml(base, tmp_path):
    """The written robot file reads back with the fitted ratios, and its E-model's modal
    damping (an independent path through the assembly) is the fit's."""
    res = fit_damping(lab_damping(robot_with_damping(base, TRUE), 5), base)
    path = write_robot(tmp_path / "damped.toml", res.robot)
    back = read_robot(path)
    for a, b in zip(back.joints, res.robot.joints, strict=True):
        assert a.model.damping_ratio == b.model.damping_ratio
        assert (a.emodel is None) == (b.emodel is None)
        if a.emodel is not None:
            assert a.emodel.damping_ratio == b.emodel.damping_ratio
    arm = validation_models(back).arm
    got = []
    for pose in ("P1", "P2", "P3"):
        md = modes(arm, back.pose(pose))
        rows = res.poses == pose
        got.append(md.damping[res.modes[rows] - 1])
    np.testing.assert_allclose(np.concatenate(got), res.fitted["joints"], rtol=1e-9)
    png = res.plot(tmp_path / "d.png")
    assert png.stat().st_size > 10_000
    assert "<- written" in res.text()


def test_rayleigh_robot_round_trips_through_toml(base, tmp_path):
    r = robot_with_damping(base, TRUE, (2.0, 4e-4))
    back = read_robot(write_robot(tmp_path / "r.toml", r))
    assert all(j.model.rayleigh == (2.0, 4e-4) for j in back.joints)


def test_bad_input_is_one_clear_error(base, tmp_path):
    sh = lab_damping(base, 0)
    with pytest.raises(ValueError, match="no 'damping_ratio' column"):
        fit_damping(replace(sh, damping_ratio=None), base)
    with pytest.raises(ValueError, match="method must be auto or one of"):
        fit_damping(sh, base, method="modal")
