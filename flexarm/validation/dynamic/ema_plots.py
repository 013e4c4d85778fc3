"""Pictures of an EMA run: the stabilisation diagram and the synthesised FRFs."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.plotting import pyplot, save_figure

__all__ = ["plot_stabilisation", "plot_synthesis"]


def plot_stabilisation(path, pm) -> Path:
    """Poles per model order (grey: all, blue: stable, red: picked; dotted: where the
    sub-bands of a split band meet) over the summed FRF magnitude of the pose
    (:class:`~.ema.PoseModes` ``pm``)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for j, (f, _) in enumerate(pm.all_poles):
        ax.plot(f, np.full(len(f), j + 1), ".", ms=2, color="0.75")
    s = pm.stable
    ax.plot(s[:, 2], s[:, 0] + 1, "o", ms=3, mfc="none", color="C0", label="stable")
    for b in pm.bands[1:]:  # where a split band's fits meet
        ax.axvline(b.core_lo, color="0.5", lw=0.8, ls=":")
    for f in pm.freq_hz:
        ax.axvline(f, color="C3", lw=0.8)
    ax.set_xlim(pm.frf.freq_hz[0], pm.frf.freq_hz[-1])
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax2 = ax.twinx()
    ax2.semilogy(pm.frf.freq_hz, np.abs(pm.frf.H).sum(axis=0), color="k", lw=0.8)
    ax2.set_ylabel("sum |H| [m/N]")
    ax.set_title(f"stabilisation diagram, pose {pm.frf.pose} (red: picked modes)",
                 fontsize=9)
    ax.legend(loc="upper left", fontsize=7)
    return save_figure(fig, path, dpi=100)


def plot_synthesis(path, pm, n_curves: int = 3) -> Path:
    """Measured and synthesised receptance (magnitude and phase) of the driving-point
    FRFs, or of the first ``n_curves`` FRFs without one."""
    plt = pyplot()
    frf = pm.frf
    drive = np.flatnonzero((frf.out_nodes == frf.in_nodes) & (frf.out_dirs == frf.in_dirs))
    rows = drive[:n_curves] if drive.size else np.flatnonzero(np.abs(frf.H).max(axis=1) > 0)[
        :n_curves]
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 5), sharex=True,
                                 gridspec_kw={"height_ratios": [2, 1]})
    for c, k in enumerate(rows):
        label = f"{frf.out_nodes[k]}{frf.out_dirs[k]}/{frf.in_nodes[k]}{frf.in_dirs[k]}"
        a1.semilogy(frf.freq_hz, np.abs(frf.H[k]), ".", ms=2, color=f"C{c}",
                    label=f"{label} measured")
        a1.semilogy(frf.freq_hz, np.abs(pm.synthesised[k]), "-", lw=1, color=f"C{c}",
                    label=f"{label} modal model")
        a2.plot(frf.freq_hz, np.degrees(np.angle(frf.H[k])), ".", ms=2, color=f"C{c}")
        a2.plot(frf.freq_hz, np.degrees(np.angle(pm.synthesised[k])), "-", lw=1,
                color=f"C{c}")
    a1.set_ylabel("|H| [m/N]")
    a2.set_ylabel("phase [deg]")
    a2.set_xlabel("frequency [Hz]")
    a1.legend(fontsize=6, ncol=2)
    a1.set_title(f"synthesised vs measured FRF, pose {frf.pose}", fontsize=9)
    return save_figure(fig, path, dpi=100)
