"""Joint damping of the E-model from measured modal damping ratios.

The model's modal damping ratio (:func:`~flexarm.assembly.analyses.modes`) is the strain
energy-weighted mean of the joints' ratios plus what the foundation and flexible bodies
add: ``zeta_r = sum_j e_jr zeta_j(omega_r) + zeta_rest_r``, with ``e_jr`` the share of
mode ``r``'s strain energy stored in joint ``j``.  That is linear in the joint ratios, so
measured ratios at several poses and modes (the energy shares change with the pose) give
a bounded linear least-squares fit.  Three fits, from few parameters to many:

- ``constant``: one ratio for every joint (1 parameter);
- ``rayleigh``: one ``(alpha, beta)`` pair for every joint, ``zeta_j(omega) = alpha /
  (2 omega) + beta omega / 2`` (2 parameters);
- ``joints``: one constant ratio per joint (one parameter per identifiable joint).

Residuals are relative (``(fit - measured) / measured``): identified damping ratios scatter
by a share of themselves.  The fit written into the robot file is the one with the lowest
corrected Akaike criterion of those residuals, so a per-joint fit has to earn its extra
parameters.  A joint whose largest energy share over the data stays below
:data:`MIN_SHARE` cannot be seen in them: it keeps its ratio, and the result says so.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from scipy.optimize import lsq_linear

from ...assembly.analyses import modes
from ...assembly.system import ArmModel
from ...fe.plotting import pyplot, save_figure
from ...fe.typing import PathType
from ...robot.description import Robot
from ..data.formats import UffOptions, read_modal
from ..data.measurements import ModalData
from ..models import DEFAULT_OPTIONS, ValidationOptions, load, validation_models
from .modal import match_modes

__all__ = ["DampingFit", "MIN_SHARE", "METHODS", "damping_design", "damping_inputs",
           "fit_damping",
           "robot_with_damping"]

#: A joint stores at least this share of some measured mode's strain energy [-] to be fitted.
MIN_SHARE = 0.05
#: The fits, from the fewest parameters to the most.
METHODS = ("constant", "rayleigh", "joints")


@dataclass(frozen=True)
class _Design:
    """Rows = matched measured modes: energy shares ``E`` (rows, joints), angular
    frequency [rad/s] of the model mode, the damping that does not come from joints,
    the row of the data, the model's damping ratio [-]."""

    E: np.ndarray
    omega: np.ndarray
    rest: np.ndarray
    row: np.ndarray
    model: np.ndarray


def damping_design(arm: ArmModel, data: ModalData) -> _Design:
    """Energy shares of the model modes matched (by frequency, per pose) to the rows of
    ``data``; unmatched rows and rows without a damping ratio are left out."""
    E, omega, rest, rows, model = [], [], [], [], []
    labels = np.asarray(data.poses)
    for pose in dict.fromkeys(labels.tolist()):
        idx = np.flatnonzero(labels == pose)
        md = modes(arm, data.q[idx[0]])
        k = match_modes(data.freq_hz[idx], md.freq_hz)
        ok = k >= 0
        idx, k = idx[ok], k[ok]
        joint = sum(md.energy[j, k] * jm.ratio(md.omega[k]) for j, jm in enumerate(arm.joints))
        E.append(md.energy[:, k].T)
        omega.append(md.omega[k])
        rest.append(md.damping[k] - joint)
        rows.append(idx)
        model.append(md.damping[k])
    return _Design(np.vstack(E), np.concatenate(omega), np.concatenate(rest),
                   np.concatenate(rows), np.concatenate(model))


def _solve(A: np.ndarray, b: np.ndarray, upper: float) -> np.ndarray:
    return lsq_linear(A, b, bounds=(0.0, upper)).x


def _fits(d: _Design, zeta: np.ndarray, prior: np.ndarray, seen: np.ndarray) -> dict:
    """Parameters and fitted ratios of every method, in relative residuals."""
    w = 1 / zeta
    fixed = d.rest + d.E[:, ~seen] @ prior[~seen]
    b = (zeta - fixed) * w
    s = d.E[:, seen].sum(axis=1)
    out = {}
    x = _solve((s * w)[:, None], b, 0.99)
    out["constant"] = (np.where(seen, x[0], prior), None, fixed + s * x[0])
    # one law in every joint, so the unseen ones take it too
    s_all = d.E.sum(axis=1)
    A = np.column_stack([s_all / (2 * d.omega), s_all * d.omega / 2]) * w[:, None]
    ab = lsq_linear(A, (zeta - d.rest) * w, bounds=(0.0, np.inf)).x
    out["rayleigh"] = (prior, tuple(float(v) for v in ab),
                       d.rest + s_all * (ab[0] / (2 * d.omega) + ab[1] * d.omega / 2))
    x = _solve(d.E[:, seen] * w[:, None], b, 0.99)
    ratios = prior.copy()
    ratios[seen] = x
    out["joints"] = (ratios, None, fixed + d.E[:, seen] @ x)
    return out


def _aicc(rel: np.ndarray, k: int) -> float:
    n = len(rel)
    rss = max(float(rel @ rel), 1e-300)
    return n * np.log(rss / n) + 2 * k + (2 * k * (k + 1) / (n - k - 1) if n > k + 1 else np.inf)


@dataclass(frozen=True, eq=False)
class DampingFit:
    """Joint damping fitted to measured modal damping (:func:`fit_damping`).

    Attributes
    ----------
    method : str
        The fit written into :attr:`robot` (one of :data:`METHODS`).
    poses, modes : (n,) arrays
        Pose label and mode number of each matched measured mode.
    freq_hz, measured : (n,) float
        Its measured frequency [Hz] and damping ratio [-].
    fitted : dict str -> (n,) float
        Model damping ratio [-] of each method at those modes.
    aicc : dict str -> float
        Corrected Akaike criterion of each method's relative residuals (lower is better).
    joint_ratios : dict str -> (n_joints,) float
        Each joint's constant ratio [-] per method (``rayleigh``: unchanged).
    rayleigh : (2,) float
        ``(alpha [1/s], beta [s])`` of the Rayleigh fit.
    seen : (n_joints,) bool
        Joints with a share of at least :data:`MIN_SHARE` in some measured mode.
    joint_names : tuple of str
    n_unmatched : int
        Measured modes with no model mode in the matching window.
    robot : Robot
        The input robot with the chosen fit's damping in every joint.
    """

    method: str
    poses: np.ndarray
    modes: np.ndarray
    freq_hz: np.ndarray
    measured: np.ndarray
    fitted: dict
    aicc: dict
    joint_ratios: dict
    rayleigh: tuple
    seen: np.ndarray
    joint_names: tuple
    n_unmatched: int
    robot: Robot

    def rms(self, method: str) -> float:
        """RMS relative error of ``method``'s ratios against the measured ones [-]."""
        rel = self.fitted[method] / self.measured - 1
        return float(np.sqrt(np.mean(rel**2)))

    def text(self) -> str:
        """Methods (chosen one marked), joint ratios, and measured vs fitted per mode."""
        lines = [f"{'method':<9s} {'params':>6s} {'rms_pct':>8s} {'AICc':>8s}"]
        for m in METHODS:
            lines.append(f"{m:<9s} {_n_params(m, self.seen):6d} {100 * self.rms(m):8.2f} "
                         f"{self.aicc[m]:8.1f}{'  <- written' if m == self.method else ''}")
        a, b = self.rayleigh
        lines += [f"rayleigh: alpha {a:.4g} 1/s, beta {b:.4g} s", "",
                  f"{'joint':<6s} {'constant':>9s} {'joints':>9s}"]
        for j, name in enumerate(self.joint_names):
            note = "" if self.seen[j] else "  (not seen in the data: kept)"
            lines.append(f"{name:<6s} {self.joint_ratios['constant'][j]:9.4f} "
                         f"{self.joint_ratios['joints'][j]:9.4f}{note}")
        lines += ["", f"{'pose':<5s} {'mode':>4s} {'f_hz':>8s} {'zeta_meas':>9s} "
                  + " ".join(f"{m:>9s}" for m in METHODS)]
        for i in range(len(self.measured)):
            lines.append(f"{self.poses[i]!s:<5s} {int(self.modes[i]):4d} {self.freq_hz[i]:8.2f} "
                         f"{self.measured[i]:9.4f} "
                         + " ".join(f"{self.fitted[m][i]:9.4f}" for m in METHODS))
        if self.n_unmatched:
            lines.append(f"{self.n_unmatched} measured modes had no model mode nearby: left out")
        return "\n".join(lines)

    def plot(self, path: PathType) -> Path:
        """Measured and fitted damping ratios [%] over frequency, as a PNG."""
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(7, 4.2))
        order = np.argsort(self.freq_hz)
        ax.plot(self.freq_hz, 100 * self.measured, "ko", label="measured")
        for m, mk in zip(METHODS, ("s", "^", "x"), strict=True):
            lab = f"{m} ({100 * self.rms(m):.1f} % rms)" + (" - written" if m == self.method
                                                            else "")
            ax.plot(self.freq_hz[order], 100 * self.fitted[m][order], mk, mfc="none", label=lab)
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("damping ratio [%]")
        ax.set_title("modal damping: measured vs fitted")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        return save_figure(fig, path, dpi=110)


def _n_params(method: str, seen: np.ndarray) -> int:
    return {"constant": 1, "rayleigh": 2, "joints": int(seen.sum())}[method]


def robot_with_damping(robot: Robot, ratios, rayleigh: tuple | None = None) -> Robot:
    """``robot`` with joint ``j``'s ``damping_ratio`` set to ``ratios[j]`` [-] (or, given
    ``rayleigh = (alpha [1/s], beta [s])``, with that Rayleigh law in every joint), in
    the physical and in the equivalent E-model joint.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> r = robot_with_damping(load_demo_robot(), [0.01, 0.02, 0.03, 0.04, 0.05, 0.06])
    >>> [j.model.damping_ratio for j in r.joints][-2:]
    [0.05, 0.06]
    """
    def jm(m, z):
        if m is None:
            return None
        if rayleigh is not None:
            return replace(m, rayleigh=tuple(float(v) for v in rayleigh))
        return replace(m, damping_ratio=float(z), rayleigh=None)

    joints = tuple(replace(j, model=jm(j.model, z), emodel=jm(j.emodel, z))
                   for j, z in zip(robot.joints, ratios, strict=True))
    return replace(robot, joints=joints)


def damping_inputs(data: ModalData | PathType, robot: Robot | PathType | None,
                   options: ValidationOptions = DEFAULT_OPTIONS, max_hz: float | None = None,
                   pose: str | None = None, response: str | None = None):
    """``(data, robot, arm, design, zeta)``: the modal data (read if a path: CSV, or a
    universal file with mode shapes measured at ``pose`` when it carries none), the robot,
    its E-model, the :func:`damping_design` and the measured ratios of its rows; modes
    above ``max_hz`` [Hz] are left out (an identification's band edge)."""
    src = data
    robot = load(robot)
    if not isinstance(data, ModalData):
        data = read_modal(data, uff=UffOptions.at(robot, pose, response))
    if data.damping_ratio is None:
        raise ValueError(f"{src if not isinstance(src, ModalData) else 'modal data'}: no "
                         f"'damping_ratio' column: nothing to fit")
    if max_hz is not None:
        keep = np.flatnonzero(np.asarray(data.freq_hz) <= max_hz)
        data = ModalData(**{f: np.asarray(getattr(data, f))[keep]  # shapes are not needed
                            for f in ("poses", "q", "modes", "freq_hz", "damping_ratio")})
    need = "damping fit needs at least 3 matched modes with damping_ratio > 0"
    if len(data.freq_hz) < 3:
        raise ValueError(f"{need}, got {len(data.freq_hz)} modes"
                         + ("" if max_hz is None else f" up to {max_hz:g} Hz"))
    arm = validation_models(robot, replace(options, flexible=False)).arm
    d = damping_design(arm, data)
    zeta = np.asarray(data.damping_ratio, float)[d.row]
    if len(zeta) < 3 or np.any(zeta <= 0):
        raise ValueError(need)
    return data, robot, arm, d, zeta


def fit_damping(data: ModalData | PathType, robot: Robot | PathType | None = None,
                method: str = "auto", options: ValidationOptions = DEFAULT_OPTIONS,
                max_hz: float | None = None, pose: str | None = None) -> DampingFit:
    """Fit joint damping of ``robot``'s E-model to the damping ratios of modal ``data``.

    Parameters
    ----------
    data : ModalData or path
        Measured modes with a ``damping_ratio`` column (e.g. from ``flexarm ema``).
    robot : Robot, path or None
        The robot (None: the demo arm); its joint stiffnesses are taken as right.
    method : {"auto", "constant", "rayleigh", "joints"}
        The fit written into the returned robot; ``auto``: the lowest AICc.
    options : ValidationOptions
        How the E-model is built.
    max_hz : float or None
        Leave out modes above this frequency [Hz] (e.g. the upper edge of the band the
        modes were identified in, where identified damping is unreliable).
    pose : str or None
        The pose a universal file without pose marks was measured at (a pose name or
        ``q1,...,q6`` [deg]).

    Returns
    -------
    DampingFit
    """
    if method != "auto" and method not in METHODS:
        raise ValueError(f"damping fit method must be auto or one of {', '.join(METHODS)}, "
                         f"got '{method}'")
    data, robot, arm, d, zeta = damping_inputs(data, robot, options, max_hz, pose)
    prior = np.array([jm.damping_ratio for jm in arm.joints])
    seen = d.E.max(axis=0) >= MIN_SHARE
    fits = _fits(d, zeta, prior, seen)
    aicc = {m: _aicc(fits[m][2] / zeta - 1, _n_params(m, seen)) for m in METHODS}
    chosen = min(METHODS, key=aicc.get) if method == "auto" else method
    ratios, ray, _ = fits[chosen]
    return DampingFit(
        chosen, np.asarray(data.poses)[d.row], np.asarray(data.modes)[d.row],
        np.asarray(data.freq_hz, float)[d.row], zeta, {m: fits[m][2] for m in METHODS}, aicc,
        {m: fits[m][0] for m in METHODS}, fits["rayleigh"][1], seen, robot.joint_names,
        len(data.freq_hz) - len(d.row),
        robot_with_damping(robot, ratios, ray if chosen == "rayleigh" else None))
