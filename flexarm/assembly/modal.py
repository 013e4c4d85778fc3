"""The modes of an arm at one pose, whatever model computed them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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

    def text(self, joint_names, n: int = 24) -> str:
        """Table of the first ``n`` modes: frequency [Hz], damping ratio and the energy
        share per joint; a last line says how many more there are."""
        lines = [f"{'mode':>4s} {'freq_Hz':>10s} {'zeta':>7s}  "
                 + " ".join(f"{name[-7:]:>7s}" for name in joint_names)]
        for r, f in enumerate(self.freq_hz[:n]):
            shares = " ".join(f"{e:7.3f}" for e in self.energy[:, r])
            lines.append(f"{r + 1:4d} {f:10.3f} {self.damping[r]:7.4f}  {shares}")
        if len(self.freq_hz) > n:
            lines.append(f"... {len(self.freq_hz) - n} more modes up to "
                         f"{self.freq_hz[-1]:.0f} Hz")
        return "\n".join(lines)
