"""The GLS noise model, the degrees of freedom and the chi^2_red band (exact, deterministic)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import chi2

from flexarm.robot.effects import Effect
from flexarm.validation.static.fit import (
    Problem,
    baseline_effects,
    chi2_band,
    fit_model,
    with_effect,
)

SIGMA = 15e-6


def _noise_map(pb: Problem) -> np.ndarray:
    """(3n, 3n) map from the tracker errors of every reading (unit variance) to the
    file's relative displacements: d_k = sigma_k e_k - sigma_ref e_ref, d_ref = 0."""
    n = len(pb.ref)
    L = np.zeros((n, 3, n, 3))
    for k in range(n):
        if pb.is_ref[k]:
            continue
        for a in range(3):
            L[k, a, k, a] += pb.sigma[k]
            L[k, a, pb.ref[k], a] -= pb.sigma[pb.ref[k]]
    return L.reshape(3 * n, 3 * n)


def _whitener(pb: Problem) -> np.ndarray:
    """(m, 3n) matrix of Problem.whiten (it is linear)."""
    n = len(pb.ref)
    E = np.eye(3 * n).reshape(3 * n, n, 3)
    return np.stack([pb.whiten(e) for e in E], axis=-1)


@pytest.mark.parametrize("ref_noise", [0.0, 45e-6])
def test_whitened_noise_is_a_projection_of_rank_n_obs(demo, lab, ref_noise):
    """GLS with the shared reference: the whitened noise has covariance P, a projection
    whose rank is n_obs = 3 (rows - series) (three reference offsets per series), also
    when the reference reading is less precise (sigma column)."""
    data = lab(poses=("P1", "P2"), dirs="x,-z", loads="0:800:200", ref_noise=ref_noise)
    pb = Problem(demo[1], data)
    W, L = _whitener(pb), _noise_map(pb)
    P = W @ L @ L.T @ W.T
    assert np.allclose(P @ P, P, atol=1e-10)
    n_series = len(pb.groups)
    assert pb.n_obs == 3 * (len(data.series) - n_series) == pytest.approx(np.trace(P))


def test_dof_is_the_expected_chi2_of_the_fit(demo, lab):
    """E[chi^2] of the fitted model under noise alone equals the dof it reports:
    n_obs - tr(2H - H^2) (H: hat matrix of the whitened data, prior included), minus
    any shape parameter chosen by search."""
    data = lab(poses=("P2",), dirs="x,z,-z", loads="0:800:200")
    arm = demo[1]
    pb = Problem(arm, data)
    eff, free = baseline_effects(arm)
    prior = {f: (1.0, 1.0) for f in free}
    eff, free, scales, prior = with_effect(eff, free, np.ones(len(free)), prior,
                                           Effect("backlash", 1, (("width", 0.0),)),
                                           ["width"], [1e-4])
    fr = fit_model(pb, eff, free, scales, prior)
    X = fr.sensitivity
    A = X.T @ X + np.diag([1.0 if f in prior else 0.0 for f in free])
    H = X @ np.linalg.solve(A, X.T)
    W, L = _whitener(pb), _noise_map(pb)
    P = W @ L @ L.T @ W.T
    R = np.eye(len(H)) - H
    assert np.trace(R @ P @ R.T) == pytest.approx(fr.dof, abs=1e-6 * fr.n_obs)
    assert fr.n_obs - fr.dof == pytest.approx(fr.n_identified)
    shaped = fit_model(pb, eff, free, scales, prior, n_shape=1)
    assert shaped.dof == pytest.approx(fr.dof - 1)


def test_chi2_band_is_the_exact_central_interval():
    for dof in (3.0, 40.0, 427.0, 426.3):
        lo, hi = chi2_band(dof)
        assert chi2.cdf(lo * dof, dof) == pytest.approx(0.005)
        assert chi2.cdf(hi * dof, dof) == pytest.approx(0.995)
        lo95, hi95 = chi2_band(dof, 0.95)
        assert lo < lo95 < 1 < hi95 < hi
    lo, hi = chi2_band(427.0)
    z = 2.5758  # the normal approximation is too low at both ends (chi^2 is skewed)
    assert lo > 1 - z * np.sqrt(2 / 427) and hi > 1 + z * np.sqrt(2 / 427)
    with pytest.raises(ValueError, match="dof > 0"):
        chi2_band(0.0)

