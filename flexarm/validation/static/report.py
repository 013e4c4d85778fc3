"""The report of a static comparison (``compare -o``): ``errors.csv``, ``residuals.csv``
and three pictures, written together or not at all (through a temporary folder,
:func:`~flexarm.fe.files.writes_folder`).

Pictures stay readable and quick at any size: up to ``tol.plot_max_panels`` series the
deflection picture has a panel per series; past that one per pose and load direction;
a panel with more than ``tol.plot_max_points`` readings shows, per load level, the
median and the 5-95 % band of the measured deflections and the model's median instead
of every point.  The residual picture turns into a density past the same count
(:func:`~.plots.plot_residual_vs_torque`).
"""

from __future__ import annotations

import csv
from dataclasses import fields
from pathlib import Path

import numpy as np

from ...fe.files import writes_folder
from ...fe.plotting import picture_from_inputs, pyplot, save_figure
from ..tolerances import tol
from .plots import plot_residual_vs_torque, write_residuals

__all__ = ["write_report", "write_rows", "plot_deflection", "binned"]


def write_rows(path, row_type: type, rows) -> None:
    """Write the dataclass ``rows`` (instances of ``row_type``) as CSV: one column per
    field, in field order; values as :mod:`csv` writes them (``repr`` of floats)."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([f.name for f in fields(row_type)])
        w.writerows([getattr(r, f.name) for f in fields(row_type)] for r in rows)


@writes_folder()
def write_report(folder, cmp) -> list[Path]:
    """Write ``errors.csv``, ``deflection_vs_force.png``, ``residuals.csv``,
    ``residual_vs_torque.png`` and ``residual_by_pose.png`` of the
    :class:`~.compare.Comparison` ``cmp`` into ``folder``, all or none."""
    out = Path(folder)
    pb, data = cmp.problem, cmp.problem.data
    res = data.disp - cmp.predicted
    return [cmp.write_errors(out / "errors.csv"),
            plot_deflection(out / "deflection_vs_force.png", cmp),
            write_residuals(out / "residuals.csv", data.series, pb.tau, res, data.force,
                            data.disp, cmp.predicted),
            plot_residual_vs_torque(out / "residual_vs_torque.png", pb.tau, res,
                                    f"{cmp.model} at {cmp.poses}"),
            _plot_by_pose(out / "residual_by_pose.png", cmp, res * 1e6)]


def binned(x: np.ndarray, y: np.ndarray, n_bins: int = tol.plot_bins):
    """Centres of the bins of ``x`` (n,) and, per bin, the 5 %, 50 % and 95 % points of
    ``y`` (n, k): (m,), (m, k) x 3.  The bins are the distinct values of ``x`` when there
    are at most ``n_bins`` (load levels), else ``n_bins`` equal ones; empty bins are left
    out.

    Examples
    --------
    >>> x = np.repeat([0.0, 100.0], 101)
    >>> y = np.r_[np.arange(101.0), 2 * np.arange(101.0)][:, None]
    >>> centres, lo, mid, hi = binned(x, y)
    >>> centres.tolist(), lo.ravel().tolist(), mid.ravel().tolist(), hi.ravel().tolist()
    ([0.0, 100.0], [5.0, 10.0], [50.0, 100.0], [95.0, 190.0])
    """
    levels = np.unique(x)
    if len(levels) <= n_bins:
        which, centres = np.searchsorted(levels, x), levels
    else:
        edges = np.linspace(levels[0], levels[-1], n_bins + 1)
        which = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, n_bins - 1)
        centres = (edges[:-1] + edges[1:]) / 2
    order = np.argsort(which, kind="stable")
    cuts = np.searchsorted(which[order], np.arange(len(centres) + 1))
    kept = np.flatnonzero(np.diff(cuts) > 0)
    points = [np.percentile(y[order[cuts[b]:cuts[b + 1]]], [5, 50, 95], axis=0) for b in kept]
    lo, mid, hi = (np.array([p[k] for p in points]) for k in range(3))
    return centres[kept], lo, mid, hi


def _panels(cmp) -> tuple[list[tuple[str, np.ndarray]], str]:
    """(title, rows) of each panel, and a note on what was left out."""
    pb = cmp.problem
    if len(pb.groups) <= tol.plot_max_panels:
        return [(str(pb.data.series[g[0]]), g) for g in pb.groups], ""
    names, pose_of = cmp.pose_groups()
    keys = [(names[p], r.dir) for p, r in zip(pose_of.tolist(), cmp.table, strict=True)]
    index = {k: i for i, k in enumerate(dict.fromkeys(keys))}
    of_series = np.array([index[k] for k in keys])
    of_row, counts = of_series[pb.series_id], np.bincount(of_series)
    shown = list(index.items())[:tol.plot_max_panels]
    panels = [(f"{pose} {d} ({counts[i]:,d} series)", np.flatnonzero(of_row == i))
              for (pose, d), i in shown]
    rest = len(index) - len(shown)
    note = f"; {rest} more pose/direction groups in errors.csv" if rest else ""
    return panels, f" ({len(pb.groups):,d} series by pose and load direction{note})"


def plot_deflection(path, cmp) -> Path:
    """``deflection_vs_force.png``: measured (points or bands) and model deflection [mm]
    against the load magnitude [N], one panel per series or per pose and direction."""
    data = cmp.problem.data
    panels, note = _panels(cmp)
    return _draw_deflection(path, np.linalg.norm(data.force, axis=1), data.disp,
                            cmp.predicted, panels, note, f"{cmp.model}, at {cmp.poses}")


@picture_from_inputs
def _draw_deflection(path, fmag, disp, predicted, panels, note: str, what: str) -> Path:
    """:func:`plot_deflection` from plain arrays (keyed by them in the picture cache):
    load magnitudes [N], measured and predicted deflections [m], panels (title, rows)."""
    plt = pyplot()
    cols = min(len(panels), 6)
    rows = -(-len(panels) // cols)
    # a few wide panels when grouped: room for the title of what was grouped
    size = (3 * cols, 2.4 * rows) if not note else (max(3 * cols, 8), max(2.4 * rows, 3.6))
    fig, axes = plt.subplots(rows, cols, figsize=size, squeeze=False)
    for ax, (title, g) in zip(axes.ravel(), panels, strict=False):
        meas, model = disp[g] * 1e3, predicted[g] * 1e3
        if len(g) <= tol.plot_max_points:  # every reading; a series' model as a line
            for k, c in enumerate("xyz"):
                ax.plot(fmag[g], meas[:, k], "o", ms=3, color=f"C{k}", label=f"{c} meas")
                if note:
                    ax.plot(fmag[g], model[:, k], ".", ms=2, color=f"C{k}")
                else:
                    ax.plot(fmag[g], model[:, k], "-", color=f"C{k}")
        else:
            centres, lo, mid, hi = binned(fmag[g], meas)
            model_mid = binned(fmag[g], model)[2]
            for k, c in enumerate("xyz"):
                ax.fill_between(centres, lo[:, k], hi[:, k], color=f"C{k}", alpha=0.25,
                                lw=0, label=f"{c} meas 5-95 %")
                ax.plot(centres, mid[:, k], "o", ms=3, color=f"C{k}")
                ax.plot(centres, model_mid[:, k], "-", color=f"C{k}")
        ax.set_title(title, fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    fig.supylabel("deflection [mm]", fontsize=8)
    axes[0, 0].legend(fontsize=6)
    fig.supxlabel("load |F| [N]  (points: measured, lines: model)" if not note else
                  "load |F| [N]  (points: measured, dots or lines: model; bands: 5-95 % of the "
                  "measured readings where a panel has many)", fontsize=8)
    fig.suptitle(f"TCP deflection, measured vs {what}"
                 + (f"\n{note.strip()}" if note else ""), fontsize=9)
    # Fixed margins: tight_layout over dozens of panels costs seconds per figure.
    bottom, top = (0.4 / rows, 0.25 / rows) if not note else (0.8 / size[1], 0.9 / size[1])
    fig.subplots_adjust(left=0.06 if not note else 0.09, right=0.99, bottom=bottom,
                        top=1 - top, wspace=0.35, hspace=0.45)
    return save_figure(fig, path, dpi=90, tight=False)


def _plot_by_pose(path, cmp, res_um: np.ndarray) -> Path:
    """``residual_by_pose.png``: box plot of |residual| [µm] per pose
    (:meth:`~.compare.Comparison.pose_groups`, ``tol.plot_max_panels`` at most; outliers
    drawn up to ``tol.plot_max_points`` readings)."""
    pb = cmp.problem
    names, pose_of = cmp.pose_groups()
    order = sorted(range(len(names)), key=lambda k: names[k])[:tol.plot_max_panels]
    of_row = pose_of[pb.series_id]
    boxes = [np.abs(res_um[(of_row == k) & ~pb.is_ref]).ravel() for k in order]
    return _draw_by_pose(path, boxes, [names[k] for k in order],
                         len(res_um) > tol.plot_max_points,
                         f"|measured - {cmp.model}| at {cmp.poses}")


@picture_from_inputs
def _draw_by_pose(path, boxes: list[np.ndarray], labels: list[str], many: bool,
                  title: str) -> Path:
    """:func:`_plot_by_pose` from the |residual| [µm] of each pose (keyed by them in the
    picture cache)."""
    fig, ax = pyplot().subplots(figsize=(5, 3))
    ax.boxplot(boxes, showfliers=not many)
    ax.set_xticks(np.arange(1, len(labels) + 1), labels)
    ax.set_ylabel("|residual| [µm]")
    ax.set_xlabel("pose")
    ax.set_title(title
                 + ("\n(whiskers 1.5 IQR, outliers not drawn)" if many else ""), fontsize=9)
    return save_figure(fig, path, dpi=90)
