"""The few distribution functions the validation tests need, from :mod:`scipy.special`.

``scipy.stats`` takes about 0.6 s to import (it builds every distribution object), which
every ``flexarm`` command that prints a chi-square band would pay; the special functions
behind these quantiles and tails load with ``scipy.linalg`` and give the same numbers
(``scipy.stats`` calls the same Cephes routines).  Arguments broadcast like NumPy's;
a statistic below zero has tail probability 1, as in ``scipy.stats``.
"""

from __future__ import annotations

import numpy as np
from scipy import special

__all__ = ["chi2_sf", "chi2_isf", "chi2_ppf", "f_sf", "norm_cdf"]


def chi2_sf(x, dof):
    """P(X > ``x``) for X ~ chi^2(``dof``) (``dof`` may be fractional).

    Examples
    --------
    >>> round(float(chi2_sf(7.814727903251178, 3)), 12), float(chi2_sf(-1.0, 3))
    (0.05, 1.0)
    """
    return special.chdtrc(dof, np.maximum(x, 0.0))


def chi2_isf(p, dof):
    """``x`` with P(X > x) = ``p`` for X ~ chi^2(``dof``).

    Examples
    --------
    >>> round(float(chi2_isf(0.05, 3)), 6)
    7.814728
    """
    return special.chdtri(dof, p)


def chi2_ppf(q, dof):
    """``x`` with P(X <= x) = ``q`` for X ~ chi^2(``dof``).

    Examples
    --------
    >>> round(float(chi2_ppf(0.005, 427.0)), 4)
    355.484
    """
    return special.chdtri(dof, 1.0 - np.asarray(q, dtype=float))


def f_sf(x, dfn, dfd):
    """P(X > ``x``) for X ~ F(``dfn``, ``dfd``).

    Examples
    --------
    >>> round(float(f_sf(3.3, 2, 5)), 6), float(f_sf(-1.0, 2, 5))
    (0.121978, 1.0)
    """
    return special.fdtrc(dfn, dfd, np.maximum(x, 0.0))


def norm_cdf(x):
    """P(Z <= ``x``) for a standard normal Z.

    Examples
    --------
    >>> round(float(norm_cdf(2.0)), 6)
    0.97725
    """
    return special.ndtr(x)
