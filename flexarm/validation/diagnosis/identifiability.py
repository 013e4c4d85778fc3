"""How well static data determine the baseline of a diagnosis: the SVD of the whitened
sensitivities with the unidentifiable parameter combinations named, the series in which
each joint's torque changes sign, and leave-one-pose-out cross-validation."""

from __future__ import annotations

import numpy as np

from ..static.fit import FitResult, Problem, fit_model
from .results import Identifiability

__all__ = ["identifiability", "leave_one_pose_out", "weak_directions"]


def identifiability(problem: Problem, fit: FitResult) -> Identifiability:
    """SVD of the whitened baseline sensitivities, correlations, torque sign changes and
    the parameter combinations the data cannot determine, in words
    (``leave_one_pose_out`` left empty: :func:`leave_one_pose_out`)."""
    X = fit.sensitivity
    sv = np.linalg.svd(X, compute_uv=False) if X.size else np.zeros(0)
    sd = fit.stderr
    corr = fit.cov / np.outer(np.maximum(sd, 1e-300), np.maximum(sd, 1e-300))
    flips = []
    for j in range(problem.arm.chain.n_joints):
        series = [str(problem.data.series[g[0]]) for g in problem.groups
                  if np.any(np.diff(np.sign(problem.tau[g, j])) != 0)]
        flips.append(tuple(series))
    names = [f"{fit.effects[i].label.replace('stiffness', 'torsion')}"
             + ("" if name == "scale" else f" {name}") for i, name in fit.free]
    return Identifiability(
        singular_values=tuple(sv.tolist()),
        condition=float(sv.max() / max(sv.min(), 1e-300)) if sv.size else float("nan"),
        correlation=tuple(map(tuple, corr.tolist())), stderr=tuple(sd.tolist()),
        sign_changes={f"joint_{j + 1}": s for j, s in enumerate(flips)},
        weak=weak_directions(X, names))


def leave_one_pose_out(problem: Problem, effects, free, scales, prior) -> dict:
    """chi^2_red on each pose when the model is fitted on the other poses."""
    out = {}
    poses = problem.pose_index
    if problem.uq.shape[0] < 3:
        return out
    for p in range(problem.uq.shape[0]):
        test = poses == p
        fr = fit_model(problem, effects, free, scales, prior, rows=~test, iterations=2)
        r = problem.whiten(problem.y - problem.predict(fr.effects), test)
        label = str(problem.data.series[np.flatnonzero(test)[0]]).split("_")[0]
        out[label] = float(r @ r / max(r.size, 1))
    return out


def weak_directions(X: np.ndarray, names, rel: float = 1e-8, corr: float = 0.95) -> tuple:
    """The parameter combinations the whitened sensitivities ``X`` (n_obs, n) cannot
    determine, in words: each right singular vector with a singular value below ``rel``
    times the largest names the parameters it involves (``names``), and each pair whose
    sensitivity columns are more than ``corr`` alike (cosine) is named as moving the
    TCP alike.

    Examples
    --------
    >>> X = np.array([[1.0, 2.0, 0.0], [0.0, 0.0, 0.0], [3.0, 6.0, 1.0]])
    >>> weak_directions(X, ["joint 1 torsion", "joint 2 torsion", "joint 3 torsion"])
    ('joint 1 torsion and joint 2 torsion move the TCP alike: only their combination is \
identifiable',)
    >>> weak_directions(np.array([[1.0, 0.0], [2.0, 0.0]]), ["joint 1 torsion",
    ...                 "joint 6 torsion"])
    ('joint 6 torsion moves the TCP in no measured direction: unidentifiable',)
    """
    X = np.asarray(X, dtype=float)
    if X.size == 0:
        return ()
    norms = np.linalg.norm(X, axis=0)
    ok = norms > rel * norms.max()
    # a parameter that moves nothing first: inside the SVD its null vector could mix
    # with another null direction
    out = [f"{names[i]} moves the TCP in no measured direction: unidentifiable"
           for i in np.flatnonzero(~ok)]
    idx = np.flatnonzero(ok)
    _, s, vt = np.linalg.svd(X[:, ok] / norms[ok], full_matrices=False)
    for sv, v in zip(s, vt, strict=True):
        if sv > rel * s[0]:
            continue
        w = np.abs(v) / np.abs(v).max()
        who = [names[idx[i]] for i in range(len(w)) if w[i] > 0.2]
        out.append(f"{' and '.join(who)} move the TCP alike: only their combination is "
                   "identifiable")
    cos = (X[:, ok] / norms[ok]).T @ (X[:, ok] / norms[ok])
    said = " ".join(out)
    for a, b in zip(*np.triu_indices(len(idx), 1), strict=True):
        if abs(cos[a, b]) > corr and not (names[idx[a]] in said and names[idx[b]] in said):
            out.append(f"{names[idx[a]]} and {names[idx[b]]} move the TCP alike "
                       f"(correlation {abs(cos[a, b]):.2f})")
    return tuple(out)
