"""How well static data determine the baseline of a diagnosis: the SVD of the whitened
sensitivities with the unidentifiable parameter combinations named, the series in which
each joint's torque changes sign, and leave-one-pose-out cross-validation."""

from __future__ import annotations

import numpy as np

from ..static.fit import FitResult, Problem, fit_model
from .results import Identifiability, weak_directions

__all__ = ["identifiability", "leave_one_pose_out"]


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
