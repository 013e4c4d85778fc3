"""PNG plots of the contact applications (matplotlib Agg, imported on use)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.plotting import pyplot, save_figure
from .ball_bar import CirclePrediction
from .chatter_map import ChatterMap

__all__ = ["plot_circle_top", "plot_circle_polar", "plot_circle_z", "plot_chatter_time",
           "plot_chatter_orbit", "plot_chatter_map"]



def _save(fig, path) -> Path:
    return save_figure(fig, path, dpi=110, tight=False, bbox_inches="tight")


def _runs(pred: CirclePrediction, label: str, compare) -> list:
    """``[(label, prediction, line style)]``: the main model solid, the others dashed."""
    styles = ("--", ":", "-.")
    return [(label, pred, "-")] + [(lab, p, styles[i % 3])
                                   for i, (lab, p) in enumerate(compare)]


def _colour(i: int):
    return f"C{i % 10}"


def plot_circle_top(pred: CirclePrediction, path, scale: float | None = None,
                    label: str = "", compare=()) -> Path:
    """Top view (base x-y) of the nominal path and the loaded paths, deviation exaggerated.

    ``scale`` multiplies the deviation (default: the largest deviation drawn as 20 %
    of the radius).  ``compare`` = ``[(label, CirclePrediction)]`` of other models on
    the same setup and loads, drawn dashed in the same colours; ``label`` names ``pred``.
    """
    plt = pyplot()
    s = pred.setup
    runs = _runs(pred, label, compare)
    dmax = max(np.abs(p.deviation).max() for _l, p, _s in runs)
    k = scale if scale is not None else (0.2 * s.radius / dmax if dmax > 0 else 1.0)
    fig, ax = plt.subplots(figsize=(6, 6))
    P = s.points * 1e3
    ax.plot(P[:, 0], P[:, 1], "k--", lw=1, label="nominal")
    for lab, p, ls in runs:
        for i, (F, d) in enumerate(zip(p.loads, p.deviation, strict=True)):
            if F > 0:
                Q = P + k * d * 1e3
                ax.plot(Q[:, 0], Q[:, 1], ls, color=_colour(i), label=f"{lab} {F:.0f} N".strip())
    ax.plot(*(s.pivot[:2] * 1e3), "k+", ms=12, label="pivot")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(f"{s.name}: top view, deviation x{k:.0f} ({'pull' if pred.is_pull else 'push'})")
    ax.legend(fontsize=7)
    return _save(fig, path)


def plot_circle_polar(pred: CirclePrediction, path, measured=None, label: str = "",
                      compare=()) -> Path:
    """ISO 230-4-style polar plot of the ball-bar reading (bar-length change) [µm].

    The radius axis is ``offset + deviation`` so that negative values stay visible;
    ``measured`` = (angle [rad], bar [m], normal [m], force [N]) from
    :func:`~flexarm.studies.contact.ball_bar.measured_deviation`, drawn as dots
    (coloured by force).  ``compare`` as in :func:`plot_circle_top`.
    """
    plt = pyplot()
    s = pred.setup
    runs = _runs(pred, label, compare)
    span = max(max(np.abs(p.bar).max() for _l, p, _s in runs) * 1e6, 1.0)
    if measured is not None:
        span = max(span, np.abs(measured[1]).max() * 1e6)
    off = 1.5 * span
    fig = plt.figure(figsize=(6.5, 6.5))
    ax = fig.add_subplot(projection="polar")
    a = s.angles
    for lab, p, ls in runs:
        for i, (F, b) in enumerate(zip(p.loads, p.bar * 1e6, strict=True)):
            ax.plot(a, off + b, ls, color=_colour(i), label=f"{lab} {F:.0f} N".strip())
    if measured is not None:
        _measured_dots(ax, pred, measured[0], off + measured[1] * 1e6, measured[3])
    ax.set_ylim(0, off + span * 1.1)
    ax.set_yticks([off - span, off, off + span])
    ax.set_yticklabels([f"{-span:.0f}", "0", f"+{span:.0f}"])
    ax.set_title(f"{s.name}: ball-bar length deviation [µm] (R = {s.radius * 1e3:.1f} mm)")
    ax.legend(loc="lower right", fontsize=7, bbox_to_anchor=(1.15, -0.1))
    return _save(fig, path)


def _measured_dots(ax, pred: CirclePrediction, x, y, force) -> None:
    """Measured points, in the colour of the nearest predicted load level."""
    force = np.asarray(force, dtype=float)
    for F in np.unique(force):
        i = int(np.argmin(np.abs(pred.loads - F)))
        sel = force == F
        ax.plot(np.asarray(x)[sel], np.asarray(y)[sel], "o", ms=3, mfc="none",
                color=_colour(i) if np.isclose(pred.loads[i], F) else "k",
                label=f"measured {F:.0f} N")


def plot_circle_z(pred: CirclePrediction, path, measured=None, label: str = "",
                  compare=()) -> Path:
    """Deviation along the circle normal (base z for horizontal circles) vs polar angle."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    order = np.argsort(pred.setup.angles)  # the path starts anywhere: plot by angle
    a = np.degrees(pred.setup.angles)[order]
    for lab, p, ls in _runs(pred, label, compare):
        for i, (F, z) in enumerate(zip(p.loads, p.normal[:, order], strict=True)):
            ax.plot(a, z * 1e3, ls, color=_colour(i), lw=1, label=f"{lab} {F:.0f} N".strip())
    if measured is not None:
        _measured_dots(ax, pred, np.degrees(measured[0]), measured[2] * 1e3, measured[3])
    ax.set_xlabel("polar angle [deg]")
    ax.set_ylabel("deviation along circle normal [mm]")
    ax.set_title(f"{pred.setup.name}: out-of-plane deviation")
    ax.grid(True)
    ax.legend(fontsize=7)
    return _save(fig, path)


def plot_chatter_time(runs, path) -> Path:
    """Time histories ``runs = [(label, t (n,), x (n, 2) [m])]`` of the plane coordinates,
    drawn in µm."""
    plt = pyplot()
    fig, axes = plt.subplots(len(runs), 1, figsize=(8, 2.8 * len(runs)), squeeze=False)
    for ax, (label, t, x) in zip(axes[:, 0], runs, strict=True):
        ax.plot(t, x[:, 0] * 1e6, label="x1 (e1)")
        ax.plot(t, x[:, 1] * 1e6, label="x2 (e2)")
        ax.set_ylabel("displacement [µm]")
        ax.set_title(label, fontsize=9)
        ax.grid(True)
        ax.legend(fontsize=8)
    axes[-1, 0].set_xlabel("time [s]")
    return _save(fig, path)


def plot_chatter_orbit(runs, path) -> Path:
    """Tool orbits in the machining plane, one panel per run (thesis Figs 4.30/4.31)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(runs), figsize=(5 * len(runs), 5), squeeze=False)
    for ax, (label, _t, x) in zip(axes[0], runs, strict=True):
        ax.plot(x[:, 0] * 1e6, x[:, 1] * 1e6, lw=0.6, label="tool orbit")
        ax.plot(x[0, 0] * 1e6, x[0, 1] * 1e6, "ro", ms=4, label="start (disturbance)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x1 [µm]")
        ax.set_ylabel("x2 [µm]")
        ax.set_title(label, fontsize=8)
        ax.legend(fontsize=7)
    return _save(fig, path)


def plot_chatter_map(cm: ChatterMap, path, label: str = "") -> Path:
    """Heat map of log10(limit K_c b) over (q2, q3): light grey = no limit, white =
    unreachable, hatched = never recommended (joint limit, singularity), red stars = the
    recommended poses; ``label`` (model and pose) heads the title."""
    from matplotlib.patches import Patch

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 5.5))
    val = np.where(np.isinf(cm.kcb), np.nan, np.log10(cm.kcb))
    ext = np.degrees([cm.q3[0], cm.q3[-1], cm.q2[0], cm.q2[-1]])
    ax.imshow(np.where(np.isinf(cm.kcb), 1.0, np.nan), origin="lower", extent=ext,
              aspect="auto", cmap="Greys", vmin=0, vmax=4)
    im = ax.imshow(val, origin="lower", extent=ext, aspect="auto", cmap="viridis")
    fig.colorbar(im, label="log10 limit K_c b [N/m]")
    handles = [Patch(facecolor="0.85", label="no limit (stable for every K_c b)")]
    if cm.is_excluded is not None and cm.is_excluded.any():
        ax.contourf(np.degrees(cm.q3), np.degrees(cm.q2), cm.is_excluded.astype(float),
                    levels=[0.5, 1.5], colors="none", hatches=["//"])
        handles.append(Patch(facecolor="none", hatch="//", label="joint limit or singular: "
                                                                 "not recommended"))
    best = cm.best(3)
    if best:
        handles += ax.plot([b3 for _b2, b3, _k in best], [b2 for b2, _b3, _k in best], "r*",
                           ms=10, ls="none", label="recommended poses")
    ax.legend(handles=handles, fontsize=7, loc="upper right")
    ax.set_xlabel("q3 [deg]")
    ax.set_ylabel("q2 [deg]")
    ax.set_title(f"{label + ': ' if label else ''}mode-coupling limit, force at "
                 f"{cm.dir_deg:.0f} deg", fontsize=10)
    return _save(fig, path)
