"""A TCP impulse on the arm's Exudyn model, read like a hammer test.

A short half-sine force pulse acts at the TCP (base frame, gravity off); Exudyn
integrates the flexible multibody system (implicit trapezoidal rule: no numerical
damping); the TCP response is turned into a receptance ``U(f) / F(f)`` (FFT of response
and force) and compared with our FRF; its peaks give the natural frequencies and the
ring-down of each mode (band-passed) its damping ratio by the logarithmic decrement.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...assembly.analyses import frf, modes
from ...assembly.arm import Arm
from ...fe.typing import ArrayLike, FloatArray
from ..plots import RECEPTANCE_SCALE, RECEPTANCE_UNIT
from .model import ExudynArm, _exudyn, exudyn_arm, simulation_settings

__all__ = ["ImpulseTest", "impulse_response", "impulse_test", "spectrum_peak",
           "log_decrement"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class ImpulseTest:
    """Exudyn's TCP impulse response next to our modal data.

    Attributes
    ----------
    t : (nt,) float
        Time [s].
    u : (nt, 3) float
        TCP displacement [m], base frame.
    force : (nt,) float
        Pulse amplitude [N] along ``direction``.
    direction : (3,) float
        Unit direction of the pulse (base frame).
    freq_hz : (nf,) float
        Frequencies of the measured receptance [Hz].
    H : (nf,) complex
        Measured receptance along ``direction`` [m/N]: ``d . U(f) / F(f)``.
    H_ours : (nf,) complex
        Our FRF along ``direction`` at ``freq_hz`` [m/N].
    peaks_hz, zeta : (k,) float
        Measured peak frequencies [Hz] and log-decrement damping ratios [-] of the first
        ``k`` modes.
    freq_ours, zeta_ours : (k,) float
        Our natural frequencies [Hz] and modal damping ratios [-].
    seconds : float
        Wall time of the Exudyn integration [s].
    """

    t: FloatArray
    u: FloatArray
    force: FloatArray
    direction: FloatArray
    freq_hz: FloatArray
    H: np.ndarray
    H_ours: np.ndarray
    peaks_hz: FloatArray
    zeta: FloatArray
    freq_ours: FloatArray
    zeta_ours: FloatArray
    seconds: float = 0.0

    def text(self) -> str:
        """Peaks and damping ratios next to ours."""
        lines = [f"{'mode':>4s} {'exudyn_Hz':>10s} {'flexarm_Hz':>10s} {'diff_%':>8s} "
                 f"{'zeta_logdec':>11s} {'zeta_ours':>9s} {'diff_%':>8s}"]
        for r in range(self.peaks_hz.size):
            lines.append(f"{r + 1:4d} {self.peaks_hz[r]:10.3f} {self.freq_ours[r]:10.3f} "
                         f"{100 * (self.peaks_hz[r] / self.freq_ours[r] - 1):8.3f} "
                         f"{self.zeta[r]:11.4f} {self.zeta_ours[r]:9.4f} "
                         f"{100 * (self.zeta[r] / self.zeta_ours[r] - 1):8.2f}")
        lines.append(f"{self.t[-1]:.2f} s simulated in {self.seconds:.1f} s")
        return "\n".join(lines)

    def write(self, folder) -> list[Path]:
        """``impulse.png``: the TCP response in time and its receptance against ours."""
        from ...fe.plotting import pyplot, save_figure

        plt = pyplot()
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 7))
        for d, name in enumerate("xyz"):
            a1.plot(self.t, self.u[:, d] * 1e6, lw=0.8, label=f"u{name}")
        a1.set_xlabel("time [s]")
        a1.set_ylabel("TCP displacement [µm]")
        a1.legend()
        a1.grid(True, alpha=0.3)
        keep = (self.freq_hz > 0) & (self.freq_hz <= 3 * self.freq_ours[-1])
        a2.semilogy(self.freq_hz[keep], np.abs(self.H[keep]) * RECEPTANCE_SCALE,
                    label="Exudyn impulse U/F")
        a2.semilogy(self.freq_hz[keep], np.abs(self.H_ours[keep]) * RECEPTANCE_SCALE, "--",
                    label="flexarm FRF")
        a2.set_xlabel("frequency [Hz]")
        a2.set_ylabel(f"|H| along the pulse [{RECEPTANCE_UNIT}]")
        a2.legend()
        a2.grid(True, which="both", alpha=0.3)
        return [save_figure(fig, Path(folder) / "impulse.png", dpi=100)]


def impulse_response(ea: ExudynArm, direction: ArrayLike, peak: float = 1000.0,
                     pulse: float = 0.005, duration: float = 3.0, dt: float = 5e-4):
    """Integrate ``ea`` under a half-sine TCP pulse of ``peak`` [N] along ``direction``
    lasting ``pulse`` [s], for ``duration`` [s] with step ``dt`` [s].

    Returns ``t`` (nt,) [s], ``u`` (nt, 3) TCP displacement [m] (base frame) and
    ``force`` (nt,) [N].  The model should be built with gravity off.
    """
    exu = _exudyn()
    import exudyn.itemInterface as eii

    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)

    def amplitude(t):
        return peak * np.sin(np.pi * t / pulse) if 0.0 <= t < pulse else 0.0

    mbs = ea.mbs
    mbs.AddLoad(eii.LoadForceVector(
        markerNumber=ea.tcp_marker, loadVector=[0.0, 0.0, 0.0],
        loadVectorUserFunction=lambda mbs_, t, v: list(amplitude(t) * d)))
    sensor = mbs.AddSensor(eii.SensorMarker(markerNumber=ea.tcp_marker, writeToFile=False,
                                            outputVariableType=exu.OutputVariableType.Position,
                                            storeInternal=True))
    mbs.Assemble()
    sims = simulation_settings()
    sims.timeIntegration.endTime = duration
    sims.timeIntegration.numberOfSteps = int(round(duration / dt))
    sims.timeIntegration.generalizedAlpha.spectralRadius = 1.0  # no numerical damping
    sims.timeIntegration.verboseMode = 0
    sims.solution.file.write = False
    sims.solution.sensors.writePeriod = dt
    mbs.SolveDynamic(sims)
    data = np.asarray(mbs.GetSensorStoredData(sensor), dtype=float)
    t = data[:, 0]
    u = data[:, 1:4] - ea.tcp_position
    return t, u, np.array([amplitude(tk) for tk in t])


def spectrum_peak(freq_hz: FloatArray, mag: FloatArray, near: float,
                  width: float = 0.15) -> float:
    """Frequency [Hz] of the largest ``mag`` within ``near`` (1 +- ``width``), refined by a
    parabola through the three samples around it."""
    idx = np.flatnonzero((freq_hz > near * (1 - width)) & (freq_hz < near * (1 + width)))
    k = idx[np.argmax(mag[idx])]
    y0, y1, y2 = np.log(mag[k - 1 : k + 2])
    shift = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
    return float(freq_hz[k] + shift * (freq_hz[1] - freq_hz[0]))


def log_decrement(t: FloatArray, y: FloatArray, f_hz: float, band: float = 0.25) -> float:
    """Damping ratio [-] of the mode at ``f_hz`` in the free response ``y(t)``: band-pass
    ``f (1 +- band)`` (zero phase), then the logarithmic decrement of the successive
    peaks, fitted over the ring-down (amplitudes from 80 % down to 5 % of the largest)."""
    from scipy.signal import butter, find_peaks, sosfiltfilt

    fs = 1.0 / (t[1] - t[0])
    sos = butter(4, [f_hz * (1 - band), f_hz * (1 + band)], btype="band", fs=fs,
                 output="sos")
    x = sosfiltfilt(sos, y)
    k, _ = find_peaks(np.abs(x), distance=max(1, int(0.4 * fs / f_hz)))
    a = np.abs(x[k])
    top = int(np.argmax(a))
    keep = np.arange(a.size) >= top
    keep &= (a < 0.8 * a[top]) & (a > 0.05 * a[top]) & (t[k] < 0.9 * t[-1])
    slope = np.polyfit(t[k][keep], np.log(a[keep]), 1)[0]  # = -zeta omega
    delta = -slope / f_hz  # per period (peaks of |x| are half-periods apart: same slope)
    return float(delta / np.sqrt(4 * np.pi**2 + delta**2))


def impulse_test(arm: Arm, q: ArrayLike, direction: ArrayLike = (1.0, 1.0, 1.0),
                 n: int = 3, duration: float = 3.0, dt: float = 5e-4, links: list | None = None,
                 progress: Callable[[str], None] | None = None) -> ImpulseTest:
    """The hammer test of the arm's Exudyn model at ``q`` [rad] (gravity off): response,
    receptance, peaks and damping of the first ``n`` modes next to ours."""
    import time

    q = np.asarray(q, dtype=float)
    ea = exudyn_arm(arm, q, gravity=None, links=links, progress=progress)
    t0 = time.perf_counter()
    t, u, force = impulse_response(ea, direction, duration=duration, dt=dt)
    seconds = time.perf_counter() - t0
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    pad = 16 * t.size  # zero padding: a fine grid for the peaks
    freq = np.fft.rfftfreq(pad, t[1] - t[0])
    U = np.fft.rfft(u @ d, pad)
    Fw = np.fft.rfft(force, pad)
    H = U / np.where(np.abs(Fw) > 0, Fw, np.inf)
    md = modes(arm.model, q)
    f_ours, z_ours = md.freq_hz[:n], md.damping[:n]
    Hf = frf(arm.model, q, freq)
    H_ours = np.einsum("i,fij,j->f", d, Hf[:, :3, :3], d)
    peaks = np.array([spectrum_peak(freq, np.abs(H), f) for f in f_ours])
    after = t > 0.05  # the free response after the pulse
    spectra = np.abs(np.fft.rfft(u[after], pad, axis=0))  # each mode: its strongest component
    comp = [int(np.argmax(spectra[np.argmin(np.abs(freq - f))])) for f in peaks]
    zeta = np.array([log_decrement(t[after], u[after, c], f) for f, c in zip(peaks, comp,
                                                                            strict=True)])
    log.info("impulse test: %.2f s simulated in %.1f s", duration, seconds)
    return ImpulseTest(t, u, force, d, freq, H, H_ours, peaks, zeta, f_ours, z_ours, seconds)
