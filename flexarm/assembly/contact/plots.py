"""PNG plots of the contact applications (matplotlib Agg, imported on use)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .ball_bar import CirclePrediction
from .chatter_map import ChatterMap

__all__ = ["plot_circle_top", "plot_circle_polar", "plot_circle_z", "plot_chatter_time",
           "plot_chatter_orbit", "plot_chatter_map"]


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path) -> Path:
    path = Path(path)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    _plt().close(fig)
    return path


def plot_circle_top(pred: CirclePrediction, path, scale: float | None = None) -> Path:
    """Top view (base x-y) of the nominal path and the loaded paths, deviation exaggerated.

    ``scale`` multiplies the deviation (default: the largest deviation drawn as 20 %
    of the radius).
    """
    plt = _plt()
    s = pred.setup
    dmax = np.abs(pred.deviation).max()
    k = scale if scale is not None else (0.2 * s.radius / dmax if dmax > 0 else 1.0)
    fig, ax = plt.subplots(figsize=(6, 6))
    P = s.points * 1e3
    ax.plot(P[:, 0], P[:, 1], "k--", lw=1, label="nominal")
    for F, d in zip(pred.loads, pred.deviation, strict=True):
        if F > 0:
            Q = P + k * d * 1e3
            ax.plot(Q[:, 0], Q[:, 1], label=f"{F:.0f} N")
    ax.plot(*(s.pivot[:2] * 1e3), "k+", ms=12, label="pivot")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(f"{s.name}: top view, deviation x{k:.0f} ({'pull' if pred.is_pull else 'push'})")
    ax.legend(fontsize=8)
    return _save(fig, path)


def plot_circle_polar(pred: CirclePrediction, path, measured=None) -> Path:
    """ISO 230-4-style polar plot of the ball-bar reading (bar-length change) [um].

    The radius axis is ``offset + deviation`` so that negative values stay visible;
    ``measured`` = (angle [rad], bar [m], normal [m], force [N]) from
    :func:`~flexarm.assembly.contact.ball_bar.measured_deviation`, drawn as dots.
    """
    plt = _plt()
    s = pred.setup
    bar = pred.bar * 1e6
    span = max(np.abs(bar).max(), 1.0)
    if measured is not None:
        span = max(span, np.abs(measured[1]).max() * 1e6)
    off = 1.5 * span
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="polar")
    a = s.angles
    for F, b in zip(pred.loads, bar, strict=True):
        ax.plot(a, off + b, label=f"{F:.0f} N")
    if measured is not None:
        ax.plot(measured[0], off + measured[1] * 1e6, ".", ms=3, label="measured")
    ax.set_ylim(0, off + span * 1.1)
    ax.set_yticks([off - span, off, off + span])
    ax.set_yticklabels([f"{-span:.0f}", "0", f"+{span:.0f}"])
    ax.set_title(f"{s.name}: ball-bar length deviation [um] (R = {s.radius * 1e3:.1f} mm)")
    ax.legend(loc="lower right", fontsize=8)
    return _save(fig, path)


def plot_circle_z(pred: CirclePrediction, path, measured=None) -> Path:
    """Deviation along the circle normal (base z for horizontal circles) vs polar angle."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4))
    a = np.degrees(pred.setup.angles)
    for F, z in zip(pred.loads, pred.normal, strict=True):
        ax.plot(a, z * 1e3, ".", ms=2, label=f"{F:.0f} N")
    if measured is not None:
        ax.plot(np.degrees(measured[0]), measured[2] * 1e3, "k.", ms=2, label="measured")
    ax.set_xlabel("polar angle [deg]")
    ax.set_ylabel("deviation along circle normal [mm]")
    ax.set_title(f"{pred.setup.name}: out-of-plane deviation")
    ax.grid(True)
    ax.legend(fontsize=8)
    return _save(fig, path)


def plot_chatter_time(runs, path) -> Path:
    """Time histories ``runs = [(label, t (n,), x (n, 2))]`` of the plane coordinates [um]."""
    plt = _plt()
    fig, axes = plt.subplots(len(runs), 1, figsize=(8, 2.8 * len(runs)), squeeze=False)
    for ax, (label, t, x) in zip(axes[:, 0], runs, strict=True):
        ax.plot(t, x[:, 0] * 1e6, label="x1 (e1)")
        ax.plot(t, x[:, 1] * 1e6, label="x2 (e2)")
        ax.set_ylabel("[um]")
        ax.set_title(label, fontsize=9)
        ax.grid(True)
        ax.legend(fontsize=8)
    axes[-1, 0].set_xlabel("time [s]")
    return _save(fig, path)


def plot_chatter_orbit(runs, path) -> Path:
    """Tool orbits in the machining plane, one panel per run (thesis Figs 4.30/4.31)."""
    plt = _plt()
    fig, axes = plt.subplots(1, len(runs), figsize=(5 * len(runs), 5), squeeze=False)
    for ax, (label, _t, x) in zip(axes[0], runs, strict=True):
        ax.plot(x[:, 0] * 1e6, x[:, 1] * 1e6, lw=0.6)
        ax.plot(x[0, 0] * 1e6, x[0, 1] * 1e6, "ro", ms=4)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x1 [um]")
        ax.set_ylabel("x2 [um]")
        ax.set_title(label, fontsize=9)
    return _save(fig, path)


def plot_chatter_map(cm: ChatterMap, path) -> Path:
    """Heat map of log10(limit K_c b) over (q2, q3); grey = no limit, white = unreachable."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 5.5))
    val = np.where(np.isinf(cm.kcb), np.nan, np.log10(cm.kcb))
    ext = np.degrees([cm.q3[0], cm.q3[-1], cm.q2[0], cm.q2[-1]])
    ax.imshow(np.where(np.isinf(cm.kcb), 1.0, np.nan), origin="lower", extent=ext,
              aspect="auto", cmap="Greys", vmin=0, vmax=4)
    im = ax.imshow(val, origin="lower", extent=ext, aspect="auto", cmap="viridis")
    fig.colorbar(im, label="log10 limit K_c b [N/m]")
    for b2, b3, _k in cm.best(3):
        ax.plot(b3, b2, "r*", ms=10)
    ax.set_xlabel("q3 [deg]")
    ax.set_ylabel("q2 [deg]")
    ax.set_title(f"mode-coupling limit, force at {cm.dir_deg:.0f} deg (grey: no limit)")
    return _save(fig, path)
