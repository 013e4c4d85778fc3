"""Wide EMA bands in overlapping sub-bands: where to cut, and one pole per mode after.

A receptance over a wide band (5-800 Hz on a robot arm) spans decades: one LSCF fit
over all of it favours the low modes, and the orders it needs for thirty modes let it
model noise near the band's top as stable poles.  The band is therefore cut into
sub-bands of a few modes each, every one fitted at an order fitted to its expected
modes:

- *expected modes*: peaks of a mode indicator (the mean over the FRFs of ``|H|``,
  each FRF scaled by its RMS, its lines of low coherence bridged) that rise by
  ``tol.ema_peak_prominence`` decades over their surroundings;
- *how many sub-bands* (``split="auto"``): enough that none holds more than
  ``tol.ema_modes_per_band`` expected modes or ``tol.ema_lines_per_band`` lines; an
  integer asks for that many, ``"none"`` for one fit;
- *cuts* at the indicator's lowest line between two peaks (the expected modes shared
  out evenly), never on a mode; each sub-band's *core* runs from cut to cut and its fit
  reaches ``tol.ema_overlap`` of the core's width into each neighbour;
- *merge*: a sub-band keeps the poles in its core (and at its edges); two poles of
  neighbouring sub-bands closer than ``tol.ema_merge_freq`` in frequency and
  ``tol.ema_merge_damping`` in damping ratio with residues of MAC above
  ``tol.ema_merge_mac`` are one mode, kept once (from the fit in whose core it lies
  more centrally).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...fe.typing import ArrayLike, FloatArray
from ..tolerances import tol
from .frf_weights import coherence_weight
from .mac import mac

__all__ = ["SubBand", "expected_peaks", "sub_bands", "merge_poles", "parse_split"]


@dataclass(frozen=True)
class SubBand:
    """One LSCF fit of a split band: lines ``lo ... hi`` [Hz] fitted at orders up to
    ``order``; its modes are those in its core ``core_lo ... core_hi`` [Hz]."""

    lo: float
    hi: float
    core_lo: float
    core_hi: float
    order: int

    def centrality(self, f: ArrayLike) -> FloatArray:
        """Distance of ``f`` [Hz] from the nearer core edge, as a share of the core's
        half-width (1 at its middle, 0 on an edge, negative outside)."""
        half = 0.5 * (self.core_hi - self.core_lo)
        return 1 - np.abs(np.asarray(f, float) - 0.5 * (self.core_lo + self.core_hi)) / half


def parse_split(text: str) -> str | int:
    """``--split`` value: ``"auto"``, ``"none"`` or a number of sub-bands >= 1.

    Examples
    --------
    >>> parse_split("auto"), parse_split("3"), parse_split("none")
    ('auto', 3, 'none')
    """
    text = str(text).strip().lower()
    if text in ("auto", "none"):
        return text
    if text.isdigit() and int(text) >= 1:
        return int(text)
    raise ValueError(f"--split {text}: auto, none or a number of sub-bands (1, 2, ...)")


def _indicator(freq: np.ndarray, H: np.ndarray, W: np.ndarray | None) -> np.ndarray:
    """(nf,) log10 of the mean over the FRFs of ``|H|`` scaled by each FRF's RMS; lines
    of low coherence (weight below that of ``tol.peak_coherence``) take the magnitude
    interpolated from the FRF's trusted lines around them, so that one channel's noisy
    lines neither make peaks nor, left out, make the mean jump between channels."""
    A = np.abs(H).astype(float)
    if W is not None:
        trusted = W >= float(coherence_weight(tol.peak_coherence))
        tiny = np.finfo(float).tiny
        for o in np.flatnonzero((~trusted).any(axis=1) & (trusted.sum(axis=1) >= 2)):
            t = trusted[o]
            A[o, ~t] = 10 ** np.interp(freq[~t], freq[t], np.log10(np.maximum(A[o, t], tiny)))
    A = A / np.maximum(np.sqrt(np.mean(A**2, axis=1, keepdims=True)), np.finfo(float).tiny)
    return np.log10(np.maximum(np.mean(A, axis=0), np.finfo(float).tiny))


def expected_peaks(freq_hz: ArrayLike, H: ArrayLike, weights: ArrayLike | None = None
                   ) -> np.ndarray:
    """Line indices of the mode indicator's peaks (see the module docstring).

    Parameters
    ----------
    freq_hz : (nf,) float
        Frequency lines [Hz] of the band.
    H : (n, nf) complex
        FRFs on those lines.
    weights : (n, nf) float, optional
        Relative weight of each line [-].

    Examples
    --------
    >>> f = np.linspace(1.0, 100.0, 991)
    >>> w = 2 * np.pi * f
    >>> H = sum(1 / ((2 * np.pi * fr) ** 2 - w**2 + 2j * 0.02 * 2 * np.pi * fr * w)
    ...         for fr in (20.0, 55.0))
    >>> f[expected_peaks(f, H[None])].round(1).tolist()
    [20.0, 55.0]
    """
    from scipy.signal import find_peaks

    H = np.atleast_2d(np.asarray(H))
    ind = _indicator(np.asarray(freq_hz, float), H,
                     None if weights is None else np.asarray(weights, float))
    return find_peaks(ind, prominence=tol.ema_peak_prominence)[0]


def _cuts(freq: np.ndarray, ind: np.ndarray, peaks: np.ndarray, n: int) -> list[int]:
    """Line indices of ``n - 1`` cuts: at the indicator's lowest line between the
    peak groups, or at even line counts when there are fewer peaks than sub-bands."""
    if len(peaks) < n:
        return [round(k * (len(freq) - 1) / n) for k in range(1, n)]
    groups = np.array_split(peaks, n)
    return [int(a[-1] + np.argmin(ind[a[-1]:b[0] + 1]))
            for a, b in zip(groups[:-1], groups[1:], strict=True)]


def sub_bands(freq_hz: ArrayLike, H: ArrayLike, f_lo: float, f_hi: float, max_order: int,
              split: str | int = "auto", weights: ArrayLike | None = None,
              min_lines: int = 20) -> list[SubBand]:
    """The LSCF fits of the band ``f_lo ... f_hi`` [Hz] (module docstring).

    Parameters
    ----------
    freq_hz : (nf,) float
        Frequency lines [Hz].
    H : (n, nf) complex
        FRFs.
    f_lo, f_hi : float
        The band [Hz].
    max_order : int
        Highest LSCF order of any fit; a single fit uses it.
    split : "auto", "none" or int
        How many sub-bands.
    weights : (n, nf) float, optional
        Relative weight of each line [-].
    min_lines : int
        Fewest lines of a core; fewer sub-bands are made than would leave one with less.

    Examples
    --------
    >>> f = np.linspace(1.0, 400.0, 3991)
    >>> w = 2 * np.pi * f
    >>> H = sum(1 / ((2 * np.pi * fr) ** 2 - w**2 + 2j * 0.01 * 2 * np.pi * fr * w)
    ...         for fr in (20.0, 45.0, 80.0, 120.0, 170.0, 230.0, 300.0, 370.0))
    >>> [(round(b.core_lo), round(b.core_hi), b.order)
    ...  for b in sub_bands(f, H[None], 1.0, 400.0, 40)]
    [(1, 154, 28), (154, 400, 28)]
    >>> len(sub_bands(f, H[None], 1.0, 400.0, 40, split="none"))
    1
    """
    freq = np.asarray(freq_hz, float)
    on = np.flatnonzero((freq >= f_lo) & (freq <= f_hi))
    fb = freq[on]
    Hb = np.atleast_2d(np.asarray(H))[:, on]
    Wb = None if weights is None else np.asarray(weights, float)[:, on]
    ind = _indicator(fb, Hb, Wb)
    peaks = expected_peaks(fb, Hb, Wb)
    if split == "none":
        n = 1
    elif split == "auto":
        n = max(math.ceil(len(peaks) / tol.ema_modes_per_band),
                math.ceil(len(fb) / tol.ema_lines_per_band), 1)
    else:
        n = int(split)
    n = max(1, min(n, len(fb) // max(min_lines, 1)))
    if n == 1:
        return [SubBand(float(f_lo), float(f_hi), float(f_lo), float(f_hi), int(max_order))]
    edges = [0, *_cuts(fb, ind, peaks, n), len(fb) - 1]
    out = []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        core_lo = float(f_lo) if a == 0 else float(fb[a])
        core_hi = float(f_hi) if b == len(fb) - 1 else float(fb[b])
        reach = tol.ema_overlap * (core_hi - core_lo)
        lo, hi = max(float(f_lo), core_lo - reach), min(float(f_hi), core_hi + reach)
        inside = np.sum((fb[peaks] >= lo) & (fb[peaks] <= hi))
        order = min(int(max_order), tol.ema_order_per_mode * int(inside) + tol.ema_order_margin)
        out.append(SubBand(lo, hi, core_lo, core_hi, order))
    return out


def merge_poles(freq_hz: ArrayLike, damping: ArrayLike, residues: ArrayLike, band: ArrayLike,
                bands: list[SubBand]) -> np.ndarray:
    """Indices of the poles kept, one per mode, sorted by frequency.

    Parameters
    ----------
    freq_hz, damping : (k,) float
        Frequency [Hz] and damping ratio [-] of the poles of every sub-band.
    residues : (k, m) complex
        Each pole's residues in the FRFs (its shape) from its sub-band's fit.
    band : (k,) int
        Index into ``bands`` of the sub-band each pole came from.
    bands : list of SubBand

    Examples
    --------
    >>> b = [SubBand(0, 60, 0, 50, 8), SubBand(40, 100, 50, 100, 8)]
    >>> merge_poles([30, 49.9, 50.05, 80], [0.01] * 4, [[1, 0], [1, 1], [1, 1.01], [0, 1]],
    ...             [0, 0, 1, 1], b).tolist()
    [0, 1, 3]
    """
    f = np.asarray(freq_hz, float)
    z = np.asarray(damping, float)
    R = np.atleast_2d(np.asarray(residues))
    which = np.asarray(band, int)
    centre = np.array([bands[b].centrality(fi) for fi, b in zip(f, which, strict=True)])
    # a pole outside its core belongs to the neighbour's fit, unless it is in no other
    # core reach (then it is kept and merged below)
    slack = tol.ema_merge_freq
    keep = centre >= -2 * slack * f / np.array([max(bands[b].core_hi - bands[b].core_lo,
                                                    np.finfo(float).tiny) for b in which])
    idx = np.flatnonzero(keep)
    idx = idx[np.argsort(-centre[idx], kind="stable")]  # most central first
    M = mac(R[idx], R[idx]) if len(idx) else np.zeros((0, 0))
    taken: list[int] = []
    for a, i in enumerate(idx):
        same = [b for b, j in enumerate(idx[:a]) if j in taken and which[j] != which[i]
                and abs(f[j] - f[i]) < tol.ema_merge_freq * f[i]
                and abs(z[j] - z[i]) < tol.ema_merge_damping * max(z[i], z[j])
                and M[a, b] > tol.ema_merge_mac]
        if not same:
            taken.append(int(i))
    return np.array(sorted(taken, key=lambda j: f[j]), int)
