"""Predictions vs modal and FRF measurements: frequency-error tables, bars and overlays.

* Modal: per pose and mode the measured and model natural frequencies, the error in Hz
  and in percent, chi^2_red with the relative frequency noise
  (``tol.freq_noise``, no fitted parameters: dof = number of frequencies) and the RMS
  relative error; a bar chart of the percent error per pose and mode.
* FRF: the model receptance at every measured line (modal superposition with the
  model's modal damping) and, per pose and input/output pair, the RMS of
  ``log10 |H_meas / H_model|`` and the error of the largest peak's frequency; overlays
  of magnitude and phase.  Measured coherence, when the data carry it, weights each
  line of the RMS by ``gamma^2 / (1 - gamma^2)`` and keeps the peak search to lines of
  good coherence (:mod:`.frf_weights`).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...assembly.analyses import frf
from ...assembly.effects import apply_effects
from ...assembly.linkflex import links_arm, split_links
from ...assembly.system import ArmModel
from ...fe.files import atomic_path, writes_folder
from ...fe.plotting import pyplot
from ...fe.text import text_table
from ...fe.units import RECEPTANCE_SCALE, RECEPTANCE_UNIT
from ..data.measurements import FrfData, ModalData
from ..static.fit import chi2_band
from ..static.report import write_rows
from ..tolerances import tol
from .frf_weights import coherence_weight, trusted_lines, weighted_rms
from .modal import match_frequencies

__all__ = ["ModalError", "ModalComparison", "FrfError", "FrfComparison", "compare_modal",
           "compare_frf", "write_modal_report", "write_frf_report"]


def _model(arm: ArmModel, effects, flexible):
    c, rest = split_links(effects)
    return apply_effects(links_arm(arm, flexible, c), rest)[0]


@dataclass(frozen=True)
class ModalError:
    """Error of one measured natural frequency (a row of ``modal_errors.csv``).

    Attributes
    ----------
    pose : str
        Pose label.
    mode : int
        Measured mode number (1-based, as in the file).
    model_mode : int
        Model mode it was matched with (1-based).
    matched : bool
        False: no model mode inside the matching window; the row is kept out of
        ``chi2_red`` and ``rms_pct``.
    measured_hz, model_hz : float
        Measured and model natural frequency [Hz].
    error_hz : float
        ``model_hz - measured_hz`` [Hz].
    error_pct : float
        ``error_hz`` relative to ``measured_hz`` [%].
    """

    pose: str
    mode: int
    model_mode: int
    matched: bool
    measured_hz: float
    model_hz: float
    error_hz: float
    error_pct: float


@dataclass(frozen=True)
class ModalComparison:
    """Result of :func:`compare_modal`.

    Attributes
    ----------
    predicted : (n,) float
        Model natural frequency matched to each measured one [Hz].
    table : tuple of ModalError
        One row per measured frequency, in the order of the data.
    chi2_red : float
        chi^2 per matched frequency with the relative frequency noise.
    band : (float, float)
        Acceptance band of ``chi2_red``.
    rms_pct : float
        RMS relative error over the matched rows [%].
    freq_noise : float
        The relative frequency noise of ``chi2_red`` [-].
    """

    predicted: np.ndarray
    table: tuple[ModalError, ...]
    chi2_red: float
    band: tuple
    rms_pct: float
    freq_noise: float = tol.freq_noise

    def text(self) -> str:
        """The frequency-error table [Hz, %], chi2_red with its band and the RMS error
        [%], as ``compare`` prints them."""
        # the noise as it was typed in percent: a short decimal survives / 100 * 100
        pct = round(self.freq_noise * 100, 10)
        return "\n".join([
            text_table(["pose", "mode", "measured_Hz", "model_Hz", "error_Hz", "error_%"],
                       [[r.pose, r.mode, r.measured_hz, r.model_hz, r.error_hz, r.error_pct]
                        for r in self.table], "{:.3f}"),
            f"chi2_red = {self.chi2_red:.3f} (band {self.band[0]:.3f}-{self.band[1]:.3f} for "
            f"{pct}% frequency noise), RMS error {self.rms_pct:.2f}%"])

    def write(self, folder) -> list[Path]:
        """:func:`write_modal_report` into ``folder``."""
        return write_modal_report(folder, self)


def compare_modal(arm: ArmModel, data: ModalData, effects=(), freq_noise: float = tol.freq_noise,
                  flexible: ArmModel | None = None) -> ModalComparison:
    """Compare the natural frequencies of ``arm`` (plus ``effects``) with ``data``.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.assembly.emodel import emodel
    >>> robot = load_demo_robot()
    >>> arm = emodel(robot, method="surface")
    >>> q = robot.pose("P1")
    >>> m = ModalData(poses=["P1"], q=[q], modes=[1], freq_hz=[8.0])
    >>> cmp = compare_modal(arm, m)
    >>> len(cmp.table), cmp.table[0].mode
    (1, 1)
    """
    # Measured modes are assigned to model modes by frequency, pose by pose; a row
    # with no model mode inside the window is shown but kept out of chi2 and RMS.
    match = match_frequencies(_model(arm, effects, flexible), data)
    f_model = match.model_hz
    f_meas = np.asarray(data.freq_hz, float)
    err = f_model - f_meas
    rel = err / f_meas
    rows = [ModalError(str(p), int(m), int(k), bool(ok), float(a), float(b), float(e),
                       float(100 * r))
            for p, m, k, ok, a, b, e, r in zip(data.poses, data.modes, match.model_mode,
                                               match.matched, f_meas, f_model, err, rel,
                                               strict=True)]
    z = rel[match.matched] / freq_noise
    n = max(len(z), 1)
    return ModalComparison(f_model, tuple(rows), float(z @ z / n), chi2_band(n),
                           float(100 * np.sqrt(np.mean(z**2)) * freq_noise) if z.size else 0.0,
                           freq_noise)


@dataclass(frozen=True)
class FrfError:
    """Error of the model receptance on one pose and input/output pair (a row of
    ``frf_errors.csv``).

    Attributes
    ----------
    pose : str
        Pose label.
    input, output : str
        Force input and displacement output axis (``"x"``, ``"y"``, ``"z"``).
    rms_log10_mag : float
        RMS of ``log10 |H_meas / H_model|`` over the measured lines (dimensionless),
        weighted by the coherence when measured.
    peak_meas_hz, peak_model_hz : float
        Frequency of the largest measured and model ``|H|`` on those lines (of good
        coherence, when measured) [Hz].
    peak_error_pct : float
        ``peak_model_hz - peak_meas_hz`` relative to ``peak_meas_hz`` [%].
    """

    pose: str
    input: str
    output: str
    rms_log10_mag: float
    peak_meas_hz: float
    peak_model_hz: float
    peak_error_pct: float


@dataclass(frozen=True)
class FrfComparison:
    """Result of :func:`compare_frf`.

    Attributes
    ----------
    data : FrfData
        The measurements compared.
    predicted : (n,) complex
        Model receptance at each measured line [m/N].
    table : tuple of FrfError
        One row per pose and input/output pair, in order of first appearance.
    """

    data: FrfData
    predicted: np.ndarray
    table: tuple[FrfError, ...]

    def text(self) -> str:
        """The error table per pose and input/output pair, as ``compare`` prints it (and
        a note when the measured coherence weights it)."""
        table = text_table(["pose", "in", "out", "rms_log10|H|", "peak_meas_Hz",
                            "peak_model_Hz", "peak_err_%"],
                           [[r.pose, r.input, r.output, r.rms_log10_mag, r.peak_meas_hz,
                             r.peak_model_hz, r.peak_error_pct] for r in self.table], "{:.3f}")
        if self.data.coherence is None:
            return table
        return table + ("\nlines weighted by the measured coherence, gamma^2 / (1 - gamma^2); "
                        f"peaks looked for where gamma^2 >= {tol.peak_coherence:g}")

    def write(self, folder) -> list[Path]:
        """:func:`write_frf_report` into ``folder``."""
        return write_frf_report(folder, self)


def _groups(data: FrfData) -> dict:
    keys = [f"{p}:{i}{o}" for p, i, o in zip(data.poses, data.inputs, data.outputs, strict=True)]
    out: dict = {}
    for k, key in enumerate(keys):
        out.setdefault(key, []).append(k)
    return {key: np.asarray(v) for key, v in out.items()}


def compare_frf(arm: ArmModel, data: FrfData, effects=(),
                flexible: ArmModel | None = None, robot=None) -> FrfComparison:
    """Model receptances at the measured lines of ``data`` and the per-pair errors;
    at a pose of ``robot.modal_damping`` with its stored modal damping
    (:func:`~.pose_damping.pose_damping`)."""
    from .pose_damping import pose_damping

    model = _model(arm, effects, flexible)
    H = np.zeros(len(data.freq_hz), complex)
    for rows in _groups(data).values():
        q = data.q[rows[0]][: model.chain.n_joints]
        zeta = None if robot is None else pose_damping(robot, model, q)
        Hk = frf(model, q, data.freq_hz[rows], zeta)
        H[rows] = Hk[:, data.output_axes[rows[0]], data.input_axes[rows[0]]]
    table = []
    for key, rows in _groups(data).items():
        meas, pred, f = data.receptance[rows], H[rows], data.freq_hz[rows]
        g2 = None if data.coherence is None else data.coherence[rows]
        ok = (np.abs(meas) > 0) & (np.abs(pred) > 0)
        lr = np.log10(np.abs(meas[ok]) / np.abs(pred[ok]))
        peak = trusted_lines(g2, len(rows))
        fm = f[peak][np.argmax(np.abs(meas[peak]))]
        fp = f[peak][np.argmax(np.abs(pred[peak]))]
        pose, io = key.split(":")
        table.append(FrfError(
            pose=pose, input=io[0], output=io[1],
            rms_log10_mag=weighted_rms(lr, None if g2 is None else coherence_weight(g2[ok])),
            peak_meas_hz=float(fm), peak_model_hz=float(fp),
            peak_error_pct=float(100 * (fp - fm) / fm) if fm > 0 else 0.0))
    return FrfComparison(data, H, tuple(table))


@writes_folder()
def write_modal_report(folder, cmp: ModalComparison) -> list[Path]:
    """``modal_errors.csv`` and ``frequency_errors.png`` (bars per pose and mode)."""
    plt = pyplot()

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = [folder / "modal_errors.csv", folder / "frequency_errors.png"]
    write_rows(out[0], ModalError, cmp.table)
    poses = list(dict.fromkeys(r.pose for r in cmp.table))
    modes = sorted({r.mode for r in cmp.table})
    width = 0.8 / max(len(modes), 1)
    fig, ax = plt.subplots(figsize=(1.2 + 1.4 * len(poses), 3))
    for k, m in enumerate(modes):
        vals = [next((r.error_pct for r in cmp.table if r.pose == p and r.mode == m), np.nan)
                for p in poses]
        ax.bar(np.arange(len(poses)) + (k - (len(modes) - 1) / 2) * width, vals, width,
               label=f"mode {m}", color=f"C{k}")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xticks(np.arange(len(poses)), poses)
    ax.set_ylabel("model - measured [%]")
    ax.set_title(f"natural frequency error (chi2_red {cmp.chi2_red:.2f})", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out[1], dpi=90)
    plt.close(fig)
    return out


@writes_folder()
def write_frf_report(folder, cmp: FrfComparison) -> list[Path]:
    """``frf_errors.csv``, ``frf_overlay.png`` (magnitude in :data:`RECEPTANCE_UNIT` and
    phase per pair) and ``frf_overlay.csv``, the plotted lines in SI (pose, input, output,
    ``freq_Hz``, real and imaginary parts of the measured and model receptance [m/N])."""
    plt = pyplot()

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = [folder / "frf_errors.csv", folder / "frf_overlay.png", folder / "frf_overlay.csv"]
    write_rows(out[0], FrfError, cmp.table)
    groups = _groups(cmp.data)
    n = len(groups)
    fig, axes = plt.subplots(2, n, figsize=(3.2 * n, 4.6), squeeze=False, sharex="col")
    for c, (key, rows) in enumerate(groups.items()):
        f = cmp.data.freq_hz[rows]
        for H, style, lab in ((cmp.data.receptance[rows], "o", "measured"),
                              (cmp.predicted[rows], "-", "model")):
            axes[0, c].semilogy(f, np.abs(H) * RECEPTANCE_SCALE, style, ms=2.5, label=lab)
            axes[1, c].plot(f, np.degrees(np.angle(H)), style, ms=2.5)
        axes[0, c].set_title(key, fontsize=8)
        axes[1, c].set_xlabel("frequency [Hz]", fontsize=8)
    axes[0, 0].set_ylabel(f"|H| [{RECEPTANCE_UNIT}]")
    axes[1, 0].set_ylabel("phase [deg]")
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out[1], dpi=90)
    plt.close(fig)
    _write_overlay(out[2], cmp, groups)
    return out


def _write_overlay(path: Path, cmp: FrfComparison, groups: dict) -> None:
    """The lines of ``frf_overlay.png`` in SI, pair by pair in the plot's order."""
    d = cmp.data
    order = np.concatenate(list(groups.values())) if groups else np.zeros(0, int)
    meas, pred = np.asarray(d.receptance)[order], cmp.predicted[order]
    cols = [np.asarray(d.freq_hz)[order], meas.real, meas.imag, pred.real, pred.imag]
    with atomic_path(path) as tmp, tmp.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["pose", "input", "output", "freq_Hz", "re_H_meas_m_per_N",
                    "im_H_meas_m_per_N", "re_H_model_m_per_N", "im_H_model_m_per_N"])
        w.writerows([d.poses[k], d.inputs[k], d.outputs[k], *(f"{v:.10g}" for v in r)]
                    for k, r in zip(order, np.column_stack(cols), strict=True))
