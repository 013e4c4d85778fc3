"""Generalised least squares on static series with a shared reference reading.

Noise model (DESIGN §8).  A reading ``k`` of a series measures
``d_k = u_k - u_ref + e_k - e_ref`` with independent tracker noise ``e ~ N(0, sigma^2)``
per coordinate, so the rows of one series share ``-e_ref``: their covariance is
``sigma^2 (I + 1 1^T)``.  GLS with that covariance equals ordinary weighted least
squares with a free offset per series and coordinate, where the reference row enters as
an observation ``d_ref = 0``.  :meth:`Problem.whiten` implements this: it subtracts
the (1/sigma^2-weighted) series mean, reference row included, and divides by sigma.
Each series of ``m`` rows then carries ``3 (m - 1)`` degrees of freedom.  The
``"independent"`` model (rows treated as independent, no offset) exists only to show
why it invents effects (the shared-reference trap).

The degrees of freedom of a fit and the band its chi^2_red must fall in are those of
:mod:`~flexarm.validation.static.fit_result`.

Model parameters are the named parameters of :class:`~flexarm.robot.effects.Effect`
objects; the fit is Gauss-Newton with finite-difference sensitivities (exact in one step
for rigid links, where every compliance enters linearly) and a weak Gaussian prior on
the baseline compliance scale factors so that directions the data cannot see stay at
their nominal values.
"""

from __future__ import annotations

import functools

import numpy as np

from ...assembly.analyses import tcp_compliance
from ...assembly.effects import ADDED, added_deflection, apply_effects, measured
from ...assembly.linkflex import links_arm, split_links
from ...assembly.statics import distinct_poses, joint_moments, series_starts
from ...assembly.system import ArmModel
from ...fe.errors import FlexarmError
from ...robot.effects import Effect, lower_bound
from ...robot.kinematics import jacobian
from ..data.measurements import StaticData
from ..tolerances import tol
from .fit_result import FitResult, chi2_band

# the result and its chi^2 band are part of this module's interface too (callers import
# them here)
__all__ = ["Problem", "FitResult", "FitError", "fit_model", "try_wpredict", "baseline_effects",
           "chi2_band"]

Param = tuple[int, str]  # (effect index, parameter name)
#: Readings per block of the per-reading work.
_ROWS = 1 << 16


class Problem:
    """One static data set and the arm model it is compared with (caches the kinematics).

    Parameters
    ----------
    arm : ArmModel
    data : StaticData
    sigma : float
        Tracker standard uncertainty [m] used when the file has no ``sigma`` column.
    noise_model : {"shared", "independent"}
    flexible : ArmModel, optional
        The flexible model of the same robot, for the ``links`` effect
        (:mod:`~flexarm.assembly.linkflex`).
    discount : (n,) bool, optional
        Readings left out of the fit (outliers): their uncertainty is multiplied by
        ``tol.discount_factor`` and they no longer count as observations.
    """

    def __init__(self, arm: ArmModel, data: StaticData, sigma: float = tol.tracker_sigma,
                 noise_model: str = "shared", flexible: ArmModel | None = None,
                 discount: np.ndarray | None = None):
        if noise_model not in ("shared", "independent"):
            raise ValueError(f"noise_model must be 'shared' or 'independent', got {noise_model}")
        self.arm, self.data, self.noise_model = arm, data, noise_model
        self.flexible = flexible
        n = len(data.series)
        self.ref = series_starts(data.series)
        self.is_ref = self.ref == np.arange(n)
        self.sigma = np.full(n, sigma) if data.sigma is None else np.asarray(data.sigma, float)
        self.discounted = np.zeros(n, bool)
        if discount is not None:
            self.discount(discount)
        # kinematics once per distinct pose, loads per reading, a block of rows at a time:
        # a million readings stay a few hundred MB
        self.uq, self.pose_index = distinct_poses(data.q)
        self.dw = np.zeros((n, 6))
        self.dw[:, :3] = data.force
        if data.moment is not None:
            self.dw[:, 3:] = data.moment
        self.dw -= self.dw[self.ref]
        self.tau = np.zeros((n, arm.chain.n_joints))
        for a in range(0, n, _ROWS):
            rows = slice(a, a + _ROWS)
            moment = None if data.moment is None else data.moment[rows]
            self.tau[rows] = joint_moments(arm, self.uq, data.force[rows], moment,
                                           pose_index=self.pose_index[rows])[:, :, 0]
        self.dtau = self.tau - self.tau[self.ref]
        new = np.r_[True, self.ref[1:] != self.ref[:-1]][:n]  # series are runs of rows
        self.groups = np.split(np.arange(n), np.flatnonzero(new)[1:]) if n else []
        self.series_id = np.cumsum(new) - 1
        self.y = np.asarray(data.disp, float)

    @functools.cached_property
    def J(self) -> np.ndarray:
        """(n, 3, n_joints) TCP translation per joint rotation [m/rad] of each reading."""
        return jacobian(self.arm.chain, self.uq)[self.pose_index, :3, :]

    def discount(self, rows) -> None:
        """Leave the readings ``rows`` (bool mask or indices) out of every fit from now on
        (robust handling of outliers): their sigma grows by ``tol.discount_factor``."""
        mask = np.zeros(len(self.sigma), bool)
        mask[np.asarray(rows)] = True
        new = mask & ~self.discounted
        self.sigma = np.where(new, self.sigma * tol.discount_factor, self.sigma)
        self.discounted = self.discounted | mask

    @property
    def n_obs_static(self) -> int:
        """Independent observations: 3 per non-reference reading, less 3 per discounted one."""
        return 3 * int((~self.is_ref).sum() - self.discounted.sum())

    @property
    def n_obs(self) -> int:
        """Independent observations (:attr:`n_obs_static`; subclasses add their own)."""
        return self.n_obs_static

    # ----- model predictions
    def law_signature(self, joint: int, shape) -> np.ndarray:
        """(n, 3) TCP motion [m] of a unit-amplitude law ``shape(tau history)`` at ``joint``."""
        extra = np.zeros(len(self.ref))
        for g in self.groups:
            extra[g] = shape(self.tau[g, joint])
        extra = extra - extra[self.ref]
        return self.J[:, :, joint] * extra[:, None]

    def model(self, effects):
        """The arm with ``effects`` (links first) and its nonlinear laws per joint."""
        c, rest = split_links(effects)
        return apply_effects(links_arm(self.arm, self.flexible, c), rest)

    def predict(self, effects) -> np.ndarray:
        """(n, 3) relative TCP deflections [m] of the arm with ``effects``."""
        arm, laws = self.model(effects)
        C = tcp_compliance(arm, self.uq)[:, :3, :]
        u = np.zeros((len(self.dw), 3))
        for a in range(0, len(u), _ROWS):
            rows = slice(a, a + _ROWS)
            u[rows] = np.einsum("nij,nj->ni", C[self.pose_index[rows]], self.dw[rows])
        for j, js in laws.items():
            for law in js:
                u += self.law_signature(j, law.deflection)
        if any(e.kind in ADDED for e in effects):
            u = u + added_deflection(arm, effects, self.data.q, self.dw[:, :3], self.dtau)
        return measured(effects, u)

    # ----- noise model
    def whiten(self, A: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
        """Whitened residual-like array: (n, 3[, p]) -> (m[, p]), GLS metric of the noise model.

        ``rows`` (bool (n,)) keeps whole series only.
        """
        A = np.asarray(A, dtype=float)
        w = 1.0 / self.sigma**2
        wb = w.reshape((-1,) + (1,) * (A.ndim - 1))
        if self.noise_model == "shared":
            num = np.zeros((len(self.groups),) + A.shape[1:])
            np.add.at(num, self.series_id, wb * A)
            den = np.bincount(self.series_id, weights=w)
            mean = num / den.reshape((-1,) + (1,) * (A.ndim - 1))
            Z = (A - mean[self.series_id]) / self.sigma.reshape(wb.shape)
            keep = np.ones(len(A), bool)
        else:
            Z = A / self.sigma.reshape(wb.shape)
            keep = ~self.is_ref
        if rows is not None:
            keep = keep & rows
        Z = Z[keep]
        return Z.reshape((-1,) + A.shape[2:])

    def wpredict(self, effects, rows: np.ndarray | None = None) -> np.ndarray:
        """(m,) whitened predictions of every observation (``whiten(predict)``)."""
        return self.whiten(self.predict(effects), rows)

    def wy(self, rows: np.ndarray | None = None) -> np.ndarray:
        """(m,) whitened measurements, the counterpart of :meth:`wpredict`."""
        return self.whiten(self.y, rows)

    def n_obs_rows(self, rows: np.ndarray | None = None) -> int:
        keep = np.ones(len(self.is_ref), bool) if rows is None else rows
        return 3 * int((~self.is_ref & keep).sum() - (self.discounted & keep).sum())

    def penalty(self, effects) -> tuple[float, int]:
        """(chi-square, observations) that the model with ``effects`` pays at a fixed cost
        and chi^2_red leaves out: none for static data (measured modes without a model
        partner: :meth:`~flexarm.validation.dynamic.modal.ModalProblem.penalty`)."""
        return 0.0, 0


def baseline_effects(arm: ArmModel) -> tuple[list[Effect], list[Param]]:
    """Torsion compliance scale per joint (nominal 1): the linear baseline."""
    eff = [Effect("stiffness", j, (("scale", 1.0),)) for j in range(arm.chain.n_joints)]
    return eff, [(j, "scale") for j in range(len(eff))]


def _set(effects, free, theta):
    out = list(effects)
    for (i, name), v in zip(free, theta, strict=True):
        out[i] = out[i].with_params(**{name: float(v)})
    return out


class FitError(FlexarmError, ValueError):
    """A model a fit needs cannot be evaluated (its starting parameters give no finite
    prediction); the reason is the message."""


#: What evaluating a model with trial parameters may raise when they leave the domain in
#: which it is valid (a non-positive-definite stiffness, a negative factor).
MODEL_ERRORS = (ValueError, ArithmeticError, np.linalg.LinAlgError, FlexarmError)


def try_wpredict(problem: Problem, effects, rows=None) -> tuple[np.ndarray | None, str]:
    """``(problem.wpredict(effects, rows), "")``, or ``(None, reason)`` when the model with
    these effects cannot be evaluated or predicts a non-finite value."""
    try:
        # an amplitude far out may overflow on the way; the result is checked below
        with np.errstate(all="ignore"):
            f = problem.wpredict(effects, rows)
    except MODEL_ERRORS as exc:
        return None, f"{type(exc).__name__}: {exc}".strip()
    if not np.all(np.isfinite(f)):
        return None, "the model predicts a non-finite value"
    return f, ""


def _inside(theta: np.ndarray, step: np.ndarray, lower: np.ndarray) -> np.ndarray:
    """``step`` cut per parameter so that ``theta + step`` stays above ``lower``: at most
    95 % of the way to the bound (the fraction-to-boundary rule of interior-point
    methods), so a compliance never reaches zero or below."""
    room = theta - lower
    return np.where(step < -0.95 * room, -0.95 * room, step)


def fit_model(problem: Problem, effects, free, scales, prior=None, rows=None,
              iterations: int = 3, n_shape: int = 0) -> FitResult:
    """Gauss-Newton GLS fit of the ``free`` parameters of ``effects``.

    Each step stays inside the parameters' domain (:func:`~flexarm.robot.effects.lower_bound`:
    compliances stay positive) and is halved until the penalised chi-square falls; a trial
    model that cannot be evaluated counts as a rise.  A sensitivity that the forward
    difference cannot evaluate is taken backward.

    Parameters
    ----------
    problem : Problem
    effects : sequence of Effect
    free : sequence of (effect index, parameter name)
    scales : (p,) float
        Typical size of each free parameter (finite-difference step and conditioning).
    prior : mapping (effect index, name) -> (mean, sd), optional
        Gaussian prior (used for the baseline scale factors).
    rows : (n,) bool, optional
        Fit on these series only (held-out validation).
    n_shape : int
        Shape parameters of ``effects`` that were chosen by a search on the same data
        (they stay fixed here but use up degrees of freedom).

    Raises
    ------
    FitError
        The model cannot be evaluated at the starting parameters.
    """
    effects, free = list(effects), list(free)
    scales = np.asarray(scales, dtype=float)
    theta = np.array([effects[i].get(name) for i, name in free])
    lower = np.array([lower_bound(effects[i].kind, name) for i, name in free])
    theta = np.maximum(theta, lower + np.where(np.isfinite(lower), 1e-6 * scales, 0.0))
    prior = prior or {}
    mu = np.array([prior.get(f, (0.0, np.inf))[0] for f in free])
    sd = np.array([prior.get(f, (0.0, np.inf))[1] for f in free])
    P = np.where(np.isfinite(sd), 1 / np.where(np.isfinite(sd), sd, 1) ** 2, 0.0)
    D = scales
    wy = problem.wy(rows)
    f0, why = try_wpredict(problem, _set(effects, free, theta), rows)
    if f0 is None:
        raise FitError(f"the model cannot be evaluated at its starting parameters ({why})")

    def objective(f, th):
        r = wy - f
        return float(r @ r + np.sum(P * (th - mu) ** 2))

    J0 = objective(f0, theta)
    X = np.zeros(f0.shape + (len(free),))
    for _ in range(iterations):
        cols = []
        for k in range(len(free)):
            h = tol.fd_step * max(scales[k], abs(theta[k]))
            for sign in (1.0, -1.0):
                t = theta.copy()
                t[k] += sign * h
                f1, _ = try_wpredict(problem, _set(effects, free, t), rows)
                if f1 is not None:
                    cols.append(sign * (f1 - f0) / h)
                    break
            else:
                cols.append(np.zeros_like(f0))
        X = np.stack(cols, axis=-1) if cols else np.zeros(f0.shape + (0,))
        # normal equations in scaled variables, with the prior
        A = (X * D).T @ (X * D) + np.diag(P * D**2)
        b = (X * D).T @ (wy - f0) - P * D * (theta - mu)
        step = _inside(theta, D * np.linalg.lstsq(A, b, rcond=1e-12)[0], lower)
        for _halving in range(8):
            f1, _ = try_wpredict(problem, _set(effects, free, theta + step), rows)
            J1 = objective(f1, theta + step) if f1 is not None else np.inf
            if J1 <= J0 + 1e-9 * max(J0, 1.0):
                break
            step = step / 2
        else:
            break
        theta, f0, J0 = theta + step, f1, J1
        if np.all(np.abs(step) <= 1e-6 * np.maximum(np.abs(theta), scales)):
            break
    final = _set(effects, free, theta)
    res = wy - f0
    A = (X * D).T @ (X * D) + np.diag(P * D**2)
    Ainv = np.linalg.pinv(A, rcond=1e-12)
    cov = D[:, None] * Ainv * D[None, :]
    G = Ainv @ ((X * D).T @ (X * D))  # tr(G) = tr(H), tr(G G) = tr(H^2)
    n_fit = float(2 * np.trace(G) - np.trace(G @ G))
    penalty, n_penalised = problem.penalty(final)
    return FitResult(tuple(final), tuple(free), theta, cov, float(res @ res),
                     problem.n_obs_rows(rows), n_fit, res, X, int(n_shape), penalty,
                     n_penalised)


def with_effect(effects, free, scales, prior, effect: Effect, names, sizes):
    """Append ``effect`` with free parameters ``names`` (typical ``sizes``)."""
    effects = list(effects) + [effect]
    i = len(effects) - 1
    return (effects, list(free) + [(i, n) for n in names],
            np.r_[scales, sizes], dict(prior))


__all__ += ["with_effect"]
