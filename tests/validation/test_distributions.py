"""The distribution tails of :mod:`flexarm.validation.distributions` against scipy.stats
(an independent implementation of the same quantities), over a sweep of arguments."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from flexarm.validation.distributions import chi2_isf, chi2_ppf, chi2_sf, f_sf, norm_cdf

DOFS = [0.5, 1.0, 2.5, 3.0, 10.0, 427.0, 1e4]


@pytest.mark.parametrize("dof", DOFS)
def test_chi_square_tails_and_quantiles_are_scipy_stats(dof):
    x = np.concatenate([[-1.0, 0.0], np.geomspace(1e-3, 10 * dof + 50, 40)])
    assert np.allclose(chi2_sf(x, dof), stats.chi2.sf(x, dof), rtol=1e-10, atol=1e-300)
    p = np.array([1e-9, 0.005, 0.05, 0.5, 0.95, 0.995])
    assert np.allclose(chi2_isf(p, dof), stats.chi2.isf(p, dof), rtol=1e-10)
    assert np.allclose(chi2_ppf(p, dof), stats.chi2.ppf(p, dof), rtol=1e-9)
    # the quantile and the tail undo each other
    assert np.allclose(chi2_sf(chi2_isf(p, dof), dof), p, rtol=1e-8)


@pytest.mark.parametrize(("dfn", "dfd"), [(1, 5), (2, 5), (3, 40), (12, 300)])
def test_f_tail_is_scipy_stats(dfn, dfd):
    x = np.concatenate([[-2.0, 0.0], np.geomspace(1e-4, 100.0, 30)])
    assert np.allclose(f_sf(x, dfn, dfd), stats.f.sf(x, dfn, dfd), rtol=1e-10, atol=1e-300)


def test_normal_cdf_is_scipy_stats():
    x = np.linspace(-8.0, 8.0, 81)
    assert np.allclose(norm_cdf(x), stats.norm.cdf(x), rtol=1e-12, atol=1e-300)
