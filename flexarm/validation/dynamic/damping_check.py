"""Diagnosis of missing joint damping: measured ratios that rise at one joint's modes.

A joint whose damper the model lacks (or underrates) shows in the identified modal damping
as ratios that exceed the model's in exactly the modes that store energy in that joint
(wrist-dominated modes for a wrist joint), at every pose.  Each joint is a candidate with
one amplitude, its extra ratio ``delta_j`` [-], whose signature is its energy share
``e_jr`` (:func:`~flexarm.validation.dynamic.damping_fit.damping_design`).  Identified ratios are
taken to scatter by ``sigma_rel`` times themselves, independently per mode and pose, and
by ``1 + w overlap`` times that where a mode's half-power band meets a neighbour's
(:func:`modal_overlap`; ``w`` is ``tol.damping_overlap_widening``): an identification
splits the damping of two overlapping modes less well (on the demo arm's wrist, zoomed and
refined LSCF gets them within 6 %, separated modes within a few per cent).

The search is forward and greedy, like the static diagnosis: the candidate with the largest
chi-square gain is accepted when its gain exceeds the chi-square(1) quantile at ``alpha``
divided by the number of candidates (a Bonferroni bound: on damping-correct data the
chance of accepting anything stays below ``alpha``), its extra ratio is positive (a
*missing* damper), and the joint is seen
(:data:`~flexarm.validation.dynamic.damping_fit.MIN_SHARE`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import nnls

from ...fe.plotting import pyplot, save_figure
from ...fe.typing import PathType
from ...robot.description import Robot
from ..data.measurements import ModalData
from ..distributions import chi2_isf, chi2_sf
from ..models import DEFAULT_OPTIONS, ValidationOptions
from ..tolerances import tol
from .damping_fit import MIN_SHARE, damping_inputs

__all__ = ["DampingDiagnosis", "diagnose_damping", "modal_overlap"]


@dataclass(frozen=True, eq=False)
class DampingDiagnosis:
    """Result of :func:`diagnose_damping`.

    Attributes
    ----------
    accepted : tuple of int
        0-based joints found to miss damping, in the order accepted.
    extra : (n_joints,) float
        Extra damping ratio [-] of each accepted joint (0 elsewhere).
    gains : (n_joints,) float
        Chi-square gain of each joint in the first round (``nan``: not seen).
    threshold : float
        The gain a candidate has to exceed.
    chi2_before, chi2_after : float
        Chi-square of the nominal model and after the accepted joints.
    n : int
        Matched measured modes.
    p_after : float
        Probability of a chi-square at least ``chi2_after`` if what is left were noise
        (small: a misfit the joint dampers do not explain).
    joint_names : tuple of str
    share : (n, n_joints) float
        Energy shares of the matched modes (to show where a joint dominates).
    ratio : (n,) float
        Measured over model damping ratio [-] of each matched mode.
    """

    accepted: tuple
    extra: np.ndarray
    gains: np.ndarray
    threshold: float
    chi2_before: float
    chi2_after: float
    n: int
    p_after: float
    joint_names: tuple
    share: np.ndarray
    ratio: np.ndarray

    def text(self) -> str:
        """Candidates, what was accepted, and the modes each accepted joint dominates."""
        lines = [f"missing joint damping: chi2 {self.chi2_before:.1f} -> {self.chi2_after:.1f} "
                 f"on {self.n} modes (gain needed {self.threshold:.1f})",
                 f"{'joint':<8s} {'gain':>8s} {'extra_zeta':>10s}"]
        for j, name in enumerate(self.joint_names):
            g = "unseen" if np.isnan(self.gains[j]) else f"{self.gains[j]:8.1f}"
            mark = "  <- missing damping" if j in self.accepted else ""
            lines.append(f"{name:<8s} {g:>8s} {self.extra[j]:10.4f}{mark}")
        for j in self.accepted:
            dom = self.share[:, j] > 0.3
            if dom.any():
                lines.append(f"{self.joint_names[j]}: measured/model ratio "
                             f"{np.mean(self.ratio[dom]):.2f} in the {int(dom.sum())} modes it "
                             f"dominates (> 30 % of the energy), "
                             f"{np.mean(self.ratio[~dom]) if (~dom).any() else np.nan:.2f} "
                             f"elsewhere")
        if not self.accepted:
            lines.append("no joint misses damping")
        if self.p_after < 0.01:
            lines.append(f"damping misfit left (p = {self.p_after:.1g}): not explained by "
                         f"joint dampers")
        return "\n".join(lines)

    def plot(self, path: PathType) -> Path:
        """Measured over model damping ratio of each mode against each joint's share of
        that mode's energy, one panel per joint, as a PNG: a joint that misses a damper
        shows as ratios rising with its share."""
        plt = pyplot()
        n = len(self.joint_names)
        cols = min(n, 3)
        fig, axes = plt.subplots(-(-n // cols), cols, figsize=(3.2 * cols, 2.6 * -(-n // cols)),
                                 sharey=True, squeeze=False)
        for j, ax in enumerate(axes.flat):
            if j >= n:
                ax.set_visible(False)
                continue
            hit = j in self.accepted
            ax.plot(100 * self.share[:, j], self.ratio, "o", ms=4,
                    color="tab:red" if hit else "tab:blue")
            ax.axhline(1.0, color="0.5", lw=0.8)
            seen = "unseen" if np.isnan(self.gains[j]) else f"gain {self.gains[j]:.1f}"
            ax.set_title(f"{self.joint_names[j]} ({seen})" + (": missing" if hit else ""),
                         fontsize=9)
            ax.set_xlim(-3, 103)
            ax.grid(alpha=0.3)
            if j % cols == 0:
                ax.set_ylabel("measured / model ratio [-]")
            if j >= n - cols:
                ax.set_xlabel("joint's energy share [%]")
        fig.suptitle(f"damping per mode, {self.n} modes (gain needed {self.threshold:.1f})",
                     fontsize=10)
        return save_figure(fig, path, dpi=110)


def modal_overlap(freq_hz, damping_ratio, poses) -> np.ndarray:
    """Per mode, its overlap with the nearest mode of the same pose [-]: the two
    half-power half-widths ``zeta f`` added, over their spacing (1: the bands touch).

    Examples
    --------
    >>> modal_overlap([100.0, 104.0, 300.0], [0.02, 0.02, 0.02], ["P1"] * 3).round(3).tolist()
    [1.02, 1.02, 0.041]
    """
    f = np.asarray(freq_hz, dtype=float)
    half = np.asarray(damping_ratio, dtype=float) * f
    poses = np.asarray(poses)
    out = np.zeros(len(f))
    for p in np.unique(poses):
        i = np.flatnonzero(poses == p)
        gap = np.abs(f[i, None] - f[None, i])
        np.fill_diagonal(gap, np.inf)
        out[i] = ((half[i, None] + half[None, i]) / np.maximum(gap, 1e-12)).max(axis=1,
                                                                               initial=0.0)
    return out


def _chi2(A: np.ndarray, r: np.ndarray, cols: list[int]) -> tuple[float, np.ndarray]:
    """Chi-square after the best non-negative extra ratios at ``cols``, and those ratios."""
    if not cols:
        return float(r @ r), np.zeros(0)
    x, res = nnls(A[:, cols], r)
    return float(res**2), x


def diagnose_damping(data: ModalData | PathType, robot: Robot | PathType | None = None,
                     sigma_rel: float = 0.05, alpha: float = 0.01, max_effects: int = 2,
                     options: ValidationOptions = DEFAULT_OPTIONS,
                     max_hz: float | None = None, pose: str | None = None
                     ) -> DampingDiagnosis:
    """Which joints of ``robot`` miss damping, judged by the damping ratios in ``data``.

    Parameters
    ----------
    data : ModalData or path
        Measured modes with damping ratios.
    robot : Robot, path or None
        The model under test (None: the demo arm).
    sigma_rel : float
        Relative scatter of an identified damping ratio [-] (0.05: 5 %) of a mode clear
        of its neighbours; ``1 + w overlap`` times that for overlapping modes
        (``w``: ``tol.damping_overlap_widening``).
    alpha : float
        Chance of accepting a joint on damping-correct data (at most).
    max_effects : int
        Joints accepted at most.
    options : ValidationOptions
        How the E-model is built.
    max_hz : float or None
        Leave out modes above this frequency [Hz] (an identification's band edge).
    """

    modal, robot, arm, d, zeta = damping_inputs(data, robot, options, max_hz, pose)
    overlap = modal_overlap(modal.freq_hz, modal.damping_ratio, modal.poses)[d.row]
    sd = sigma_rel * zeta * (1.0 + tol.damping_overlap_widening * overlap)
    A = d.E / sd[:, None]
    r = (zeta - d.model) / sd
    seen = d.E.max(axis=0) >= MIN_SHARE
    n_cand = int(seen.sum())
    threshold = float(chi2_isf(alpha / max(n_cand, 1), 1))
    accepted: list[int] = []
    chi_now, _ = _chi2(A, r, accepted)
    chi_before = chi_now
    gains = np.full(len(arm.joints), np.nan)
    while len(accepted) < max_effects:
        best, best_gain = None, -np.inf
        for j in np.flatnonzero(seen):
            if j in accepted:
                continue
            c, x = _chi2(A, r, accepted + [int(j)])
            gain = chi_now - c
            if not accepted:
                gains[j] = gain
            if x[-1] > 0 and gain > best_gain:
                best, best_gain = int(j), gain
        if best is None or best_gain <= threshold:
            break
        accepted.append(best)
        chi_now -= best_gain
    extra = np.zeros(len(arm.joints))
    if accepted:
        extra[accepted] = _chi2(A, r, accepted)[1]
    dof = max(len(r) - len(accepted), 1)
    return DampingDiagnosis(tuple(accepted), extra, gains, threshold, chi_before, chi_now,
                            len(r), float(chi2_sf(chi_now, dof)), robot.joint_names,
                            d.E, zeta / d.model)
