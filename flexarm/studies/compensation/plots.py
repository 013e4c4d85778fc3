"""The compensation pictures (matplotlib Agg).

:func:`plot_compensation`: left, the top view (base x-y) of every procedure: the
programmed path, and the loaded path of the programmed and of the compensated program
with the deviation exaggerated (the factor in the title).  Right, for a circle the polar
deviation about the programmed circle as the circle test draws it
(:func:`~flexarm.studies.contact.plots.plot_circle_polar`), otherwise the deviation
along the path; samples of motions where a joint law jumps are dotted.

:func:`plot_history`: the loop's error history (:class:`~.history.PathHistory`): the
RMS and the peak deviation of every step as bars (log scale, the gain over the first
step written on them), and the deviation of each step's measured path, polar about the
programmed circle (or along the path).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.plotting import pyplot, save_figure

__all__ = ["plot_compensation", "plot_history"]


def _angles(run) -> np.ndarray:
    """(n,) polar angle [rad] of a run's loaded points about its programmed circle."""
    c, n, _r = run.circle
    ref = np.eye(3)[0] if abs(n[0]) < 0.9 else np.eye(3)[1]
    e1 = ref - (ref @ n) * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    d = run.points - c
    return np.arctan2(d @ e2, d @ e1)


def _polar(ax, curves, fontsize: int) -> None:
    """Radial deviation [µm] of the runs ``curves`` ((run, colour, label), the first the
    largest) about their programmed circle, on polar axes ``ax``, around a circle of
    1.5 times the first's largest deviation; samples where a joint law jumps dotted."""
    first = curves[0][0]
    span_um = max(np.abs(first.radial).max() * 1e6, 1.0)
    off = 1.5 * span_um
    for run, colour, label in curves:
        order = np.argsort(_angles(run))
        ang, rad = _angles(run)[order], off + run.radial[order] * 1e6
        ax.plot(ang, rad, color=colour, lw=1, label=f"{label}: RMS {run.rms() * 1e6:.0f} µm")
        if run.is_jump is not None and run.is_jump.any():
            jump = run.is_jump[order]
            ax.plot(ang[jump], rad[jump], ".", color="k", ms=2, label="a joint law jumps")
    ax.set_ylim(0, off + span_um * 1.1)
    ax.set_yticks([off - span_um, off, off + span_um])
    ax.set_yticklabels([f"{-span_um:.0f}", "0", f"+{span_um:.0f}"])
    ax.set_title(f"{first.name}: radial deviation [µm] (R = {first.circle[2] * 1e3:.1f} mm)",
                 fontsize=fontsize)


def _along(ax, curves) -> None:
    """Distance from the programmed path [mm] along the path of the runs ``curves``
    ((run, colour, label))."""
    for run, colour, label in curves:
        s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(run.points, axis=0), axis=1))]
        ax.plot(s * 1e3, np.linalg.norm(run.deviation, axis=1) * 1e3, color=colour, lw=1,
                label=label)
    ax.set_xlabel("path length [mm]")
    ax.set_ylabel("distance from the programmed path [mm]")
    ax.grid(True)
    ax.legend(fontsize=7)


def plot_compensation(result, path) -> Path:
    """Write the picture of a :class:`~.result.CompensationResult` to ``path`` (PNG).

    Examples
    --------
    >>> import tempfile, os
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> from flexarm.studies.compensation.workflow import compensate
    >>> res = compensate(THESIS_RAPID, force="ballbar:800N", procs=["Path_30"], step_mm=10)
    >>> out = plot_compensation(res, os.path.join(tempfile.mkdtemp(), "c.png"))
    >>> out.stat().st_size > 10_000
    True
    """
    plt = pyplot()
    before, after = result.runs_before, result.runs_after
    circle = next((k for k, r in enumerate(before) if r.circle is not None), None)
    fig = plt.figure(figsize=(12, 5.8))
    top = fig.add_subplot(1, 2, 1)
    span = max(max(np.ptp(r.programmed[:, :2], axis=0).max() for r in before), 1e-3)
    dmax = max(max(np.linalg.norm(r.deviation, axis=1).max() for r in before), 1e-12)
    k = 0.1 * span / dmax
    for i, (b, a) in enumerate(zip(before, after, strict=True)):
        P = b.programmed * 1e3
        top.plot(P[:, 0], P[:, 1], "k--", lw=0.8, label="programmed" if i == 0 else None)
        for run, style, what in ((b, "-", "programmed"), (a, "-", "compensated")):
            Q = (run.points - run.deviation + k * run.deviation) * 1e3
            top.plot(Q[:, 0], Q[:, 1], style, lw=1.2, color="C3" if what == "programmed"
                     else "C2", label=f"loaded, {what} targets" if i == 0 else None)
    top.set_aspect("equal", adjustable="datalim")
    top.set_xlabel("x [mm]")
    top.set_ylabel("y [mm]")
    top.set_title(f"top view, deviation x{k:.0f}", fontsize=10)
    top.legend(fontsize=7)
    if circle is not None:
        ax = fig.add_subplot(1, 2, 2, projection="polar")
        b, a = before[circle], after[circle]
        _polar(ax, [(b, "C3", "programmed"), (a, "C2", "compensated")], 10)
        ax.legend(loc="lower right", fontsize=7, bbox_to_anchor=(1.15, -0.12))
    else:
        _along(fig.add_subplot(1, 2, 2),
               [(r, c, f"{r.name} {w}") for b, a in zip(before, after, strict=True)
                for r, c, w in ((b, "C3", "before"), (a, "C2", "after"))])
    fig.suptitle(f"{result.model}; {result.force}", fontsize=9)
    return save_figure(fig, path, dpi=110, tight=False, bbox_inches="tight")


def _bars(ax, history, key: str, title: str) -> None:
    """Grouped bars of ``key`` [mm]: one group per procedure, one bar per step."""
    figures = history.figures()
    labels, procs = history.labels, history.procedures
    width = 0.8 / len(labels)
    for i, label in enumerate(labels):
        for j, proc in enumerate(procs):
            f = next((f for f in figures if f["step"] == label and f["procedure"] == proc), None)
            if f is None:
                continue
            x = j + (i - (len(labels) - 1) / 2) * width
            ax.bar(x, f[key] * 1e3, width, color=f"C{i}", label=label if j == 0 else None)
            if i > 0 and np.isfinite(f["gain"]) and key == "rms":
                ax.text(x, f[key] * 1e3, f"{f['gain']:.0f}x", ha="center", va="bottom",
                        fontsize=7)
    ax.set_yscale("log")
    ax.set_xticks(range(len(procs)), procs, fontsize=8)
    ax.set_ylabel(f"{title} [mm]")
    ax.grid(True, axis="y", which="both", alpha=0.3)


def plot_history(history, path) -> Path:
    """Write the error history of a :class:`~.history.PathHistory` to ``path``.

    Examples
    --------
    >>> import tempfile, os
    >>> from flexarm.studies.compensation.lab.history import PathHistory
    >>> from flexarm.studies.compensation.lab.measured import MeasuredPath
    >>> from flexarm.studies.compensation.solve.runs import PathRun, circle_of
    >>> phi = np.linspace(0, 2 * np.pi, 90)
    >>> ref = np.c_[1 + 0.1 * np.cos(phi), 0.1 * np.sin(phi), np.zeros(90)]
    >>> runs = [PathRun("Path_30", ref, ref * s, ref * s - ref, circle_of(ref))
    ...         for s in (1.001, 1.0001)]
    >>> h = PathHistory(("before", "after"), tuple(MeasuredPath(r, "m.csv", "p.mod")
    ...                                            for r in runs), "p.mod")
    >>> plot_history(h, os.path.join(tempfile.mkdtemp(), "h.png")).stat().st_size > 10_000
    True
    """
    plt = pyplot()
    fig = plt.figure(figsize=(14, 4.8))
    kind = "radial deviation" if any(m.run.circle is not None for m in history.measured) \
        else "distance from the path"
    _bars(fig.add_subplot(1, 3, 1), history, "rms", f"RMS {kind}")
    peak = fig.add_subplot(1, 3, 2)
    _bars(peak, history, "peak", f"peak {kind}")
    fig.legend(*peak.get_legend_handles_labels(), loc="upper center", fontsize=8,
               ncol=len(history.labels), bbox_to_anchor=(0.36, 0.02))
    labels = history.labels
    circle = next((m.run for m in history.measured if m.run.circle is not None), None)
    if circle is not None:
        ax = fig.add_subplot(1, 3, 3, projection="polar")
        _polar(ax, [(m.run, f"C{labels.index(step)}", step)
                    for step, m in zip(history.steps, history.measured, strict=True)
                    if m.run.name == circle.name], 9)
        ax.legend(loc="upper center", fontsize=7, bbox_to_anchor=(0.5, -0.08))
    else:
        _along(fig.add_subplot(1, 3, 3),
               [(m.run, f"C{labels.index(step)}", f"{m.run.name}, {step}")
                for step, m in zip(history.steps, history.measured, strict=True)])
    fig.suptitle(f"measured at each step, against {history.program}", fontsize=9)
    fig.subplots_adjust(wspace=0.3)
    return save_figure(fig, path, dpi=110, tight=False, bbox_inches="tight")
