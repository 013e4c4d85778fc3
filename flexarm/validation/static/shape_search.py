"""Search the shape parameters (hardening thresholds, hysteresis radii) of a fitted
model again, with every amplitude free.

The diagnosis adds effects one at a time and finds each new shape parameter with the
model of that moment.  A shape found before a second effect on the same joint joined is
biased (a hardening threshold absorbs part of a backlash step): after each acceptance,
and when a candidate joins a joint that already has a shaped effect, every shape is
searched again (cyclic coordinate search on a log scale, each step a bounded 1-D
minimisation of the GLS chi-square with all amplitudes refitted).
"""

from __future__ import annotations

import numpy as np

from .fit import FitResult, fit_model

__all__ = ["SHAPES", "shaped", "research_shapes"]

#: Effect kind -> its shape parameter.
SHAPES = {"hardening": "threshold", "hysteresis": "radius"}


def shaped(effects, first: int = 0, joint: int | None = None) -> list[int]:
    """Indices (from ``first`` on) of the effects with a shape parameter (on ``joint``)."""
    return [i for i, e in enumerate(effects) if i >= first and e.kind in SHAPES
            and (joint is None or e.joint == joint)]


def research_shapes(problem, effects, free, scales, prior, n_shape: int, indices,
                    passes: int = 2, span: float = 3.0) -> FitResult:
    """Fit of ``effects`` after searching the shape parameters of ``indices`` again.

    Each shape moves within ``[g / span, g * span]`` of its current value ``g``; the
    amplitudes (``free``) are refitted at every trial.  Returns the final fit (its
    ``n_shape`` unchanged: the same shape parameters are counted).
    """
    from scipy.optimize import minimize_scalar

    effects = list(effects)
    fit = fit_model(problem, effects, free, scales, prior, n_shape=n_shape)
    if not indices:
        return fit
    for _ in range(passes):
        before = fit.chi2
        for i in indices:
            name = SHAPES[effects[i].kind]
            g0 = effects[i].get(name)
            base = list(fit.effects)

            def chi2(x, i=i, name=name, base=base):
                trial = list(base)
                trial[i] = trial[i].with_params(**{name: float(np.exp(x))})
                return fit_model(problem, trial, free, scales, prior, iterations=2).chi2

            opt = minimize_scalar(chi2, bounds=(np.log(g0 / span), np.log(g0 * span)),
                                  method="bounded", options={"xatol": 1e-3})
            if opt.fun < fit.chi2:
                trial = list(base)
                trial[i] = trial[i].with_params(**{name: float(np.exp(opt.x))})
                fit = fit_model(problem, trial, free, scales, prior, n_shape=n_shape)
            effects = list(fit.effects)
        if before - fit.chi2 < 0.1:
            break
    return fit
