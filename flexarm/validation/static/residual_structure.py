"""What is left in the residual of a fitted model: tests for structure, each with a
stated false-alarm rate, and the noise scale.

The residual ``y - predict(effects)`` is whitened in the GLS metric of the noise model
(:meth:`~flexarm.validation.static.fit.Problem.whiten`).  Each test regresses it on a few
columns that a missing effect outside the candidate library would leave, projected off
the fitted model's own sensitivities, and compares the gain with the rest of the
residual (an F test: a noise level larger than stated does not set it off).  Tests over
a family (every joint, every series) take the smallest p-value times the family size
(Bonferroni), so each test as a whole has the false-alarm rate ``alpha``:

* ``offsets``: the readings of one series share an offset against its reference
  reading (the reference was off; the tracker re-locked);
* ``outliers``: isolated readings far out, from robust standardised residuals (scale by
  the median absolute deviation), named by series and step;
* ``frame``: a small rotation or scale of the measurement frame (``r x u`` and ``u`` of
  the model's deflections);
* ``drift``: the tracker drifts in reading order (linear in the reading index);
* ``tool``: a residual linear in the load with a pose-independent direction in the tool
  frame (``R E R^T dF`` for the six symmetric unit matrices ``E``);
* ``joint_angle``: a joint's compliance changing with its angle across series;
* ``joint_law``: a joint's deflection nonlinear in its torque (smooth odd and even
  terms ``tau |tau|`` and ``tau^3``).

Readings flagged as outliers are left out of the other tests.  ``noise_scale`` is the
residual's RMS per degree of freedom (outliers left out) relative to the stated sigma.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..tolerances import tol
from .structure_regressors import STRUCTURES, StructureTest, structure_tests, unit_columns

__all__ = ["StructureTest", "ResidualStructure", "residual_structure", "STRUCTURES"]

@dataclass(frozen=True)
class ResidualStructure:
    """All residual-structure tests of one fitted model and the noise scale.

    Attributes
    ----------
    tests : tuple of StructureTest
        In :data:`STRUCTURES` order.
    noise_scale : float
        Residual RMS per degree of freedom over the stated sigma, outliers left out [-].
    outliers : tuple of (str, int, float)
        Flagged readings: series, step, robust standardised size (in noise sigmas).
    outlier_rows : tuple of int
        Their row indices in the data.
    dof : float
        Degrees of freedom of the residual the F tests use.
    """

    tests: tuple
    noise_scale: float
    outliers: tuple = ()
    outlier_rows: tuple = ()
    dof: float = 0.0

    @property
    def found(self) -> tuple:
        """The tests that found structure, smallest p-value first."""
        return tuple(sorted((t for t in self.tests if t.found), key=lambda t: t.p_value))

    def test(self, name: str) -> StructureTest:
        return next(t for t in self.tests if t.name == name)


def _entry_rows(problem) -> np.ndarray:
    """Row index of each entry of a whitened (n, 3) array."""
    n = len(problem.is_ref)
    keep = np.ones(n, bool) if problem.noise_model == "shared" else ~problem.is_ref
    return np.repeat(np.flatnonzero(keep), 3)


def _project_off(Q: np.ndarray, A: np.ndarray) -> np.ndarray:
    return A - Q @ (Q.T @ A) if Q.shape[1] else A


def _basis(X: np.ndarray) -> np.ndarray:
    if X.size == 0:
        return np.zeros((X.shape[0], 0))
    U, sv, _ = np.linalg.svd(X, full_matrices=False)
    return U[:, sv > sv.max() * 1e-8] if sv.max() > 0 else np.zeros((X.shape[0], 0))


class _Residual:
    """The whitened residual with its regressor machinery (outlier rows masked)."""

    def __init__(self, problem, effects, sensitivity: np.ndarray, n_fit: float):
        self.problem = problem
        self.u = problem.predict(effects)
        raw = problem.y - self.u
        self.r_all = problem.whiten(raw)
        m = len(self.r_all)
        self.rows = _entry_rows(problem)
        self.X = sensitivity[:m]
        self.n_fit = n_fit
        self.mask = np.ones(m, bool)
        self.extra: list = []  # raw regressors of the structures already found

    def masked(self, rows: np.ndarray) -> None:
        self.mask = ~np.isin(self.rows, rows)

    def dof(self, n_out: int) -> float:
        k = sum(A.shape[-1] for A in self.extra)
        return max(self.problem.n_obs_static - self.n_fit - 3 * n_out - k, 1.0)

    def columns(self, A: np.ndarray) -> np.ndarray:
        """Whitened raw (n, 3, k) regressors, masked and projected off the model."""
        W = self.problem.whiten(A)[self.mask]
        return _project_off(self.Q, W)

    def prepare(self) -> None:
        """Basis of the model and the structures found so far, and the residual off it."""
        X = self.X[self.mask]
        if self.extra:
            X = np.column_stack([X] + [self.problem.whiten(A)[self.mask] for A in self.extra])
        self.Q = _basis(X)
        self.r = _project_off(self.Q, self.r_all[self.mask])


def _outliers(res: _Residual, alpha: float, r: np.ndarray, n_fit: float):
    """Flagged rows, their robust standardised sizes [sigma] and the first test's p-value.

    Sequential: the reading with the largest robust size (its 3 coordinates over the
    median absolute deviation, chi^2(3), Bonferroni over the readings) is flagged when
    below ``alpha``, then fitted out (a free offset of that reading, which also removes
    its share of its series' reference) before the next is tested, so an outlier does not
    drag its series' other readings along.
    """
    from ..distributions import chi2_sf

    p = res.problem
    rows = res.rows[::3]
    cand = ~p.is_ref[rows] & ~p.discounted[rows]
    n = max(int(cand.sum()), 1)
    Q = _basis(res.X)
    flagged, sizes, p_first = [], [], None
    for _ in range(max(int(tol.max_outlier_share * n), 1)):
        keep = ~np.isin(res.rows, rows[flagged])
        med = np.median(r[keep])
        s = max(1.4826 * float(np.median(np.abs(r[keep] - med))), 1e-12)
        d2 = ((r / s).reshape(-1, 3) ** 2).sum(axis=1)
        d2[~cand] = 0.0
        k = int(np.argmax(d2))
        pv = min(1.0, n * float(chi2_sf(d2[k], 3)))
        p_first = pv if p_first is None else p_first
        if pv >= alpha:
            break
        flagged.append(k)
        sizes.append(float(np.sqrt(d2[k])))
        cand[k] = False
        G = _project_off(Q, p.whiten(unit_columns(len(p.is_ref), rows[[k]])))
        r = _project_off(_basis(G), r)
    return rows[flagged], np.array(sizes), 1.0 if p_first is None else p_first


def residual_structure(problem, effects, sensitivity: np.ndarray, n_fit: float,
                       alpha: float = tol.structure_alpha) -> ResidualStructure:
    """Residual-structure tests of the model ``effects`` fitted to ``problem``.

    Parameters
    ----------
    problem : Problem
        The data and the arm (:class:`~flexarm.validation.static.fit.Problem`).
    effects : sequence of Effect
        The fitted model.
    sensitivity : (m, p) float
        Its whitened sensitivities (``FitResult.sensitivity``; static rows first).
    n_fit : float
        Its effective number of fitted parameters (``FitResult.n_identified`` plus the
        shape parameters).
    alpha : float
        False-alarm rate of each test.

    Returns
    -------
    ResidualStructure
    """
    res = _Residual(problem, effects, sensitivity, n_fit)
    out_rows, _, _ = _outliers(res, alpha, res.r_all, n_fit)
    res.masked(out_rows)
    res.prepare()
    found = [A for t, A in structure_tests(res, res.dof(len(out_rows)), alpha)
             if t.found and A is not None]
    # structure inflates the tails: judge outliers on the residual without it
    r, k = _cleaned(res, found)
    out_rows, out_z, p_out = _outliers(res, alpha, r, n_fit + k)
    res.masked(out_rows)
    res.prepare()
    dof = res.dof(len(out_rows))
    series = np.asarray(problem.data.series)
    steps = np.asarray(problem.data.steps)
    outliers = tuple((str(series[i]), int(steps[i]), float(z))
                     for i, z in sorted(zip(out_rows, out_z, strict=True), key=lambda t: -t[1]))
    where = ", ".join(f"{s} step {k}" for s, k, _ in outliers[:4])
    where += " ..." if len(outliers) > 4 else ""
    tests = _forward(res, out_rows, alpha)
    tests.insert(1, StructureTest("outliers", p_out, alpha, where,
                                  f"{len(outliers)} reading(s)" if outliers else ""))
    rss = float(res.r @ res.r)
    return ResidualStructure(tuple(tests), float(np.sqrt(rss / dof)), outliers,
                             tuple(int(i) for i in out_rows), dof)


def _forward(res: _Residual, out_rows, alpha: float) -> list:
    """The F tests by forward selection: the most significant structure joins the model
    and the others are tested again against what is left (so a structure that only
    correlates with a stronger one is not reported)."""
    final: dict = {}
    for _ in range(len(STRUCTURES)):
        run = structure_tests(res, res.dof(len(out_rows)), alpha)
        new = [(t, A) for t, A in run if t.name not in final]
        best = min(new, key=lambda x: x[0].p_value, default=None)
        if best is None or not best[0].found or best[1] is None:
            final.update({t.name: t for t, _ in new})
            break
        final[best[0].name] = best[0]
        res.extra.append(best[1])
        res.prepare()
    return [final[k] for k in STRUCTURES if k in final]


def _cleaned(res: _Residual, found: list) -> tuple[np.ndarray, int]:
    """The whole whitened residual with the ``found`` structures (raw regressors) fitted
    out, and the number of columns removed."""
    if not found:
        return res.r_all, 0
    Q = _basis(res.X)
    G = _project_off(Q, np.column_stack([res.problem.whiten(A) for A in found]))
    coef, *_ = np.linalg.lstsq(G, res.r_all, rcond=1e-10)
    return res.r_all - G @ coef, G.shape[1]
