"""Missing joint damping found from modal damping ratios; nothing found on correct data."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.demo_arm import load_demo_robot
from flexarm.validation.dynamic.damping_check import diagnose_damping
from flexarm.validation.dynamic.damping_fit import robot_with_damping
from flexarm.validation.lab.virtual_lab import run_lab

from ..helpers import lab_shapes, noisy_damping


@pytest.fixture(scope="module")
def base():
    return load_demo_robot()


@pytest.mark.parametrize("joint", [1, 3, 4])
def test_missing_damper_is_found_in_19_of_20_seeds(base, joint):
    """The joint's ratio 4.5 % where the model says 3 %, 8 modes at P1-P3, 3 % noise on
    each ratio (assumed 3 %): the joint alone is accepted (sweep: 20/20 for joints 1-5;
    joint 6 stores under 5 % of the first 8 modes and is reported unseen)."""
    nominal = np.array([j.model.damping_ratio for j in base.joints])
    z = nominal.copy()
    z[joint] = 1.5 * nominal[joint]
    sh = lab_shapes(robot_with_damping(base, z), 8)
    hits = [diagnose_damping(noisy_damping(sh, s), base, sigma_rel=0.03) for s in range(20)]
    assert sum(h.accepted == (joint,) for h in hits) >= 19
    ok = [h for h in hits if h.accepted == (joint,)]
    extra = np.array([h.extra[joint] for h in ok])
    assert np.all(np.abs(extra / (0.5 * nominal[joint]) - 1) < 0.3)  # sweep: 19 %
    assert "<- missing damping" in ok[0].text()


def test_nothing_is_accepted_on_damping_correct_data(base):
    sh = lab_shapes(base, 8)
    hits = [diagnose_damping(noisy_damping(sh, s), base, sigma_rel=0.03) for s in range(20)]
    assert sum(h.accepted == () for h in hits) >= 19
    assert "no joint misses damping" in hits[0].text()
    assert np.isnan(hits[0].gains[5])  # joint 6 unseen in 8 modes


def test_diagnose_with_modal_damping_names_the_missing_damper(base):
    """``diagnose --modal`` with damping ratios: a joint-3 damper at 1.5x the model's is
    reported after the static diagnosis; without modal data there is no damping check."""
    from flexarm.validation.workflow import run_diagnosis

    nominal = np.array([j.model.damping_ratio for j in base.joints])
    z = nominal.copy()
    z[2] = 1.5 * nominal[2]
    truth = robot_with_damping(base, z)
    static = run_lab(truth, poses="P1,P2", loads="0:400:200", dirs="y,z", seed=1).data
    run = run_diagnosis(static, base, modal=noisy_damping(lab_shapes(truth, 8), 1),
                        damping_noise_pct=3.0)
    assert run.damping is not None and run.damping.accepted == (2,)
    assert "missing joint damping" in run.text()
    plain = run_diagnosis(static, base)
    assert plain.damping is None and "missing joint damping" not in plain.text()
