"""The modes of an arm at one pose, whatever model computed them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.notebook import data_frame, span
from ..fe.typing import FloatArray

__all__ = ["Modes"]


@dataclass(frozen=True)
class Modes:
    """Modes of the arm at one pose.

    Attributes
    ----------
    freq_hz : (n,) float
        Natural frequencies [Hz], ascending.
    shapes : (n_x, n) float
        Mass-normalised mode shapes on the independent coordinates; the largest
        entry of each is positive (deterministic sign).
    tcp_shapes : (6, n) float
        TCP motion of each mode shape.
    damping : (n,) float
        Modal damping ratios [-] (joint ratios weighted by modal strain energy).
    energy : (n_joints, n) float
        Share of each mode's strain energy stored in each joint spring [-].
    coordinate_names : list of str
    """

    freq_hz: FloatArray
    shapes: FloatArray
    tcp_shapes: FloatArray
    damping: FloatArray
    energy: FloatArray
    coordinate_names: list

    @property
    def omega(self) -> FloatArray:
        """(n,) angular frequencies [rad/s]."""
        return 2 * np.pi * self.freq_hz

    def __repr__(self) -> str:
        """One line: mode count, frequency range [Hz], damping range [%], coordinates.

        Examples
        --------
        >>> Modes(np.array([7.5, 16.0]), np.eye(3, 2), np.zeros((6, 2)),
        ...       np.array([0.02, 0.03]), np.full((2, 2), 0.5), ["a", "b", "c"])
        Modes(2 modes, 7.5–16 Hz, damping 2–3 %, 3 coordinates, 2 joints)
        """
        return (f"Modes({len(self.freq_hz)} modes, {span(self.freq_hz, 'Hz')}, damping "
                f"{span(np.asarray(self.damping) * 100, '%', '{:.3g}')}, "
                f"{np.shape(self.shapes)[0]} coordinates, {np.shape(self.energy)[0]} joints)")

    def to_dataframe(self, joint_names=None):
        """``pandas.DataFrame``, one row per mode: ``mode`` (from 1), ``f_Hz``, ``zeta``
        (damping ratio [-]) and ``energy_share_<joint>`` (share of the mode's strain
        energy in each joint spring [-]; joints named ``joint_1`` … unless
        ``joint_names`` is given), the columns of ``mode_energy.csv``.

        Examples
        --------
        >>> m = Modes(np.array([7.5, 16.0]), np.eye(3, 2), np.zeros((6, 2)),
        ...           np.array([0.02, 0.03]), np.array([[0.9, 0.2], [0.1, 0.8]]), ["a", "b"])
        >>> m.to_dataframe().columns.tolist()
        ['mode', 'f_Hz', 'zeta', 'energy_share_joint_1', 'energy_share_joint_2']
        """
        energy = np.asarray(self.energy)
        if joint_names is None:
            joint_names = [f"joint_{k + 1}" for k in range(energy.shape[0])]
        if len(joint_names) != energy.shape[0]:
            raise ValueError(f"joint_names must name {energy.shape[0]} joints, "
                             f"got {len(joint_names)}")
        columns = {"mode": np.arange(1, len(self.freq_hz) + 1), "f_Hz": self.freq_hz,
                   "zeta": self.damping}
        columns.update({f"energy_share_{n}": e for n, e in zip(joint_names, energy,
                                                               strict=True)})
        return data_frame(columns)

    def text(self, joint_names, n: int = 24) -> str:
        """Table of the first ``n`` modes: frequency [Hz], damping ratio and the energy
        share per joint (each column as wide as its joint's full name); a last line says
        how many more there are.

        Examples
        --------
        >>> m = Modes(np.array([7.5]), np.eye(3, 1), np.zeros((6, 1)), np.array([0.02]),
        ...           np.array([[0.75], [0.25]]), ["a", "b"])
        >>> print(m.text(["shoulder_pan_joint", "j2"]))
        mode    freq_Hz    zeta  shoulder_pan_joint      j2
           1      7.500  0.0200               0.750   0.250
        """
        names = list(joint_names)
        widths = [max(7, len(name)) for name in names]
        widths += [7] * (len(self.energy) - len(widths))  # shares of unnamed springs
        lines = [f"{'mode':>4s} {'freq_Hz':>10s} {'zeta':>7s}  "
                 + " ".join(f"{name:>{w}s}" for name, w in zip(names, widths, strict=False))]
        for r, f in enumerate(self.freq_hz[:n]):
            shares = " ".join(f"{e:{w}.3f}"
                              for e, w in zip(self.energy[:, r], widths, strict=False))
            lines.append(f"{r + 1:4d} {f:10.3f} {self.damping[r]:7.4f}  {shares}")
        if len(self.freq_hz) > n:
            lines.append(f"... {len(self.freq_hz) - n} more modes up to "
                         f"{self.freq_hz[-1]:.0f} Hz")
        return "\n".join(lines)
