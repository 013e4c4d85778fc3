"""Weights of measured FRF lines from their coherence.

The random error of an FRF estimate from ``n_d`` averages falls with the ordinary
coherence ``gamma^2`` of its line: the normalised random error of the gain estimate is
``eps[|H|] = sqrt(1 - gamma^2) / (|gamma| sqrt(2 n_d))`` (Bendat & Piersol, *Random
Data*, 4th ed., 2010, ch. 9: random errors of frequency response function estimates).
Its inverse variance, the weight of a line in a least-squares comparison of ``log |H|``,
is thus proportional to ``gamma^2 / (1 - gamma^2)``; ``n_d`` is the same for every line
of a measurement and cancels out.  A coherence of 1 (a noise-free line) is capped at
``1 - tol.coherence_floor`` so that no single line takes all the weight.
"""

from __future__ import annotations

import numpy as np

from ...fe.typing import ArrayLike, FloatArray
from ..tolerances import tol

__all__ = ["coherence_weight", "weighted_rms", "trusted_lines"]


def coherence_weight(gamma2: ArrayLike) -> FloatArray:
    """Relative inverse-variance weight ``gamma^2 / (1 - gamma^2)`` of FRF lines.

    Parameters
    ----------
    gamma2 : (n,) float
        Ordinary coherence of each line [-], in [0, 1].

    Returns
    -------
    (n,) float
        Weight [-] (0 for a line of zero coherence).

    Examples
    --------
    >>> coherence_weight([0.0, 0.5, 0.9]).round(6).tolist()
    [0.0, 1.0, 9.0]
    """
    g2 = np.clip(np.asarray(gamma2, float), 0.0, 1.0 - tol.coherence_floor)
    return g2 / (1.0 - g2)


def weighted_rms(values: ArrayLike, weights: ArrayLike | None = None) -> float:
    """RMS of ``values``, weighted by ``weights`` (None: equal weights; 0 for no values).

    Examples
    --------
    >>> weighted_rms([1.0, 3.0]), weighted_rms([1.0, 3.0], [1.0, 0.0])
    (2.23606797749979, 1.0)
    """
    v = np.asarray(values, float)
    if not v.size:
        return 0.0
    w = np.ones_like(v) if weights is None else np.asarray(weights, float)
    total = float(np.sum(w))
    return float(np.sqrt(np.sum(w * v**2) / total)) if total > 0 else 0.0


def trusted_lines(gamma2: ArrayLike | None, n: int) -> np.ndarray:
    """(n,) bool: lines whose coherence reaches ``tol.peak_coherence`` (all lines when
    there is no coherence, or when none reaches it): where a peak is looked for.

    Examples
    --------
    >>> trusted_lines([0.99, 0.2, 0.95], 3).tolist(), trusted_lines(None, 2).tolist()
    ([True, False, True], [True, True])
    """
    if gamma2 is None:
        return np.ones(n, bool)
    ok = np.asarray(gamma2, float) >= tol.peak_coherence
    return ok if ok.any() else np.ones(n, bool)
