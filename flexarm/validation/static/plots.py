"""Pictures of a static comparison and of a diagnosis: the error history of the model
versions and the residuals against joint torque.

Both draw only what their tables hold (``history.csv``, the residual columns), so the
PNG and the CSV show the same numbers.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ...fe.plotting import picture_from_inputs, pyplot, save_figure
from ...fe.typing import FloatArray
from ..tolerances import tol

__all__ = ["plot_history", "plot_residual_vs_torque", "torque_joints", "write_residuals",
           "NOISE_FLOOR_FACTOR"]

#: A relative reading (loaded minus reference, both with tracker noise sigma) carries
#: noise sqrt(2) sigma per component: the expected RMS of a perfect model (a fitted one
#: lands a little below it, by the share of the noise its parameters absorb).
NOISE_FLOOR_FACTOR = float(np.sqrt(2.0))

#: Joints whose largest torque is below this share of the largest joint's carry no
#: information on a residual plot (e.g. 1e-14 N m on a wrist joint) and are left out.
TORQUE_SHARE = 1e-3


@picture_from_inputs
def plot_history(path, rows: list[dict], nominal_rms: float | None = None,
                 sigma: float | None = None, what: str = "") -> Path:
    """Bars of the fitted and held-out RMS error [µm] of each model version.

    Parameters
    ----------
    rows : list of dict
        ``history.csv`` rows: ``version``, ``model``, ``rms_fit_um``, ``rms_heldout_um``.
    nominal_rms : float, optional
        RMS of the nominal (unfitted) model [m], drawn first (the real headline:
        what the fit gained).
    sigma : float, optional
        Tracker noise [m]; the noise floor ``sqrt(2) sigma`` (a perfect model's expected
        RMS) is drawn as a line, and the reduced chi-square band of the last version
        (``band_lo``, ``band_hi``) as the RMS band a perfect model falls in.
    what : str
        The model and poses, for the title (e.g. ``"E-model at P1, P2, P3"``).

    Rows with a finite ``freq_rms_pct`` (modal data) add a second panel: the RMS error
    [%] of the paired measured frequencies per version, with its unpaired modes.
    """
    plt = pyplot()
    modal = [r for r in rows if np.isfinite(float(r.get("freq_rms_pct", np.nan) or np.nan))]
    if modal:
        fig, (ax, axf) = plt.subplots(1, 2, figsize=(12, 3.6),
                                      gridspec_kw={"width_ratios": (3, 2), "wspace": 0.7})
        _frequency_panel(axf, rows)
    else:
        fig, ax = plt.subplots(figsize=(8, 3.6))
    labels, fit, held = [], [], []
    if nominal_rms is not None:
        labels.append("nominal")
        fit.append(nominal_rms * 1e6)
        held.append(np.nan)
    labels += [f"v{r['version']}" for r in rows]
    fit += [r["rms_fit_um"] for r in rows]
    held += [r["rms_heldout_um"] for r in rows]
    x = np.arange(len(labels))
    ax.bar(x - 0.2, fit, 0.4, label="fitted series" + (" (nominal: all series)"
                                                       if nominal_rms is not None else ""))
    ax.bar(x + 0.2, held, 0.4, label="held-out series")
    if sigma is not None:
        floor = NOISE_FLOOR_FACTOR * sigma * 1e6
        ax.axhline(floor, color="k", ls="--", lw=1,
                   label=f"noise floor √2·σ = {floor:.1f} µm\n(a perfect model's RMS)")
        lo, hi = (rows[-1].get(k) for k in ("band_lo", "band_hi")) if rows else (None, None)
        if lo is not None and hi is not None:
            # RMS^2 / floor^2 is the reduced chi-square: its band, in µm
            ax.axhspan(floor * np.sqrt(lo), floor * np.sqrt(hi), color="k", alpha=0.12,
                       label=f"χ² band of a perfect model\n({floor * np.sqrt(lo):.1f}-"
                             f"{floor * np.sqrt(hi):.1f} µm)")
    ax.set_xticks(x, labels)
    ax.set_xlabel("model version")
    ax.set_ylabel("RMS error [µm]")
    if nominal_rms is not None and nominal_rms * 1e6 > 5 * max(max(fit[1:], default=1), 1):
        from matplotlib.ticker import FormatStrFormatter

        ax.set_yscale("log")  # the nominal error dwarfs the fits' steps
        ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.set_ylabel("RMS error [µm] (log scale)")
    # beside the axes: inside, it would cover the bars that sit near the noise floor
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    steps = [r["model"].split(" + ")[-1] for r in rows]
    ax.set_title(f"static TCP error{' of the ' + what if what else ''} per model version: "
                 + " -> ".join(
        (["nominal"] if nominal_rms is not None else []) + steps), fontsize=8)
    return save_figure(fig, path, dpi=90, bbox_inches="tight")


def _frequency_panel(ax, rows: list[dict]) -> None:
    """Bars of the paired frequencies' RMS error [%] per version, unpaired modes above."""
    err = [float(r["freq_rms_pct"]) for r in rows]
    x = np.arange(len(rows))
    ax.bar(x, err, 0.5, color="tab:green")
    for xi, e, r in zip(x, err, rows, strict=True):
        n = int(r.get("unpaired_modes", 0) or 0)
        if n:
            ax.annotate(f"{n} unpaired", (xi, e), ha="center", va="bottom", fontsize=7)
    ax.set_xticks(x, [f"v{r['version']}" for r in rows])
    ax.set_xlabel("model version")
    ax.set_ylabel("frequency RMS error [%]")
    ax.set_title("error of the paired measured frequencies per model version", fontsize=8)


def torque_joints(tau: FloatArray) -> np.ndarray:
    """Indices of the joints whose largest ``|torque|`` (n, n_joints) [N m] is at least
    :data:`TORQUE_SHARE` of the largest joint's.

    Examples
    --------
    >>> torque_joints(np.array([[100.0, -50.0, 1e-14], [80.0, 20.0, 0.0]])).tolist()
    [0, 1]
    """
    peak = np.abs(np.asarray(tau, dtype=float)).max(axis=0)
    return np.flatnonzero(peak >= TORQUE_SHARE * peak.max())


@picture_from_inputs
def plot_residual_vs_torque(path, tau: FloatArray, residual: FloatArray,
                            title: str = "") -> Path:
    """Residual x, y, z [µm] against each joint's torque [N m], one panel per joint that
    carries torque (:func:`torque_joints`), with a legend.  Past
    ``tol.plot_max_points`` readings, a density instead (:func:`_plot_density`).

    ``tau`` (n, n_joints) [N m]; ``residual`` (n, 3) [m] (measured minus predicted).
    """
    plt = pyplot()
    joints = torque_joints(tau)
    res = np.asarray(residual, dtype=float) * 1e6
    left_out = sorted(set(range(np.shape(tau)[1])) - set(joints.tolist()))
    names = ", ".join(str(j + 1) for j in left_out)
    note = (f" (joint{'s' if len(left_out) > 1 else ''} {names} "
            f"carr{'y' if len(left_out) > 1 else 'ies'} no torque: not shown)" if left_out else "")
    title = (title + ": " if title else "") + "residual vs joint torque" + note
    if len(res) > tol.plot_max_points:
        return _plot_density(path, np.asarray(tau, dtype=float), res, joints, title)
    fig, axes = plt.subplots(1, len(joints), figsize=(2.8 * len(joints) + 0.6, 2.9),
                             squeeze=False, sharey=True)
    for j, ax in zip(joints, axes[0], strict=True):
        for k, c in enumerate("xyz"):
            ax.plot(tau[:, j], res[:, k], ".", ms=3, color=f"C{k}", label=f"residual {c}")
        ax.set_xlabel(f"joint {j + 1} torque [N m]", fontsize=7)
        ax.tick_params(labelsize=7)
    axes[0, 0].set_ylabel("residual (measured - model) [µm]", fontsize=7)
    axes[0, 0].legend(fontsize=6)
    fig.suptitle(title, fontsize=8)
    return save_figure(fig, path, dpi=90)


def _plot_density(path, tau: FloatArray, res_um: FloatArray, joints: np.ndarray,
                  title: str) -> Path:
    """The residual picture of many readings: one row per residual component, one column
    per joint, each a 2-D histogram (log colour scale) of the readings' residual [µm]
    against the joint's torque [N m]."""
    from matplotlib.colors import LogNorm

    plt = pyplot()
    fig, axes = plt.subplots(3, len(joints), figsize=(2.8 * len(joints) + 1.2, 6.4),
                             squeeze=False, sharey="row")
    peak, image = 1, None
    counts = {}
    for k in range(3):
        y_edges = _edges(res_um[:, k])
        for j in joints:
            h, xe, _ = np.histogram2d(tau[:, j], res_um[:, k], (_edges(tau[:, j]), y_edges))
            counts[k, j] = (h, xe, y_edges)
            peak = max(peak, int(h.max()))
    for k, c in enumerate("xyz"):
        for j, ax in zip(joints, axes[k], strict=True):
            h, xe, ye = counts[k, j]
            image = ax.pcolormesh(xe, ye, np.where(h > 0, h, np.nan).T,
                                  norm=LogNorm(1, peak), cmap="viridis")
            ax.tick_params(labelsize=7)
            if k == 2:
                ax.set_xlabel(f"joint {j + 1} torque [N m]", fontsize=7)
        axes[k, 0].set_ylabel(f"residual {c} [µm]", fontsize=7)
    fig.colorbar(image, ax=axes, shrink=0.8, label="readings per cell")
    fig.suptitle(f"{title} ({len(res_um):,d} readings: density)", fontsize=8)
    return save_figure(fig, path, dpi=90, tight=False)


def _edges(x: np.ndarray) -> np.ndarray:
    """``tol.plot_bins`` equal bins over the finite range of ``x`` (one unit wide if flat)."""
    lo, hi = float(np.min(x)), float(np.max(x))
    if hi <= lo:
        lo, hi = lo - 0.5, hi + 0.5
    return np.linspace(lo, hi, tol.plot_bins + 1)


def write_residuals(path, series, tau: FloatArray, residual: FloatArray,
                    force: FloatArray | None = None, measured: FloatArray | None = None,
                    predicted: FloatArray | None = None) -> Path:
    """``residuals.csv``, one row per reading: its series, the joint torques
    ``tau_j<k>_Nm`` and the residual ``res_<x|y|z>_um`` (measured minus model) that
    :func:`plot_residual_vs_torque` draws; with ``force`` (n, 3) [N], ``measured`` and
    ``predicted`` (n, 3) [m] also ``f_N`` (load magnitude) and ``d<x|y|z>_meas_mm``,
    ``d<x|y|z>_model_mm`` (what ``deflection_vs_force.png`` draws)."""
    tau = np.asarray(tau, dtype=float)
    head = ["series"] + [f"tau_j{j + 1}_Nm" for j in range(tau.shape[1])]
    cols = [tau]
    if force is not None:
        head.append("f_N")
        cols.append(np.linalg.norm(np.asarray(force, dtype=float), axis=1)[:, None])
    for name, d in (("meas", measured), ("model", predicted)):
        if d is not None:
            head += [f"d{c}_{name}_mm" for c in "xyz"]
            cols.append(np.asarray(d, dtype=float) * 1e3)
    head += [f"res_{c}_um" for c in "xyz"]
    cols.append(np.asarray(residual, dtype=float) * 1e6)
    table = np.hstack(cols)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    labels = [str(x) for x in series]
    if len(labels) != len(table):
        raise ValueError(f"{len(labels)} series labels for {len(table)} readings")
    # one format per row, a block of rows at a time (what csv.writer gives for these
    # cells, in a fraction of its time: a million readings)
    quote = any(set(x) & set(',"\r\n') for x in dict.fromkeys(labels))
    fmt = ",".join(["%s"] + ["%.10g"] * table.shape[1]) + "\n"
    with open(path, "w", newline="") as fh:
        csv.writer(fh).writerow(head)
        for a in range(0, len(table), 1 << 15):
            names = labels[a:a + (1 << 15)]
            if quote:
                names = [_csv_cell(x) for x in names]
            fh.write("".join(fmt % (x, *row) for x, row in
                             zip(names, table[a:a + (1 << 15)].tolist(), strict=True)))
    return path


def _csv_cell(text: str) -> str:
    """``text`` as the csv module writes a cell (quoted when it holds a comma, a quote or
    a line break)."""
    if any(c in text for c in ',"\r\n'):
        return '"' + text.replace('"', '""') + '"'
    return text
