"""What a static fit gives, and how its goodness is judged: :class:`FitResult` and the
exact band of chi^2_red (the fit itself: :mod:`~flexarm.validation.static.fit`).

Degrees of freedom and the chi^2_red band.  With the stated noise and a model that
contains the truth, the GLS chi-square of a fit is chi^2(nu) distributed with

    nu = n_obs - n_fit - n_shape,

``n_obs`` = 3 per non-reference reading (= all 3 m coordinates of a series minus its 3
reference offsets, the GLS-equivalent count; the ``independent`` model has no offsets and
drops the reference rows, the same number), plus any modal frequencies;
``n_fit`` = the effective number of fitted parameters, ``tr(2H - H^2)`` of the hat matrix
``H`` of the whitened data (= the number of fitted compliances and amplitudes the data
determine; a direction that only the weak prior pins down counts 0; with this trace the
expected chi^2 of pure noise after a linear fit is exactly ``nu``, prior included);
``n_shape`` = shape parameters chosen by a search outside the Gauss-Newton step (a
hardening threshold, a hysteresis torque radius: one each).  A refit that adds an effect
therefore removes its amplitudes (a backlash width, a lost motion, a compliance, up to
three wrist couplings) through ``n_fit`` and its shape parameter through ``n_shape``.
:func:`chi2_band` is the exact central interval of chi^2(nu)/nu.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..tolerances import tol

__all__ = ["FitResult", "chi2_band"]


@dataclass(frozen=True)
class FitResult:
    """A fitted model: effects with fitted values, covariance and goodness of fit.

    ``chi2`` is the unscaled GLS chi-square with the stated noise; ``chi2_red`` divides by
    ``dof = n_obs - n_identified - n_shape`` (module docstring): ``n_identified`` is the
    effective number of fitted parameters ``tr(2H - H^2)``, ``n_shape`` the number of shape
    parameters fixed by a search outside this fit (hardening threshold, hysteresis radius).
    """

    effects: tuple
    free: tuple
    theta: np.ndarray
    cov: np.ndarray
    chi2: float
    n_obs: int
    n_identified: float
    residual: np.ndarray
    sensitivity: np.ndarray
    n_shape: int = 0
    penalty: float = 0.0
    n_penalised: int = 0

    @property
    def dof(self) -> float:
        return max(self.n_obs - self.n_penalised - self.n_identified - self.n_shape, 1.0)

    @property
    def chi2_red(self) -> float:
        """chi^2 / dof without the fixed cost of measured modes that have no model partner
        (``penalty`` over ``n_penalised`` observations,
        :meth:`~flexarm.validation.static.fit.Problem.penalty`)."""
        return (self.chi2 - self.penalty) / self.dof

    @property
    def stderr(self) -> np.ndarray:
        return np.sqrt(np.clip(np.diag(self.cov), 0, None))

    def bic(self, n_extra: int = 0) -> float:
        """chi^2 + k ln(n_obs) with ``k`` free parameters, the ``n_shape`` shape parameters
        and ``n_extra`` more."""
        return self.chi2 + (len(self.free) + self.n_shape + n_extra) * np.log(self.n_obs)


def chi2_band(dof: float, coverage: float = tol.chi2_band_coverage) -> tuple[float, float]:
    """Exact central ``coverage`` interval of chi^2_red = chi^2(dof) / dof.

    The quantiles are chi^2 quantiles (:func:`~flexarm.validation.distributions.chi2_ppf`) at ``(1 - coverage) / 2`` and
    ``(1 + coverage) / 2`` (not the normal approximation ``1 +- z sqrt(2 / dof)``, which
    is too low at both ends: chi^2 is skewed).  ``dof`` may be fractional (effective
    parameter counts, :class:`FitResult`).  The default coverage ``0.99`` (0.5 % and
    99.5 % quantiles) is chosen because the band is checked on every model version of every
    data set, and a correct model falls outside a 95 % band once in twenty: at 99 % a false
    "something is missing" costs 1 %, while a missing effect worth adding moves chi^2_red
    by far more than the band's half-width (0.18 at dof 430).

    Examples
    --------
    >>> [round(v, 3) for v in chi2_band(427.0)]
    [0.833, 1.185]
    """
    from ..distributions import chi2_ppf

    if not dof > 0:
        raise ValueError(f"chi2_band needs dof > 0, got {dof}")
    a = (1 - coverage) / 2
    return float(chi2_ppf(a, dof) / dof), float(chi2_ppf(1 - a, dof) / dof)
