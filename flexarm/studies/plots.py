"""PNG plots of arm analyses (matplotlib imported inside, Agg backend)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..fe.files import atomic_path, writes_folder
from ..fe.plotting import picture_from_inputs, pyplot, save_figure
from ..fe.typing import FloatArray
from ..fe.units import RECEPTANCE_SCALE, RECEPTANCE_UNIT

__all__ = ["plot_frf", "plot_mode_energy", "write_mode_energy", "RECEPTANCE_UNIT",
           "RECEPTANCE_SCALE"]

@picture_from_inputs
def plot_frf(path, freq_hz: FloatArray, H: FloatArray, title: str = "") -> Path:
    """Bode plot of the direct TCP receptances H_xx, H_yy, H_zz (nf, 6, 6) [m/N], drawn
    in :data:`RECEPTANCE_UNIT` (a PNG drawn before from the same inputs is copied)."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    for d, name in enumerate("xyz"):
        h = H[:, d, d]
        a1.loglog(freq_hz, np.abs(h) * RECEPTANCE_SCALE, label=f"H{name}{name} = {name}/F{name}")
        a2.semilogx(freq_hz, np.degrees(np.angle(h)), label=f"H{name}{name}")
    a1.set_ylabel(f"|H| [{RECEPTANCE_UNIT}]")
    a2.set_ylabel("phase [deg]")
    a2.set_xlabel("frequency [Hz]")
    a1.legend()
    a2.legend(fontsize=8)
    a1.grid(True, which="both", alpha=0.3)
    a2.grid(True, which="both", alpha=0.3)
    a1.set_title(title or "TCP receptance")
    return save_figure(fig, path, dpi=100, tight=False)


@writes_folder()
def write_mode_energy(folder, freq_hz: FloatArray, energy: FloatArray, joint_names,
                      title: str = "") -> list[Path]:
    """``mode_energy.csv`` (mode, ``f_Hz``, energy share per joint [-]) and
    ``mode_energy.png`` (:func:`plot_mode_energy`, the same numbers) in ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    csv = folder / "mode_energy.csv"
    cols = ["mode", "f_Hz"] + [f"energy_share_{n}" for n in joint_names]
    rows = np.column_stack([np.arange(1, len(freq_hz) + 1), freq_hz, np.asarray(energy).T])
    with atomic_path(csv) as tmp:
        np.savetxt(tmp, rows, delimiter=",", comments="", fmt="%.10g", header=",".join(cols))
    return [csv, plot_mode_energy(folder / "mode_energy.png", freq_hz, energy, joint_names,
                                  title)]


def plot_mode_energy(path, freq_hz: FloatArray, energy: FloatArray, joint_names,
                     title: str = "") -> Path:
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
    ax.set_title(title or "strain energy per joint of each mode", fontsize=10)
    return save_figure(fig, path, dpi=100)
