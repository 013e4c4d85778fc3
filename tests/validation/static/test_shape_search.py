"""Shape parameters searched again with every amplitude free
(flexarm/validation/shape_search.py), and two effects on one joint in a diagnosis:
backlash 0.2 mrad and hardening (K1/K2 = 0.5 below 800 N m) on joint 2, which the greedy
search with frozen thresholds fitted as backlash 0.13-0.17 mrad and threshold ~580 N m."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.effects import Effect
from flexarm.validation.diagnosis.search import diagnose
from flexarm.validation.static.fit import Problem, baseline_effects
from flexarm.validation.static.shape_search import research_shapes, shaped
from flexarm.validation.tolerances import tol

from ..conftest import covers

EFFECTS = ("backlash:j2=0.2mrad", "hardening:j2=0.5,t=800Nm")
WIDTH, THRESHOLD = 2e-4, 800.0


def _extra(arm):  # K1/K2 = 0.5 against the nominal stiffness
    return 1 / arm.joints[1].torsion


def test_research_moves_a_wrong_threshold(demo, lab):
    arm = demo[1]
    problem = Problem(arm, lab(list(EFFECTS), seed=1))
    effects, free = baseline_effects(arm)
    n = len(effects)
    effects += [Effect("backlash", 1, (("width", 1e-4),)),
                Effect("hardening", 1, (("extra", 1e-7), ("threshold", 500.0)))]
    free += [(n, "width"), (n + 1, "extra")]
    scales = np.r_[np.ones(n), 1e-4, 1e-7]
    prior = {f: (1.0, tol.baseline_prior_sd) for f in free[:n]}
    assert shaped(effects, n) == [n + 1] and shaped(effects, n, joint=0) == []
    fit = research_shapes(problem, effects, free, scales, prior, 1, [n + 1])
    assert abs(fit.effects[-1].get("threshold") - THRESHOLD) < 0.1 * THRESHOLD
    assert abs(fit.effects[-2].get("width") - WIDTH) < 0.15 * WIDTH
    assert fit.n_shape == 1
    assert fit.chi2_red < 1.2


def _two_on_one_joint(demo, lab, seed):
    arm = demo[1]
    dg = diagnose(arm, lab(list(EFFECTS), seed=seed))
    got = {e.kind: e for e in dg.accepted}
    ok = set(got) == {"backlash", "hardening"} and not dg.unexplained
    close = ok and (abs(got["backlash"].get("width") - WIDTH) < 0.25 * WIDTH
                    and abs(got["hardening"].get("threshold") - THRESHOLD) < 0.15 * THRESHOLD)
    return dg, ok, close


def test_two_effects_on_one_joint(demo, lab):
    dg, ok, close = _two_on_one_joint(demo, lab, seed=0)
    assert ok and close, [e.params for e in dg.accepted]
    lo, hi = dg.final.band
    assert lo <= dg.final.chi2_red <= hi
    # the accepted effects hold the values after the joint search (the step that accepted
    # the hardening first shows its greedy, biased value)
    extra = next(e for e in dg.accepted if e.kind == "hardening").get("extra")
    assert abs(extra - _extra(demo[1])) < 0.15 * _extra(demo[1]), extra
    step = next(s for s in dg.steps if s.accepted and s.winner.name == "backlash_j2")
    value, sd = step.winner.params["width"]  # accepted second: fitted jointly
    assert covers(value, sd, WIDTH), (value, sd)


@pytest.mark.slow
def test_two_effects_on_one_joint_seed_sweep(demo, lab):
    """Seeds 0-19: both accepted and the model explains the data on >= 18; the backlash
    width within 25 % and the threshold within 15 % of the truth on >= 18."""
    out = [_two_on_one_joint(demo, lab, seed) for seed in range(20)]
    for seed, (dg, ok, close) in enumerate(out):
        print(f"seed {seed}: {ok} {close} "  # noqa: T201
              f"{[(e.label, dict(e.params)) for e in dg.accepted]}")
    assert sum(ok for _, ok, _ in out) >= 18
    assert sum(close for _, _, close in out) >= 18
