"""Acceptance scenarios of issue 6 on virtual-lab data (nominal stiffnesses off by ±30 %).

A pass: the right effect at the right joint is ranked first and accepted, chi^2_red falls
into its band, the held-out RMS falls to about sqrt(2) sigma, and the fitted parameter's
interval covers the truth.

Seeds.  One data set is one noise draw, and the truth itself leaves the 99 % chi^2_red
band on 1 % of them (seed 1, used by most fast tests, is such a draw: the noise alone
gives chi^2_red 0.817 < 0.832).  So a fast test (one seed) checks what holds on *every*
draw: the final model fits the data as well as the truth does, within the chi^2 of its
fitted parameters (chi^2_truth - chi^2_fit ~ chi^2(n_fit)); chi^2_red is in its band
unless the noise alone is out of it on the same side; the held-out RMS is within 10 % of
the noise's own RMS (about sqrt(2) sigma).  The band's coverage, the detection rate and
the dof count are checked over seeds 0-19 by ``test_scenario_seed_sweep`` (slow; ``-s``
prints every seed's chi^2_red).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from scipy.stats import chi2

from flexarm.validation.diagnosis.search import Checks, diagnose
from flexarm.validation.static.fit import Problem

from ..conftest import covers, noise_alone
from ..helpers import PERTURB

SIGMA = 15e-6
#: Seeds of the slow sweeps: all of 0-19, none left out.
SWEEP_SEEDS = tuple(range(20))


def _status(step, name):
    return next(c for c in step.candidates if c.name == name)


def _check_fit(final, noise=None):
    """chi^2_red, the truth comparison and the held-out RMS of the final model.

    ``noise``: :func:`~tests.validation.conftest.noise_alone` of the data (without it the
    plain band and 1.6 sigma are checked)."""
    lo, hi = final.band
    red = final.chi2_red
    if noise is None:
        assert lo <= red <= hi, (red, final.band)
        assert final.rms_heldout < 1.6 * SIGMA
        return
    chi_truth, rms_noise, n_obs = noise
    n_fit = n_obs - final.dof
    gain = chi_truth - red * final.dof
    assert -1.0 <= gain <= chi2.ppf(0.999, n_fit), (gain, n_fit)
    noise_red = chi_truth / n_obs
    assert (lo <= red <= hi or (noise_red < lo and red < lo) or (noise_red > hi and red > hi)), (
        red, final.band, noise_red)
    assert final.rms_heldout <= 1.1 * rms_noise, (final.rms_heldout, rms_noise)


def _found(dg, name, param, truth, noise=None):
    """One hidden effect: ranked first, accepted, interval covers ``truth``, nothing else."""
    first = dg.steps[0]
    assert first.winner.name == name and first.accepted, first.winner
    after = dg.steps[1]
    value, sd = first.winner.params[param]
    assert covers(value, sd, truth), (value, sd, truth)
    assert not after.accepted  # nothing else
    assert after.rms_heldout < first.rms_heldout
    _check_fit(after, noise)
    return first


@dataclass(frozen=True)
class Scenario:
    """Hidden effects, the expected findings ((candidate, parameter, truth [SI] or a
    function of the arm), in any order), the fast test's seed, load/unload cycles."""

    effects: tuple
    expect: tuple
    seed: int = 1
    cycles: bool = False


def _hardening_extra(arm):  # K1/K2 = 0.5 is stated against the nominal stiffness
    k = arm.joints[0].torsion
    return 1 / (0.5 * k) - 1 / k


def _wrist_c45(arm):  # the correlation 0.5 of the lab arm's compliances (after PERTURB)
    return 0.5 * np.sqrt(1 / (PERTURB[3] * arm.joints[3].torsion)
                         / (PERTURB[4] * arm.joints[4].torsion))


#: Base compliance: 1e7 N m/rad (1e-7 rad/(N m)).  At 2e7 it is at this data set's
#: detection limit: accepted on 17 of seeds 0-19 in scenarios 5 and 9 (its unique
#: signature is 8 % of the whole; the other draws give dBIC below 10, e.g. 6.8 at seed 3).
#: Backlash (scenario 1): joint 2's torque reverses in series P2_+z only.  With whole
#: series held out, no fold could show the jump and the held-out check failed at seed 2
#: (19 of 20); folds of single readings (every third reading of every series) give 20/20.
SCENARIOS = {
    "1_backlash_j2": Scenario(("backlash:j2=0.1mrad",), (("backlash_j2", "width", 1e-4),), 3),
    "3_hardening_j1": Scenario(("hardening:j1=0.5,t=400Nm",),
                               (("hardening_j1", "extra", _hardening_extra),)),
    "4_hysteresis_j2": Scenario(("hysteresis:j2=0.1mrad,r=300Nm",),
                                (("hysteresis_j2", "lost", 1e-4),), cycles=True),
    "5_base": Scenario(("base:k=1e7",), (("base", "compliance", 1e-7),)),
    "6_wrist": Scenario(("wrist:c45=0.5",), (("wrist", "c45", _wrist_c45),)),
    "9_backlash_and_base": Scenario(("backlash:j2=0.1mrad", "base:k=1e7"),
                                    (("backlash_j2", "width", 1e-4),
                                     ("base", "compliance", 1e-7))),
}


@dataclass(frozen=True)
class Outcome:
    """One scenario on one seed (see :func:`_run`)."""

    seed: int
    diagnosis: object
    found: bool  # exactly the expected effects accepted, one per step, the first first
    covered: bool  # every fitted parameter's interval covers its truth
    chi2_red: float  # of the final model
    band: tuple
    dof: float
    noise_red: float  # chi^2_red of the truth itself (the noise alone, dof n_obs)
    gain: float  # chi^2(truth) - chi^2(final fit): chi^2(n_fit) when the dof are right
    n_fit: float  # n_obs - dof of the final model
    rms_heldout: float
    rms_noise: float

    @property
    def in_band(self) -> bool:
        return self.band[0] <= self.chi2_red <= self.band[1]

    @property
    def heldout_ok(self) -> bool:
        ho = [s.rms_heldout for s in self.diagnosis.steps]
        return bool(np.all(np.diff(ho) < 0) and ho[-1] <= 1.1 * self.rms_noise)

    def line(self) -> str:
        acc = "+".join(e.label for e in self.diagnosis.accepted) or "-"
        return (f"seed {self.seed:2d}: accepted {acc}; chi2_red {self.chi2_red:.3f} "
                f"(band {self.band[0]:.3f}-{self.band[1]:.3f}, noise alone "
                f"{self.noise_red:.3f}), chi2 gain vs truth {self.gain:5.1f} for "
                f"{self.n_fit:.2f} fitted, held-out {self.rms_heldout / SIGMA:.2f} sigma "
                f"(noise {self.rms_noise / SIGMA:.2f}), covers {self.covered}")


def _run(demo, lab, sc: Scenario, seed: int) -> Outcome:
    arm = demo[1]
    data = lab(list(sc.effects), seed=seed, cycles=sc.cycles)
    clean = lab(list(sc.effects), seed=seed, cycles=sc.cycles, noise=0.0)
    dg = diagnose(arm, data)
    chi_truth, rms_noise, n_obs = noise_alone(Problem(arm, data), data, clean)
    steps, k = dg.steps, len(sc.expect)
    wins = [s.winner.name if s.winner is not None else None for s in steps]
    names = {e[0] for e in sc.expect}
    found = (len(dg.accepted) == k and all(s.accepted for s in steps[:k])
             and set(wins[:k]) == names)
    covered = True
    for name, param, truth in sc.expect:
        step = next((s for s in steps if s.accepted and s.winner.name == name), None)
        if step is None:
            covered = False
            continue
        value, sd = step.winner.params[param]
        covered &= covers(value, sd, truth(arm) if callable(truth) else truth)
    final = dg.final
    return Outcome(seed, dg, found, bool(covered), final.chi2_red, final.band, final.dof,
                   chi_truth / n_obs, chi_truth - final.chi2_red * final.dof,
                   n_obs - final.dof, final.rms_heldout, rms_noise)


def _check(demo, lab, key):
    """The fast test of a scenario: its one seed, every per-draw check."""
    sc = SCENARIOS[key]
    arm = demo[1]
    data = lab(list(sc.effects), seed=sc.seed, cycles=sc.cycles)
    clean = lab(list(sc.effects), seed=sc.seed, cycles=sc.cycles, noise=0.0)
    dg = diagnose(arm, data)
    noise = noise_alone(Problem(arm, data), data, clean)
    if len(sc.expect) == 1:
        name, param, truth = sc.expect[0]
        _found(dg, name, param, truth(arm) if callable(truth) else truth, noise)
    return dg, noise


def test_1_backlash_joint2_found(demo, lab):
    dg, _ = _check(demo, lab, "1_backlash_j2")
    step = dg.steps[0]
    assert "changes sign" in step.explanation and "P2_+z" in step.explanation
    assert step.winner.checks.passed and step.winner.checks.failed == ()
    ident = dg.identifiability
    assert len(ident.singular_values) == len(ident.stderr) == 6
    assert set(ident.leave_one_pose_out) == {"P1", "P2", "P3"}
    assert ident.sign_changes["joint_2"] == ("P2_+z",)
    text = dg.text().splitlines()
    flat = " ".join(dg.text().split())
    assert f"ACCEPTED: {' '.join(step.explanation.split())}" in flat
    assert step.explanation.startswith("joint 2 backlash of ")
    assert "  joint 2 torque changes sign in: P2_+z" in text
    assert text.index("") < text.index(f"v0 baseline: chi2_red {step.chi2_red:.3f} (band "
                                       f"{step.band[0]:.3f}-{step.band[1]:.3f}), RMS fitted "
                                       f"{step.rms_fit * 1e6:.1f} µm, held-out "
                                       f"{step.rms_heldout * 1e6:.1f} µm")
    assert flat.endswith(" ".join(" ".join(f"note: {n}" for n in dg.notes).split()))


def test_checks_report_failures_in_order():
    c = Checks(dbic=True, heldout=False, plausible=True, interval=False)
    assert not c.passed and c.failed == ("heldout", "interval")
    assert Checks(True, True, True, True).passed
    assert Checks(True, True, True, True, distinct=False).failed == ("distinct",)


def test_8_wrong_stiffness_no_effect(demo, lab):
    perturb = (1.0, 1.0, 1.6, 1.0, 1.0, 1.0)
    data = lab(perturb=perturb)
    dg = diagnose(demo[1], data)
    assert not dg.accepted
    _check_fit(dg.steps[0], noise_alone(Problem(demo[1], data), data,
                                        lab(perturb=perturb, noise=0.0)))


def test_11_shared_reference_trap(demo, lab):
    naive_out, ours_out, naive_hit = 0, 0, 0
    for seed in range(4):
        data = lab(seed=seed)
        naive = diagnose(demo[1], data, noise_model="independent", heldout=False,
                         max_effects=0)
        ours = diagnose(demo[1], data, heldout=False, max_effects=0)
        naive_out += not (naive.steps[0].band[0] <= naive.steps[0].chi2_red
                          <= naive.steps[0].band[1])
        naive_hit += (naive.steps[0].winner.dbic > 10 if naive.steps[0].winner is not None
                      else 0)
        ours_out += ours.steps[0].chi2_red > ours.steps[0].band[1]
        assert ours.steps[0].winner.dbic < 10
    assert naive_out == 4 and ours_out == 0  # naive: "something is missing", every seed


def test_11_shared_reference_false_hit(demo, lab):
    """Reference readings with a larger error than the others (tracker re-lock, 45 um,
    stated in the file's sigma column), series of 5 readings: the naive analysis (the
    same code with the covariance replaced by sigma^2 I) accepts a false effect (4 of
    seeds 0-7; seeds 0, 1 here); ours accepts nothing and chi^2_red is in band (8 of 8)."""
    for seed in (0, 1):
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
    dg, _ = _check(demo, lab, "3_hardening_j1")
    assert abs(dg.steps[0].winner.grid_value - 400) < 40
    assert dg.final.dof == pytest.approx(dg.steps[0].dof - 2, abs=0.01)  # extra + threshold


def test_4_hysteresis_cycles_found_monotonic_untestable(demo, lab):
    dg, _ = _check(demo, lab, "4_hysteresis_j2")
    assert dg.final.dof == pytest.approx(dg.steps[0].dof - 2, abs=0.01)  # lost + radius
    mono = diagnose(demo[1], lab(["hysteresis:j2=0.1mrad,r=300Nm"]), heldout=False)
    c = _status(mono.steps[0], "hysteresis_j2")
    assert not mono.accepted and c.status == "untestable" and "cycles" in c.detail


def test_5_base_compliance_found_with_aliasing(demo, lab):
    dg, _ = _check(demo, lab, "5_base")
    assert "joint-1 torsion" in _status(dg.steps[0], "base").detail


def test_6_coupled_wrist_found(demo, lab):
    _check(demo, lab, "6_wrist")


def test_9_two_effects_in_sequence(demo, lab):
    dg, noise = _check(demo, lab, "9_backlash_and_base")
    assert sorted(e.kind for e in dg.accepted) == ["backlash", "base"]
    assert dg.steps[0].accepted and dg.steps[1].accepted and not dg.steps[2].accepted
    ho = [s.rms_heldout for s in dg.steps]
    assert ho[0] > ho[1] > ho[2]  # the error falls twice
    _check_fit(dg.steps[2], noise)


@pytest.mark.slow
@pytest.mark.parametrize("key", list(SCENARIOS))
def test_scenario_seed_sweep(demo, lab, key):
    """Every scenario on seeds 0-19: the right effects accepted on >= 95 % (19), the
    99 % intervals cover the truth on >= 90 %, chi^2_red in its 99 % band on >= 80 %
    (a correct band leaves more than 4 of 20 out with probability 4e-6), the held-out
    RMS falls to within 10 % of the noise's on >= 95 %; and the dof are counted right:
    over the seeds, the chi^2 the final fit gains on the truth averages its number of
    fitted parameters (chi^2(n_fit)) and chi^2_red averages 1.  ``-s`` prints each seed."""
    out = [_run(demo, lab, SCENARIOS[key], seed) for seed in SWEEP_SEEDS]
    ok = [o for o in out if o.found]
    gain = np.array([o.gain for o in ok])
    n_fit = float(np.mean([o.n_fit for o in ok]))
    red = np.array([o.chi2_red for o in ok])
    lines = [f"scenario {key}, seeds {SWEEP_SEEDS[0]}-{SWEEP_SEEDS[-1]}:"]
    lines += ["  " + o.line() for o in out]
    lines.append(f"  found {len(ok)}/{len(out)}, covered {sum(o.covered for o in ok)}, in band "
                 f"{sum(o.in_band for o in ok)}, held-out ok {sum(o.heldout_ok for o in ok)}; "
                 f"mean chi2_red {red.mean():.3f} (sd {red.std(ddof=1):.3f}); mean chi2 gain "
                 f"{gain.mean():.2f} for {n_fit:.2f} fitted")
    print("\n" + "\n".join(lines))  # noqa: T201
    assert len(ok) >= 0.95 * len(out)
    assert sum(o.covered for o in ok) >= 0.9 * len(ok)
    assert sum(o.in_band for o in ok) >= 0.8 * len(ok)
    assert sum(o.heldout_ok for o in ok) >= 0.95 * len(ok)
    assert abs(gain.mean() - n_fit) < 4 * np.sqrt(2 * n_fit / len(ok))
    assert abs(red.mean() - 1) < 4 * np.sqrt(2 / ok[0].dof / len(ok))


def test_pure_noise_few_seeds(demo, lab):
    hits = sum(bool(diagnose(demo[1], lab(seed=100 + s)).accepted) for s in range(3))
    assert hits == 0


@pytest.mark.slow
def test_10_pure_noise_40_seeds(demo, lab):
    """Nothing accepted on >= 95 % of seeds 1000-1039 (at most 2 hits); the baseline's
    chi^2_red in its 99 % band on >= 90 % (``-s`` prints them)."""
    seeds = range(1000, 1040)
    dgs = [diagnose(demo[1], lab(seed=s)) for s in seeds]
    hits = [s for s, dg in zip(seeds, dgs, strict=True) if dg.accepted]
    first = [dg.steps[0] for dg in dgs]
    inside = sum(f.band[0] <= f.chi2_red <= f.band[1] for f in first)
    print(f"\nscenario 10, seeds {seeds[0]}-{seeds[-1]}: accepted on "  # noqa: T201
          f"{hits or 'none'}; baseline chi2_red in band on {inside}/{len(first)}: "
          + " ".join(f"{f.chi2_red:.3f}" for f in first))
    assert len(hits) <= 2
    assert inside >= 0.9 * len(first)
