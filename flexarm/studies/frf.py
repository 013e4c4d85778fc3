"""The TCP receptance of an arm at a pose over a frequency band (Bode data)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..assembly.analyses import frf
from ..assembly.system import ArmModel
from ..fe.files import atomic_path, writes_folder
from ..fe.typing import ArrayLike, FloatArray
from .plots import plot_frf

__all__ = ["FrfReport", "frf_report"]

_XYZ = "xyz"


@dataclass(frozen=True, eq=False)
class FrfReport:
    """TCP receptance at one pose (base frame, modal damping of the model).

    Attributes
    ----------
    freq_hz : (nf,) float
        Frequencies [Hz] (log-spaced).
    H : (nf, 6, 6) complex
        Receptance [m/N, rad/(N m)] at ``freq_hz``.
    static : (6, 6) float
        Static gain H(0) [m/N, ...] (the TCP compliance).
    title : str
    """

    freq_hz: FloatArray
    H: np.ndarray
    static: FloatArray
    title: str = ""

    def peaks(self) -> list[tuple[str, float, float]]:
        """Per direction x, y, z: (name, frequency [Hz], ``|H|`` [m/N]) of the largest peak."""
        out = []
        for d, name in enumerate(_XYZ):
            k = int(np.argmax(np.abs(self.H[:, d, d])))
            out.append((name, float(self.freq_hz[k]), float(abs(self.H[k, d, d]))))
        return out

    def text(self) -> str:
        """Static gain and largest peak per direction (mm/kN, Hz)."""
        lines = ["direction  static_gain_mm_per_kN  peak_Hz  peak_mm_per_kN"]
        lines += [f"{name:>9s}  {self.static[d, d] * 1e6:21.4f}  {f:7.2f}  {h * 1e6:14.4f}"
                  for d, (name, f, h) in enumerate(self.peaks())]
        return "\n".join(lines)

    @writes_folder()
    def write(self, folder) -> list[Path]:
        """``frf_bode.png`` and ``frf.csv`` in ``folder``.

        ``frf.csv``: ``freq_Hz``, then the real and imaginary parts of the translational
        receptance ``H_ij`` [m/N] (TCP displacement along ``i`` per force along ``j``, base
        frame): the driving points ``xx``, ``yy``, ``zz`` first (the curves of the plot),
        then the cross terms ``xy``, ``xz``, ``yx``, ``yz``, ``zx``, ``zy``.
        """
        folder = Path(folder)
        png = plot_frf(folder / "frf_bode.png", self.freq_hz, self.H, self.title)
        pairs = [(d, d) for d in range(3)] + [(i, j) for i in range(3) for j in range(3)
                                              if i != j]
        cols = ["freq_Hz"] + [f"{p}_H{_XYZ[i]}{_XYZ[j]}_m_per_N" for i, j in pairs
                              for p in ("re", "im")]
        rows = np.column_stack([self.freq_hz] + [part(self.H[:, i, j]) for i, j in pairs
                                                 for part in (np.real, np.imag)])
        csv = folder / "frf.csv"
        with atomic_path(csv) as tmp:
            tmp.write_text(",".join(cols) + "\n" + "".join(
                ",".join(f"{v:.10g}" for v in r) + "\n" for r in rows))
        return [png, csv]


def frf_report(arm: ArmModel, q: ArrayLike, fmax: float = 100.0, n: int = 600,
               fmin: float = 0.5, title: str = "") -> FrfReport:
    """TCP receptance at pose ``q`` (n,) [rad] on ``n`` log-spaced frequencies from
    ``fmin`` to ``fmax`` [Hz], with the static gain.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> rep = frf_report(two_link_arm(), [0.0, 0.5], fmax=50.0, n=100)
    >>> rep.H.shape
    (100, 6, 6)
    """
    if not 0 < fmin < fmax:
        raise ValueError(f"need 0 < fmin < fmax [Hz], got {fmin:g} and {fmax:g}")
    f = np.geomspace(fmin, fmax, n)
    H = frf(arm, q, np.concatenate([[0.0], f]))
    return FrfReport(f, H[1:], H[0].real, title)
