"""Expected ΔBIC of candidate series between fitted hypotheses, and greedy selection.

For truth ``a`` and rival ``b`` every candidate series ``c`` contributes, in the whitened
GLS metric of :class:`~flexarm.validation.static.fit.Problem`, the Gram matrix ``S_b^T S_b`` of
``b``'s (scaled) sensitivities, ``S_b^T d_ab`` and ``|d_ab|^2`` with
``d_ab = W (p_a - p_b)``; over a set of series the expected excess chi-square of the
refitted rival is ``|d|^2 - h^T (G + prior)^-1 h`` (sums over the set).  Whitening is
per series (shared reference), so these terms add over series exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...assembly.system import ArmModel
from ..data.measurements import StaticData
from ..static.fit import Problem
from ..tolerances import tol

__all__ = ["PairTerms", "pair_terms", "greedy", "expected_dbic"]


@dataclass(frozen=True, eq=False)
class PairTerms:
    """Per-candidate terms: ``gram[b]`` (c, p_b, p_b), ``cross[a][b]`` (c, p_b),
    ``dd`` (h, h, c), ``prior[b]`` (p_b,) precision in scaled units, ``k`` free
    parameters per hypothesis, ``n_obs`` observations per series."""

    gram: tuple
    cross: tuple
    dd: np.ndarray
    prior: tuple
    k: np.ndarray
    n_obs: int


def _candidate_data(poses, dirs, loads, cycles) -> StaticData:
    levels = np.r_[loads, loads[-2::-1]] if cycles else np.asarray(loads)
    m = len(levels)
    vec = np.array([v for _, v in dirs], float)
    n_c = len(poses) * len(vec)
    series = np.repeat([f"C{c}" for c in range(n_c)], m)
    q = np.repeat(np.repeat(poses, len(vec), axis=0), m, axis=0)
    force = (np.tile(vec, (len(poses), 1))[:, None, :] * levels[None, :, None]).reshape(-1, 3)
    return StaticData(series=list(series), steps=np.tile(np.arange(m), n_c), q=q, force=force,
                      disp=np.zeros_like(force), sigma=None)


def _sensitivity(problem: Problem, hyp) -> np.ndarray:
    """(m, p) whitened sensitivities of ``hyp``'s free parameters, per typical size."""
    effects = list(hyp.effects)
    f0 = problem.predict(effects)
    cols = []
    for (i, name), s in zip(hyp.free, hyp.scales, strict=True):
        v = effects[i].get(name)
        h = tol.fd_step * max(s, abs(v))
        e = list(effects)
        e[i] = e[i].with_params(**{name: v + h})
        cols.append(problem.whiten((problem.predict(e) - f0) / h * s))
    return np.stack(cols, axis=-1)


def pair_terms(arm: ArmModel, hyps, poses, dirs, loads, cycles, sigma) -> PairTerms:
    """Terms of every candidate series (pose-major, then ``dirs``) for :func:`greedy`."""
    data = _candidate_data(poses, dirs, loads, cycles)
    problem = Problem(arm, data, sigma)
    n_c = len(poses) * len(dirs)
    rows = len(data.series) // n_c * 3
    pred = [problem.whiten(problem.predict(list(h.effects))).reshape(n_c, rows) for h in hyps]
    sens = [_sensitivity(problem, h).reshape(n_c, rows, -1) for h in hyps]
    gram = tuple(np.einsum("crp,crs->cps", S, S) for S in sens)
    cross = tuple(tuple(np.einsum("crp,cr->cp", sens[b], pred[a] - pred[b]) for b in
                        range(len(hyps))) for a in range(len(hyps)))
    dd = np.array([[((pred[a] - pred[b]) ** 2).sum(axis=1) for b in range(len(hyps))]
                   for a in range(len(hyps))])
    prior = []
    for h in hyps:
        pr = dict(h.prior)
        prior.append(np.array([(s / pr[f][1]) ** 2 if f in pr else 0.0
                               for f, s in zip(h.free, h.scales, strict=True)]))
    return PairTerms(gram, cross, dd, tuple(prior), np.array([len(h.free) for h in hyps]),
                     rows - 3)


def _lambda(terms: PairTerms, G, h, dd, n_series: int) -> np.ndarray:
    """(h, h, c) expected ΔBIC with each candidate added to the current sums."""
    nh = len(terms.k)
    out = np.zeros((nh, nh) + dd.shape[2:])
    pen = np.log(max(terms.n_obs * n_series, 1))
    for a in range(nh):
        for b in range(nh):
            if a == b:
                continue
            A = G[b] + np.diag(terms.prior[b])
            x = np.linalg.solve(A + 1e-12 * np.eye(A.shape[-1]) * np.trace(A, axis1=-2,
                                axis2=-1)[..., None, None] / A.shape[-1], h[a][b][..., None])
            out[a, b] = dd[a, b] - (h[a][b] * x[..., 0]).sum(-1) + (terms.k[b] - terms.k[a]) * pen
    return out


def greedy(terms: PairTerms, n_series: int):
    """Indices of the chosen candidates, the smallest pair ΔBIC after each, and the final
    (h, h) expected ΔBIC matrix."""
    nh = len(terms.k)
    G = [np.zeros(g.shape[1:]) for g in terms.gram]
    h = [[np.zeros(terms.cross[a][b].shape[1:]) for b in range(nh)] for a in range(nh)]
    dd = np.zeros((nh, nh))
    off = ~np.eye(nh, dtype=bool)
    chosen, steps, lam = [], [], np.zeros((nh, nh))
    for k in range(n_series):
        Gc = [G[b] + terms.gram[b] for b in range(nh)]
        hc = [[h[a][b] + terms.cross[a][b] for b in range(nh)] for a in range(nh)]
        lam_c = _lambda(terms, Gc, hc, dd[:, :, None] + terms.dd, k + 1)
        worst = lam_c[off].min(axis=0)
        score = worst + 1e-6 * lam_c[off].sum(axis=0)
        c = int(np.argmax(score))
        chosen.append(c)
        steps.append(float(worst[c]))
        G = [G[b] + terms.gram[b][c] for b in range(nh)]
        h = [[h[a][b] + terms.cross[a][b][c] for b in range(nh)] for a in range(nh)]
        dd = dd + terms.dd[:, :, c]
        lam = lam_c[:, :, c]
    return chosen, steps, lam


def expected_dbic(terms: PairTerms, chosen) -> np.ndarray:
    """(h, h) expected ΔBIC (row: truth, column: rival) of the candidates ``chosen``
    (indices, repeats allowed) measured together."""
    idx = np.asarray(chosen, int)
    nh = len(terms.k)
    G = [terms.gram[b][idx].sum(axis=0) for b in range(nh)]
    h = [[terms.cross[a][b][idx].sum(axis=0) for b in range(nh)] for a in range(nh)]
    return _lambda(terms, G, h, terms.dd[:, :, idx].sum(axis=-1), len(idx))
