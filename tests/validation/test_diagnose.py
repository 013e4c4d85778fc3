"""Acceptance scenarios of issue 6 on virtual-lab data (nominal stiffnesses off by ±30 %).

A pass: the right effect at the right joint is ranked first and accepted, chi^2_red falls
into its band, the held-out RMS falls to about sqrt(2) sigma, and the fitted parameter's
interval covers the truth.
"""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.validation.diagnose import diagnose

from .conftest import covers

SIGMA = 15e-6


def _status(step, name):
    return next(c for c in step.candidates if c.name == name)


def _found(dg, name, param, truth):
    first = dg.steps[0]
    assert first.winner["name"] == name and first.accepted, first.winner
    after = dg.steps[1]
    assert after.band[0] - 0.05 <= after.chi2_red <= after.band[1]
    assert after.rms_heldout < 1.6 * SIGMA
    value, sd = first.winner["params"][param]
    assert covers(value, sd, truth), (value, sd, truth)
    assert not after.accepted  # nothing else
    return first


def test_1_backlash_joint2_found(demo, lab):
    dg = diagnose(demo[1], lab(["backlash:j2=0.1mrad"], seed=3))
    step = _found(dg, "backlash_j2", "width", 1e-4)
    assert "changes sign" in step.explanation and "P2_+z" in step.explanation


def test_8_wrong_stiffness_no_effect(demo, lab):
    dg = diagnose(demo[1], lab(perturb=(1.0, 1.0, 1.6, 1.0, 1.0, 1.0)))
    assert not dg.accepted
    assert dg.steps[0].band[0] - 0.05 <= dg.steps[0].chi2_red <= dg.steps[0].band[1]


def test_11_shared_reference_trap(demo, lab):
    naive_out, ours_out, naive_hit = 0, 0, 0
    for seed in range(4):
        data = lab(seed=seed)
        naive = diagnose(demo[1], data, noise_model="independent", heldout=False,
                         max_effects=0)
        ours = diagnose(demo[1], data, heldout=False, max_effects=0)
        naive_out += not (naive.steps[0].band[0] <= naive.steps[0].chi2_red
                          <= naive.steps[0].band[1])
        naive_hit += naive.steps[0].winner["dbic"] > 10 if naive.steps[0].winner else 0
        ours_out += ours.steps[0].chi2_red > ours.steps[0].band[1]
        assert ours.steps[0].winner["dbic"] < 10
    assert naive_out == 4 and ours_out == 0  # naive: "something is missing", every seed


def test_11_shared_reference_false_hit(demo, lab):
    """Reference readings with a larger error than the others (tracker re-lock, 45 um,
    stated in the file's sigma column), series of 5 readings: the naive analysis (the
    same code with the covariance replaced by sigma^2 I) accepts a false effect (4 of
    seeds 0-7; seeds 1, 2 here); ours accepts nothing and chi^2_red is in band (8 of 8)."""
    for seed in (1, 2):
        data = lab(seed=seed, loads="0:800:200", ref_noise=45e-6)
        naive = diagnose(demo[1], data, noise_model="independent", max_effects=0)
        ours = diagnose(demo[1], data, max_effects=0)
        assert naive.steps[0].accepted and naive.accepted, naive.steps[0].winner
        assert naive.steps[0].chi2_red > 5 * naive.steps[0].band[1]
        first = ours.steps[0]
        assert not ours.accepted and first.band[0] <= first.chi2_red <= first.band[1]


def test_2_backlash_never_reversing_untestable(demo, lab):
    dg = diagnose(demo[1], lab(["backlash:j2=0.1mrad"], poses=("P1", "P3")), poses=demo[0].poses)
    assert not dg.accepted
    c = _status(dg.steps[0], "backlash_j2")
    assert c.status == "untestable" and "add loads" in c.detail and "+z" in c.detail


def test_3_hardening_joint1_found(demo, lab):
    dg = diagnose(demo[1], lab(["hardening:j1=0.5,t=400Nm"]))
    k2 = demo[1].joints[0].torsion  # K1/K2 is stated against the nominal stiffness
    step = _found(dg, "hardening_j1", "extra", 1 / (0.5 * k2) - 1 / k2)
    assert abs(step.winner["grid"][1] - 400) < 40


def test_4_hysteresis_cycles_found_monotonic_untestable(demo, lab):
    dg = diagnose(demo[1], lab(["hysteresis:j2=0.1mrad,r=300Nm"], cycles=True))
    _found(dg, "hysteresis_j2", "lost", 1e-4)
    mono = diagnose(demo[1], lab(["hysteresis:j2=0.1mrad,r=300Nm"]), heldout=False)
    c = _status(mono.steps[0], "hysteresis_j2")
    assert not mono.accepted and c.status == "untestable" and "cycles" in c.detail


def test_5_base_compliance_found_with_aliasing(demo, lab):
    dg = diagnose(demo[1], lab(["base:k=2e7"]))
    _found(dg, "base", "compliance", 5e-8)
    assert "joint-1 torsion" in _status(dg.steps[0], "base").detail


def test_6_coupled_wrist_found(demo, lab):
    arm = demo[1]
    dg = diagnose(arm, lab(["wrist:c45=0.5"]))
    truth = 0.5 * np.sqrt(1 / arm.joints[3].torsion / arm.joints[4].torsion)
    _found(dg, "wrist", "c45", truth)


def test_9_two_effects_in_sequence(demo, lab):
    dg = diagnose(demo[1], lab(["backlash:j2=0.1mrad", "base:k=2e7"], seed=1))
    assert [e.kind for e in dg.accepted] == ["backlash", "base"]
    ho = [s.rms_heldout for s in dg.steps]
    assert ho[0] > ho[1] > ho[2] and dg.steps[2].rms_heldout < 1.6 * SIGMA


def test_pure_noise_few_seeds(demo, lab):
    hits = sum(bool(diagnose(demo[1], lab(seed=100 + s)).accepted) for s in range(3))
    assert hits == 0


@pytest.mark.slow
def test_10_pure_noise_40_seeds(demo, lab):
    hits = sum(bool(diagnose(demo[1], lab(seed=1000 + s)).accepted) for s in range(40))
    assert hits <= 2
