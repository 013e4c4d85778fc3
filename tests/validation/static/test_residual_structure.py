"""Residual-structure tests on the baseline fit (flexarm/validation/residual_structure.py):
each fault outside the candidate library is named, pure noise sets nothing off, and the
F tests' p-values are uniform on pure noise (the stated false-alarm rate holds)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import kstest

from flexarm.validation.static.fit import Problem, baseline_effects, fit_model
from flexarm.validation.static.residual_structure import STRUCTURES, residual_structure
from flexarm.validation.tolerances import tol

from ..misfit_cases import DRIFT, MISFIT_CASES, NOISE_FACTOR, misfit_data


def _baseline_structure(arm, data):
    problem = Problem(arm, data)
    effects, free = baseline_effects(arm)
    prior = {f: (1.0, tol.baseline_prior_sd) for f in free}
    fr = fit_model(problem, effects, free, np.ones(len(free)), prior)
    return fr, residual_structure(problem, fr.effects, fr.sensitivity, fr.n_identified)


@pytest.mark.parametrize("case", ["none"] + list(MISFIT_CASES))
def test_each_fault_named_alone(demo, case):
    """One seed: exactly the right structure (none for pure noise or a larger noise)."""
    robot, arm = demo
    data, rows = misfit_data(robot, arm, case, seed=1)
    _, rs = _baseline_structure(arm, data)
    names = [t.name for t in rs.found]
    expected = MISFIT_CASES.get(case, (None,))[0]
    assert names == ([] if expected in (None, "scale") else [expected]), [
        t.line() for t in rs.found]
    assert [t.name for t in rs.tests] == list(STRUCTURES)
    if case == "noise":
        assert abs(rs.noise_scale - NOISE_FACTOR) < 0.2, rs.noise_scale
    elif case == "none":
        assert abs(rs.noise_scale - 1.0) < 0.15
    if case == "outliers":
        steps = {(str(data.series[i]), int(data.steps[i])) for i in rows}
        assert steps == {(s, k) for s, k, _ in rs.outliers}
        assert all(z > 15 for _, _, z in rs.outliers[:len(rows)])
    if case == "drift":  # the fitted size: 5 µm per reading
        size = float(rs.test("drift").size.split()[0])
        assert abs(size - 1e6 * np.linalg.norm(DRIFT)) < 1.0, size


@pytest.mark.slow
def test_false_alarm_rate_on_pure_noise(demo):
    """Seeds 0-99 of pure noise: every test together sets off at most 3 (7 tests at a
    stated rate of 0.001 give 0.7 expected); the non-family F tests' p-values are
    uniform (Kolmogorov-Smirnov p > 0.001)."""
    robot, arm = demo
    found, pvals = 0, {k: [] for k in ("frame", "drift", "tool")}
    for seed in range(100):
        data, _ = misfit_data(robot, arm, "none", seed)
        _, rs = _baseline_structure(arm, data)
        found += len(rs.found)
        for k in pvals:
            pvals[k].append(rs.test(k).p_value)
    print(f"\nstructure false alarms on 100 pure-noise seeds: {found}; KS p: "  # noqa: T201
          + ", ".join(f"{k} {kstest(v, 'uniform').pvalue:.3f}" for k, v in pvals.items()))
    assert found <= 3
    for v in pvals.values():
        assert kstest(v, "uniform").pvalue > 1e-3
