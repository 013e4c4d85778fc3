"""A wrist damper through the lab's FRFs: ``lab --frf-band`` reaches the joint-5 modes
(239-265 Hz), ``ema`` identifies them, and the damping check names joint 5."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.validation.data.formats.uff import read_uff
from flexarm.validation.dynamic.damping_check import diagnose_damping
from flexarm.validation.dynamic.damping_fit import robot_with_damping
from flexarm.validation.dynamic.ema import run_ema
from flexarm.validation.lab.virtual_lab import run_lab

#: FRF band of the lab [Hz]: past the joint-5 modes (239-265 Hz at P1-P3).
BAND = (0.25, 300.0)


@pytest.fixture(scope="module")
def base():
    return load_demo_robot()


def test_lab_frf_band_option_sets_the_lines(tmp_path):
    assert main(["lab", "--poses", "P1", "--loads", "0:100:100", "--dirs", "z", "--modal",
                 str(tmp_path / "lab.uff"), "--n-modes", "4", "--frf-band", "10:300",
                 "-o", str(tmp_path / "s.csv")]) == 0
    f = read_uff(tmp_path / "lab.uff").frfs[0].freq_hz
    assert f[0] == 10.0 and f[-1] == 300.0 and np.allclose(np.diff(f), 0.25)
    assert main(["lab", "--modal", str(tmp_path / "x.uff"), "--frf-band", "300",
                 "-o", str(tmp_path / "x.csv")]) == 2


def _check(robot, base, seed: int):
    lab = run_lab(robot, poses="P1,P2,P3", loads="0:100:100", dirs="z", modal=True,
                  n_modes=10, seed=seed, frf_band=BAND)
    modal = run_ema(list(lab.frfs), min_stable=0.5).modal()
    return diagnose_damping(modal, base, sigma_rel=0.05)


@pytest.mark.slow  # a seed sweep through FRFs to 300 Hz and ema: minutes
def test_missing_wrist_damper_is_found_through_ema(base):
    """Joint 5's ratio at 1.5x the model's, FRFs (2 % noise) to 300 Hz at P1-P3, poles
    from ``ema``, 5 % assumed scatter of a ratio clear of its neighbours, seeds 0-19: the
    damper is named on 19 or more seeds and nothing is accepted on damping-correct data.
    At P1 and P2 joint 5's two modes overlap (9 Hz apart, half-power bandwidths near
    17 Hz): ``ema`` got their ratios 20-40 % wrong from one fit over the band, and
    weighted as if separated they hid the damper on 7 of 20 seeds, so the check widens a
    ratio's scatter by its modal overlap (sweep then: 20/20 for any widening factor from
    0.5 to 5 times the overlap).  Fitted in zoomed sub-bands with each FRF scaled to its
    RMS and refined, the pair comes out as two poles with ratios within 0.1-5.7 %; a
    widening of 1x then left joint 5's gain at 8.6 (the lab's exact ratios give 9.3), so
    the check widens by 0.5x (20/20 named, 20/20 quiet).
    Joint 6 (its mode near 555 Hz turns the tool about its own axis) stays unseen."""
    nominal = np.array([j.model.damping_ratio for j in base.joints])
    z = nominal.copy()
    z[4] *= 1.5
    hits = [_check(robot_with_damping(base, z), base, s) for s in range(20)]
    clean = [_check(base, base, s) for s in range(20)]
    found = sum(h.accepted == (4,) for h in hits)
    quiet = sum(h.accepted == () for h in clean)
    print(f"\njoint-5 damper through ema: found {found}/20, nothing on correct data "  # noqa: T201
          f"{quiet}/20")
    assert found >= 19 and quiet >= 19
    assert all(h.accepted in ((), (4,)) for h in hits)
    assert np.isnan(hits[0].gains[5])


def test_one_seed_of_the_wrist_damper_through_ema(base):
    """Seed 0 of the sweep above: the damper named, nothing on correct data."""
    z = np.array([j.model.damping_ratio for j in base.joints])
    z[4] *= 1.5
    assert _check(robot_with_damping(base, z), base, 0).accepted == (4,)
    assert _check(base, base, 0).accepted == ()
