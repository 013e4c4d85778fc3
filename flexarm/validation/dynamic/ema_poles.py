"""The stabilisation diagram of EMA: stable poles, the columns picked as modes, and the
poles of a split band merged (see :mod:`.ema` for the rules)."""

from __future__ import annotations

import numpy as np

from .ema_bands import SubBand, merge_poles
from .ema_lsq import lscf_poles, lsfd_residues, pole_freq_damping

__all__ = ["STABLE_FREQ", "STABLE_DAMPING", "CLUSTER", "stable_poles", "pick_columns",
           "band_poles", "merged_poles"]

#: A pole is stable when the previous order has one this close in frequency [-] ...
STABLE_FREQ = 0.01
#: ... and in damping ratio [-] (relative).
STABLE_DAMPING = 0.05
#: Stable poles closer than this (relative frequency gap) form one column [-].
CLUSTER = 0.005
_MAX_DAMPING = 0.2  # poles more damped than this are numerical


def stable_poles(pole_freq, pole_xi, f_lo: float, f_hi: float) -> np.ndarray:
    """(k, 4) rows ``(order index, pole index, freq [Hz], damping ratio)`` of the stable
    poles of an LSCF run (``pole_freq``, ``pole_xi``: one array per order).

    Examples
    --------
    >>> f = [np.array([10.0]), np.array([10.02, 30.0]), np.array([10.01, 31.0])]
    >>> z = [np.array([0.02]), np.array([0.0201, 0.05]), np.array([0.0202, 0.05])]
    >>> stable_poles(f, z, 1.0, 100.0)[:, :2].astype(int).tolist()
    [[1, 0], [2, 0]]
    """
    rows = []
    for j in range(1, len(pole_freq)):
        fp, xp = np.asarray(pole_freq[j]), np.asarray(pole_xi[j])
        fq, xq = np.asarray(pole_freq[j - 1]), np.asarray(pole_xi[j - 1])
        ok = (xp > 0) & (xp < _MAX_DAMPING) & (fp >= f_lo) & (fp <= f_hi)
        if not fq.size or not ok.any():
            continue
        near = (np.abs(fq[None, :] - fp[:, None]) < STABLE_FREQ * fp[:, None]) & \
            (np.abs(xq[None, :] - xp[:, None]) < STABLE_DAMPING * xp[:, None])
        k = np.flatnonzero(ok & near.any(axis=1))
        rows.append(np.column_stack([np.full(len(k), j), k, fp[k], xp[k]]))
    return np.concatenate(rows) if rows else np.zeros((0, 4))


def pick_columns(stable: np.ndarray, n_orders: int, min_stable: float) -> np.ndarray:
    """The medoid pole (nearest the column's median frequency) of every column of the
    diagram stable at ``min_stable`` of the ``n_orders`` orders or more.

    Parameters
    ----------
    stable : (s, 4) float
        Rows of :func:`stable_poles`.
    n_orders : int
        Orders of the diagram.
    min_stable : float
        Share of the orders [-].

    Returns
    -------
    (k, 4) float
        One row of ``stable`` per mode, by frequency.

    Examples
    --------
    >>> s = np.array([[1, 0, 10.0, 0.02], [2, 0, 10.02, 0.02], [3, 1, 10.01, 0.02],
    ...               [2, 1, 50.0, 0.01]])
    >>> pick_columns(s, 4, 0.5)[:, 2].tolist()
    [10.01]
    """
    if not len(stable):
        return np.zeros((0, 4))
    s = stable[np.argsort(stable[:, 2], kind="stable")]
    need = min_stable * n_orders
    groups = np.split(s, np.flatnonzero(np.diff(s[:, 2]) / s[:-1, 2] > CLUSTER) + 1)
    cols = [c for g in groups for c in _one_pole_per_order(g, need)]
    keep = [c[np.argmin(np.abs(c[:, 2] - np.median(c[:, 2])))] for c in cols
            if len(np.unique(c[:, 0])) >= need]
    return np.array(keep) if keep else np.zeros((0, 4))


def _one_pole_per_order(group: np.ndarray, need: float) -> list[np.ndarray]:
    """``group`` (rows of :func:`stable_poles` by frequency) as columns: cut at its widest
    frequency gap, part by part, while it holds two poles at ``need`` orders or more.

    Two modes a little more than ``CLUSTER`` apart chain into one group through the
    poles between them (the single pole of the orders too low to split the pair); a
    column has one pole per order, so a group with two at as many orders as make a mode
    holds two modes.  A noise pole that joins a column at a few orders does not cut it.
    """
    _, per_order = np.unique(group[:, 0], return_counts=True)
    if len(group) < 2 or np.sum(per_order >= 2) < max(need, 1):
        return [group]
    cut = int(np.argmax(np.diff(group[:, 2]))) + 1
    return [*_one_pole_per_order(group[:cut], need), *_one_pole_per_order(group[cut:], need)]


def band_poles(freq_hz: np.ndarray, H: np.ndarray, weights: np.ndarray | None,
               band: SubBand, min_stable: float) -> tuple[np.ndarray, np.ndarray, list]:
    """The modes of one sub-band: its LSCF diagram and the columns picked in it.

    Parameters
    ----------
    freq_hz : (nf,) float
        Frequency lines [Hz].
    H : (n, nf) complex
        Receptances [m/N].
    weights : (n, nf) float or None
        Relative weight of each line [-].
    band : SubBand
        Lines and highest order of the fit.
    min_stable : float
        Share of the orders at which a column must be stable [-].

    Returns
    -------
    poles : (k,) complex
        The picked poles [rad/s].
    stable : (s, 4) float
        Rows of :func:`stable_poles`.
    diagram : list of (2, p) float
        Frequency [Hz] and damping ratio [-] of every pole per order.

    Examples
    --------
    >>> f = np.arange(1.0, 100.0, 0.25)
    >>> w, wr = 2 * np.pi * f, 2 * np.pi * 40.0
    >>> H = (1 / (wr**2 - w**2 + 0.02j * wr * w))[None]
    >>> p, _, _ = band_poles(f, H, None, SubBand(1.0, 99.75, 1.0, 99.75, 10), 0.25)
    >>> np.round(pole_freq_damping(p), 6).tolist()
    [[40.0], [0.01]]
    """
    poles = lscf_poles(freq_hz, H, band.lo, band.hi, band.order, weights)
    fd = [pole_freq_damping(p) for p in poles]
    stable = stable_poles([f for f, _ in fd], [z for _, z in fd], band.lo, band.hi)
    picked = pick_columns(stable, len(poles), min_stable)
    chosen = np.array([poles[int(j)][int(k)] for j, k in picked[:, :2]], complex)
    return chosen, stable, [np.array(x) for x in fd]


def merged_poles(freq_hz: np.ndarray, H: np.ndarray, weights: np.ndarray | None,
                 bands: list, min_stable: float) -> tuple[np.ndarray, np.ndarray, list]:
    """The modes of every sub-band (:func:`band_poles`), one pole per mode
    (:func:`~.ema_bands.merge_poles` on their residues in their own fits); with the
    stable rows and the diagram of all the fits together.

    Examples
    --------
    >>> f = np.arange(1.0, 200.0, 0.25)
    >>> w, wr = 2 * np.pi * f, 2 * np.pi * np.array([[40.0], [120.0]])
    >>> H = np.sum(1 / (wr**2 - w**2 + 0.02j * wr * w), axis=0)[None]
    >>> bands = [SubBand(1.0, 120.0, 1.0, 80.0, 10), SubBand(60.0, 199.75, 80.0, 199.75, 10)]
    >>> p, _, _ = merged_poles(f, H, None, bands, 0.25)
    >>> np.round(pole_freq_damping(p)[0], 4).tolist()
    [40.0, 120.0]
    """
    found = [band_poles(freq_hz, H, weights, b, min_stable) for b in bands]
    stable = np.concatenate([st for _, st, _ in found])
    n_orders = max(len(d) for _, _, d in found)
    diagram = [np.hstack([d[j] for _, _, d in found if j < len(d)]) for j in range(n_orders)]
    if len(bands) == 1:
        return found[0][0], stable, diagram
    poles = np.concatenate([p for p, _, _ in found])
    if not len(poles):
        return poles, stable, diagram
    which = np.concatenate([np.full(len(p), i) for i, (p, _, _) in enumerate(found)])
    residues = np.vstack([lsfd_residues(freq_hz, H, p, b.lo, b.hi, weights)[0].T
                          for (p, _, _), b in zip(found, bands, strict=True) if len(p)])
    f, z = pole_freq_damping(poles)
    return poles[merge_poles(f, z, residues, which, bands)], stable, diagram
