"""The backward step of the diagnosis: an effect accepted early may be a stand-in.

A forward search accepts the candidate that best explains what is left, one at a time.
When the true cause is found later, an effect accepted before it may only have been
borrowing part of its pattern (a joint-1 bearing tilt taking up some of a joint-2 stiffness
that grows with torque).  After every acceptance past the first, each earlier accepted
effect is taken out again and the model refitted without it; the one whose removal the
Bayesian information criterion prefers most (keeping it gains less than
``tol.delta_bic_accept``, the bar it had to pass to get in) is dropped, and the test is
repeated until every accepted effect earns its place.  This is stepwise regression's
backward elimination with the acceptance threshold as the stay threshold.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..static.fit import MODEL_ERRORS, FitResult, Problem, chi2_band, fit_model
from ..static.shape_search import SHAPES
from ..tolerances import tol

__all__ = ["Dropped", "backward_step"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Dropped:
    """An accepted effect taken out again, and the model without it.

    Attributes
    ----------
    index : int
        Its index in the effects of the model it was dropped from.
    label : str
        The dropped effect (``"joint 1 bearing tilt"``).
    dbic_keep : float
        ΔBIC of keeping it in the model with the later effects (< ``tol.delta_bic_accept``).
    fit : FitResult
        The refitted model without it.
    free : list of (effect index, name)
        Its free parameters (indices renumbered).
    scales : (p,) float
        Their typical sizes.
    n_shape : int
        Shape parameters still counted.
    """

    index: int
    label: str
    dbic_keep: float
    fit: FitResult
    free: list
    scales: np.ndarray
    n_shape: int

    def text(self, after: str) -> str:
        """One sentence: what was dropped and why (``after`` names the later effect)."""
        return (f"{self.label} dropped: with {after} in, the data no longer need it "
                f"(keeping it gains ΔBIC {self.dbic_keep:.1f} < {tol.delta_bic_accept:g})")


def _without(fr: FitResult, free, scales, k: int):
    """Effects, free parameters and scales of the model ``fr`` without effect ``k``."""
    effects = [e for i, e in enumerate(fr.effects) if i != k]
    keep = [j for j, (i, _) in enumerate(free) if i != k]
    free2 = [(i - (i > k), name) for i, name in (free[j] for j in keep)]
    return effects, free2, np.asarray(scales, float)[keep]


def backward_step(problem: Problem, fr: FitResult, free, scales, prior, n_shape: int,
                  candidates: range) -> Dropped | None:
    """The effect among ``candidates`` (indices into ``fr.effects``) that the model ``fr``
    is better without, or None when every one earns its place.

    Keeping effect ``k`` gains ΔBIC = (χ²_without − χ²_with) / s − p_k ln n, with ``p_k``
    its free and shape parameters, ``n`` the observations and ``s`` the misfit inflation
    (χ²_red of ``fr`` when it lies above its band, as in the forward step's F test).  A
    refit that cannot be evaluated keeps the effect.
    """
    band = chi2_band(fr.dof)
    infl = max(1.0, fr.chi2_red) if fr.chi2_red > band[1] else 1.0
    iterations = 8 if getattr(problem, "n_modal", 0) else 3
    best = None
    for k in candidates:
        effect = fr.effects[k]
        shape = int(effect.kind in SHAPES)
        n_k = sum(i == k for i, _ in free) + shape
        effects, free2, scales2 = _without(fr, free, scales, k)
        prior2 = {(i - (i > k), name): v for (i, name), v in prior.items() if i != k}
        try:
            fr2 = fit_model(problem, effects, free2, scales2, prior2, iterations=iterations,
                            n_shape=n_shape - shape)
        except MODEL_ERRORS as exc:
            log.info("backward step: model without %s failed: %s", effect.label, exc)
            continue
        dbic = (fr2.chi2 - fr.chi2) / infl - n_k * np.log(fr.n_obs)
        log.info("backward step: keeping %s gains dBIC %.1f", effect.label, dbic)
        if dbic < tol.delta_bic_accept and (best is None or dbic < best.dbic_keep):
            best = Dropped(k, effect.label, float(dbic), fr2, free2, scales2, n_shape - shape)
    return best
