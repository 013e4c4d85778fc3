"""The physical refit of a screened candidate with the current model: its visible
amplitudes free, its shape parameter (if any) optimised, and the covariance marginal over
that shape parameter."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..tolerances import tol
from .candidates import Screen, signature
from .fit import Problem, fit_model

__all__ = ["physical_refit", "shape_marginal"]


def physical_refit(problem: Problem, fr, free, scales, prior, best: Screen, n_shape: int = 0):
    """Physical refit of a candidate with the current model: amplitudes the data can see
    (whitened norm at typical size >= ``tol.untestable_norm``) are free, the others stay
    0; they start from zero, from the best amplitudes of the screen's nonlinear scan and,
    with vibration data, from the static data's own fit; the best of those fits wins; the
    shape parameter (if any) is optimised around its best grid value and counted
    in the degrees of freedom (with the ``n_shape`` of the current model).

    Returns the fit, its free parameters and scales, the amplitudes kept and the standard
    deviation of the shape parameter (NaN without one); the fit's covariance is then
    marginal over the shape parameter (:func:`shape_marginal`)."""
    from scipy.optimize import minimize_scalar

    c = best.candidate
    S = signature(problem, fr.effects, c, best.grid_value) * np.asarray(c.sizes)
    keep = [a for a, n in zip(c.amplitudes, np.linalg.norm(S, axis=0), strict=True)
            if n >= tol.untestable_norm] or list(c.amplitudes[:1])
    i = len(fr.effects)
    free2 = list(free) + [(i, a) for a in keep]
    scales2 = np.r_[scales, [s for a, s in zip(c.amplitudes, c.sizes, strict=True) if a in keep]]

    n_shape2 = n_shape + (c.grid_name is not None)

    starts = [np.zeros(len(c.amplitudes))]
    if best.start:  # the nonlinear scan's amplitudes too: the better of the two fits wins
        starts.append(np.asarray(best.start, float))

    # frequencies and mode pairings bend the chi-square: Gauss-Newton needs more steps
    steps = 8 if getattr(problem, "n_modal", 0) else 3

    def run(g, iterations=steps):
        fits = [fit_model(problem, list(fr.effects) + [c.effect(g, a)], free2, scales2, prior,
                          iterations=iterations, n_shape=n_shape2) for a in starts]
        static = getattr(problem, "static_problem", None)
        if static is not None:  # and from the static data's own fit of the candidate
            fs = fit_model(static, list(fr.effects) + [c.effect(g)], free2, scales2, prior)
            fits.append(fit_model(problem, fs.effects, free2, scales2, prior,
                                  iterations=iterations, n_shape=n_shape2))
        return min(fits, key=lambda f: f.chi2)

    g = best.grid_value
    if c.grid_name is not None:
        lo, hi = np.log(g / 10), np.log(g * 10)
        opt = minimize_scalar(lambda x: run(np.exp(x), 2).chi2, bounds=(lo, hi),
                              method="bounded", options={"xatol": 1e-3})
        g = float(np.exp(opt.x))
        fr2, g_sd = shape_marginal(problem, run(g), scales2, prior, c.grid_name)
        return fr2, free2, scales2, keep, g_sd
    return run(g), free2, scales2, keep, float("nan")


def shape_marginal(problem: Problem, fit, scales, prior, name: str):
    """``fit`` (whose last effect has the shape parameter ``name``, found by search) with
    the covariance of its free parameters marginal over that shape parameter, and the
    shape parameter's standard deviation.

    At a fixed shape the amplitude's interval is conditional and too narrow when the two
    trade off (a hardening threshold a little higher with a little more extra compliance
    fits almost as well): with it, the 99 % intervals of the hardening amplitude covered
    the truth on 17 of 20 seeds.  The shape's sensitivity column (finite difference)
    joins the linearised normal equations, with the same prior on the baseline."""
    eff = list(fit.effects)
    g = eff[-1].get(name)
    h = tol.fd_step * abs(g)
    f0 = problem.wpredict(eff)
    xg = (problem.wpredict(eff[:-1] + [eff[-1].with_params(**{name: g + h})]) - f0) / h
    X = np.column_stack([fit.sensitivity, xg])
    D = np.r_[scales, abs(g)]
    sd = np.array([prior.get(f, (0.0, np.inf))[1] for f in fit.free] + [np.inf])
    P = np.where(np.isfinite(sd), 1 / np.where(np.isfinite(sd), sd, 1) ** 2, 0.0)
    A = (X * D).T @ (X * D) + np.diag(P * D**2)
    cov = D[:, None] * np.linalg.pinv(A, rcond=1e-12) * D[None, :]
    return replace(fit, cov=cov[:-1, :-1]), float(np.sqrt(max(cov[-1, -1], 0.0)))
