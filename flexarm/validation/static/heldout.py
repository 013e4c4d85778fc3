"""Held-out validation of a fitted model: the RMS of the residual on readings (or whole
series) left out of the fit, fold by fold."""

from __future__ import annotations

import copy

import numpy as np

from ..tolerances import tol
from .fit import Problem, fit_model

__all__ = ["heldout_rms"]


def heldout_rms(problem: Problem, effects, free, scales, prior, folds: int = tol.cv_folds,
                by: str | None = None) -> float:
    """RMS [m] of the raw relative residual on held-out readings or series.

    ``by`` (default ``tol.heldout_by``): ``"readings"`` holds out every ``folds``-th
    reading of every series (stratified: each fold holds readings of every series, so a
    torque reversal seen in one series only is still both fitted and tested; a held-out
    reading leaves the fit as a discounted one does); ``"series"`` holds out whole series
    (round-robin over a fixed permutation).  Discounted readings are never tested.
    """
    by = by or tol.heldout_by
    if by not in ("readings", "series"):
        raise ValueError(f"heldout by must be 'readings' or 'series', got {by}")
    sid = problem.series_id
    n_s = sid.max() + 1
    if n_s < folds:
        return float("nan")
    perm = np.random.default_rng(0).permutation(n_s)  # fixed, mixes directions
    if by == "series":
        fold_of = (perm % folds)[sid]
    else:
        pos = np.arange(len(sid)) - problem.ref  # position within the series
        fold_of = (pos + perm[sid]) % folds
    usable = ~problem.is_ref & ~problem.discounted
    sq, cnt = 0.0, 0
    for k in range(folds):
        test = fold_of == k
        if by == "series":
            fr = fit_model(problem, effects, free, scales, prior, rows=~test, iterations=2)
        else:
            train = copy.copy(problem)
            train.discount(np.flatnonzero(test & ~problem.is_ref))
            fr = fit_model(train, effects, free, scales, prior, iterations=2)
        r = (problem.y - problem.predict(fr.effects))[test & usable]
        sq += float((r**2).sum())
        cnt += r.size
    return float(np.sqrt(sq / max(cnt, 1)))
