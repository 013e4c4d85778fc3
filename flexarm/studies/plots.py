"""PNG plots of arm analyses (matplotlib imported inside, Agg backend)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..fe.plotting import pyplot
from ..fe.typing import FloatArray

__all__ = ["plot_frf", "plot_mode_energy"]



def plot_frf(path, freq_hz: FloatArray, H: FloatArray, title: str = "") -> Path:
    """Bode plot of the direct TCP receptances H_xx, H_yy, H_zz [mm/N] (nf, 6, 6)."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    for d, name in enumerate("xyz"):
        h = H[:, d, d]
        a1.loglog(freq_hz, np.abs(h) * 1e3, label=f"{name}/F{name}")
        a2.semilogx(freq_hz, np.degrees(np.angle(h)), label=name)
    a1.set_ylabel("|H| [mm/N]")
    a2.set_ylabel("phase [deg]")
    a2.set_xlabel("frequency [Hz]")
    a1.legend()
    a1.grid(True, which="both", alpha=0.3)
    a2.grid(True, which="both", alpha=0.3)
    a1.set_title(title or "TCP receptance")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def plot_mode_energy(path, freq_hz: FloatArray, energy: FloatArray, joint_names) -> Path:
    """Stacked bars: share of each mode's strain energy per joint."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    x = np.arange(len(freq_hz))
    bottom = np.zeros(len(freq_hz))
    for name, e in zip(joint_names, energy, strict=True):
        ax.bar(x, e, bottom=bottom, label=name)
        bottom += e
    ax.set_xticks(x, [f"{f:.1f}" for f in freq_hz], rotation=45)
    ax.set_xlabel("mode frequency [Hz]")
    ax.set_ylabel("strain energy share [-]")
    ax.legend(fontsize=7, ncol=3)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
