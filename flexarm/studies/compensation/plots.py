"""The compensation picture: top view and deviation, before and after (matplotlib Agg).

Left, the top view (base x-y) of every procedure: the programmed path, and the loaded
path of the programmed and of the compensated program with the deviation exaggerated
(the factor in the title).  Right, for a circle the polar deviation about the programmed
circle as the circle test draws it
(:func:`~flexarm.studies.contact.plots.plot_circle_polar`), otherwise the deviation
along the path; samples of motions where a joint law jumps are dotted.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.plotting import pyplot, save_figure

__all__ = ["plot_compensation"]


def _angles(run) -> np.ndarray:
    """(n,) polar angle [rad] of a run's loaded points about its programmed circle."""
    c, n, _r = run.circle
    ref = np.eye(3)[0] if abs(n[0]) < 0.9 else np.eye(3)[1]
    e1 = ref - (ref @ n) * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    d = run.points - c
    return np.arctan2(d @ e2, d @ e1)


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
        span_um = max(np.abs(b.radial).max() * 1e6, 1.0)
        off = 1.5 * span_um
        for run, colour, what in ((b, "C3", "programmed"), (a, "C2", "compensated")):
            order = np.argsort(_angles(run))
            ang = _angles(run)[order]
            ax.plot(ang, off + run.radial[order] * 1e6, color=colour,
                    label=f"{what}: RMS {run.rms() * 1e6:.0f} µm")
            if run.is_jump is not None and run.is_jump.any():
                ax.plot(ang[run.is_jump[order]], off + run.radial[order][run.is_jump[order]]
                        * 1e6, ".", color="k", ms=2, label="a joint law jumps")
        ax.set_ylim(0, off + span_um * 1.1)
        ax.set_yticks([off - span_um, off, off + span_um])
        ax.set_yticklabels([f"{-span_um:.0f}", "0", f"+{span_um:.0f}"])
        ax.set_title(f"{b.name}: radial deviation [µm] (R = {b.circle[2] * 1e3:.1f} mm)",
                     fontsize=10)
        ax.legend(loc="lower right", fontsize=7, bbox_to_anchor=(1.15, -0.12))
    else:
        ax = fig.add_subplot(1, 2, 2)
        for b, a in zip(before, after, strict=True):
            for run, colour in ((b, "C3"), (a, "C2")):
                s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(run.points, axis=0), axis=1))]
                ax.plot(s * 1e3, np.linalg.norm(run.deviation, axis=1) * 1e3, color=colour,
                        lw=1, label=f"{run.name} {'before' if run is b else 'after'}")
        ax.set_xlabel("path length [mm]")
        ax.set_ylabel("distance from the programmed path [mm]")
        ax.grid(True)
        ax.legend(fontsize=7)
    fig.suptitle(f"{result.model}; {result.force}", fontsize=9)
    return save_figure(fig, path, dpi=110, tight=False, bbox_inches="tight")
