"""Mode-shape correlation: MAC, AutoMAC, pairing by MAC, CoMAC.

- ``MAC_jk = |a_j^H b_k|^2 / ((a_j^H a_j)(b_k^H b_k))`` between measured shape ``a_j``
  and model shape ``b_k`` at the same DOFs: 1 for parallel shapes, 0 for orthogonal
  ones, blind to scaling and sign (Allemang & Brown).
- AutoMAC, the measured set against itself: large off-diagonal terms say the points
  cannot tell those modes apart (the point set is insufficient).
- Pairing: one-to-one, maximising the summed MAC, with the frequency difference as a
  tie-break (cost ``-MAC + TIE_WEIGHT |f_model - f_meas| / f_meas``, solved by
  ``scipy.optimize.linear_sum_assignment``), inside a frequency window; a measured mode
  whose partner has ``MAC < threshold`` is reported as unpaired, not forced onto a model
  mode.
- CoMAC per point over the paired modes (Lieven & Ewins), after scaling each model
  shape onto its measured partner (modal scale factor): near 1 where model and test
  move alike, low where the model is wrong.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ...fe.typing import ArrayLike, FloatArray

__all__ = ["MAC_THRESHOLD", "TIE_WEIGHT", "FREQ_RATIO", "mac", "automac", "ModePairing",
           "pair_modes", "comac", "moving_points", "reversed_channels", "real_shapes", "plot_mac"]

#: A pair needs at least this MAC [-]; below it the measured mode stays unpaired.
MAC_THRESHOLD = 0.8
#: Largest frequency ratio of a MAC pair [-]: a model whose joint is at a quarter of the
#: modelled stiffness puts that joint's mode at half the frequency, which MAC must still
#: pair; a tenfold ratio is another mode whatever its shape.
FREQ_RATIO = 2.0
#: Weight of the relative frequency difference in the pairing cost [-]: 10 % in
#: frequency weighs as 0.01 in MAC, so frequency only decides between near-equal MACs.
TIE_WEIGHT = 0.1


def mac(A: ArrayLike, B: ArrayLike) -> FloatArray:
    """(nA, nB) MAC between the rows of ``A`` (nA, m) and ``B`` (nB, m), real or complex.

    Examples
    --------
    >>> mac([[1.0, 0.0], [1.0, 1.0]], [[2.0, 0.0], [0.0, -3.0]]).round(3).tolist()
    [[1.0, 0.0], [0.5, 0.5]]
    """
    A, B = np.atleast_2d(A), np.atleast_2d(B)
    if A.shape[1] != B.shape[1]:
        raise ValueError(f"MAC needs shapes at the same DOFs: {A.shape[1]} and {B.shape[1]}")
    num = np.abs(np.conj(A) @ B.T) ** 2
    den = np.einsum("ij,ij->i", np.conj(A), A).real[:, None] * \
        np.einsum("ij,ij->i", np.conj(B), B).real[None, :]
    return num / np.maximum(den, np.finfo(float).tiny)


def automac(A: ArrayLike) -> FloatArray:
    """(n, n) MAC of a shape set with itself (ones on the diagonal).

    Examples
    --------
    >>> automac([[1.0, 0.0], [1.0, 0.1]]).round(3).tolist()
    [[1.0, 0.99], [0.99, 1.0]]
    """
    return mac(A, A)


@dataclass(frozen=True)
class ModePairing:
    """Measured modes paired with model modes (:func:`pair_modes`).

    Attributes
    ----------
    model : (nA,) int
        Index of the model mode paired with each measured mode, -1 when unpaired.
    mac : (nA,) float
        MAC of each pair (of the best candidate when unpaired).
    threshold : float
        The MAC a pair needed.
    """

    model: np.ndarray
    mac: np.ndarray
    threshold: float = MAC_THRESHOLD

    @property
    def paired(self) -> np.ndarray:
        """(nA,) bool: the measured mode has a partner."""
        return self.model >= 0


def pair_modes(M: ArrayLike, f_meas: ArrayLike, f_model: ArrayLike,
               threshold: float = MAC_THRESHOLD, tie_weight: float = TIE_WEIGHT,
               ratio: float = FREQ_RATIO) -> ModePairing:
    """Pair measured modes (rows of the MAC matrix ``M``) with model modes (columns).

    A pair needs ``MAC >= threshold`` and frequencies within a factor ``ratio`` of each
    other: shapes alike at a tenfold frequency are not the same mode.

    Examples
    --------
    Two close modes listed in the other order are paired by shape, not by frequency:

    >>> M = np.array([[0.02, 0.97, 0.0], [0.96, 0.03, 0.0], [0.0, 0.0, 0.4]])
    >>> p = pair_modes(M, [10.0, 10.4, 30.0], [10.1, 10.3, 29.0])
    >>> p.model.tolist(), p.mac.round(2).tolist()
    ([1, 0, -1], [0.97, 0.96, 0.4])
    """
    M = np.asarray(M, float)
    fa, fb = np.asarray(f_meas, float), np.asarray(f_model, float)
    rel = np.abs(fb[None, :] - fa[:, None]) / fa[:, None]
    far = np.maximum(fb[None, :] / fa[:, None], fa[:, None] / fb[None, :]) > ratio
    cost = -np.where(far, 0.0, M) + tie_weight * np.minimum(rel, 10.0) + 10.0 * far
    rows, cols = linear_sum_assignment(cost)
    model = np.full(len(fa), -1)
    best = np.zeros(len(fa))
    model[rows], best[rows] = cols, np.where(far[rows, cols], 0.0, M[rows, cols])
    lonely = np.setdiff1d(np.arange(len(fa)), rows)  # more measured than model modes
    best[lonely] = np.where(far[lonely], 0.0, M[lonely]).max(axis=1) if M.shape[1] else 0.0
    model[best < threshold] = -1
    return ModePairing(model, best, threshold)


def comac(A: ArrayLike, B: ArrayLike, groups: ArrayLike | None = None) -> FloatArray:
    """CoMAC of paired shapes ``A`` (measured) and ``B`` (model), both (n_pairs, m).

    Each model shape is first scaled onto its measured partner (modal scale factor
    ``b^H a / b^H b``); then ``CoMAC_i = |sum_r a_ri conj(b_ri)|^2 / (sum_r |a_ri|^2
    sum_r |b_ri|^2)``.  The sum is signed (after the scale factor fixed each mode's
    sign), so a point that moves the wrong way in one mode drops, which the
    absolute-value form would not see.  ``groups`` (m,) labels DOFs that belong to
    one point (its x, y, z): the CoMAC is then per group, in order of first appearance.

    Examples
    --------
    >>> A = np.array([[1.0, 2.0, 1.0], [1.0, 0.0, -1.0], [1.0, -1.0, 1.0]])
    >>> B = A.copy(); B[0, 2] = -1.0  # the model is wrong at the third DOF
    >>> comac(A, B).round(3).tolist()
    [0.97, 0.968, 0.242]
    """
    A, B = np.atleast_2d(A), np.atleast_2d(np.asarray(B))
    msf = np.einsum("ij,ij->i", np.conj(B), A) / np.maximum(
        np.einsum("ij,ij->i", np.conj(B), B).real, np.finfo(float).tiny)
    B = B * msf[:, None]
    num = np.abs(np.sum(np.conj(A) * B, axis=0))
    aa = np.sum(np.abs(A) ** 2, axis=0)
    bb = np.sum(np.abs(B) ** 2, axis=0)
    if groups is not None:
        labels, first, inv = np.unique(np.asarray(groups), return_index=True,
                                       return_inverse=True)
        order = np.argsort(first)
        inv = np.argsort(order)[inv.ravel()]
        num = np.bincount(inv, num, len(labels))
        aa, bb = np.bincount(inv, aa, len(labels)), np.bincount(inv, bb, len(labels))
    return num**2 / np.maximum(aa * bb, np.finfo(float).tiny)


def moving_points(A: ArrayLike, groups: ArrayLike, share: float = 0.1) -> np.ndarray:
    """(k,) bool per point (group of DOFs, in order of first appearance): whether it moves
    at least ``share`` of the most-moving point (RMS over the modes ``A`` (n, m) after
    scaling each mode to unit peak).  A point that barely moves has a CoMAC of noise.

    Examples
    --------
    >>> moving_points([[1.0, 0.5, 0.01]], [1, 2, 3]).tolist()
    [True, True, False]
    """
    A = np.atleast_2d(np.abs(np.asarray(A)))
    A = A / np.maximum(A.max(axis=1, keepdims=True), np.finfo(float).tiny)
    labels, first, inv = np.unique(np.asarray(groups), return_index=True, return_inverse=True)
    order = np.argsort(first)
    inv = np.argsort(order)[inv.ravel()]
    rms = np.sqrt(np.bincount(inv, (A**2).sum(axis=0), len(labels)))
    return rms >= share * rms.max()


def reversed_channels(A: ArrayLike, B: ArrayLike, min_gain: float = 0.05,
                      weighted: bool = False) -> list:
    """Channels (columns of the paired shapes ``A`` measured, ``B`` model, both (n, m))
    whose sign flip raises the mean MAC of the pairs by at least ``min_gain``, found one
    at a time (each flip judged with the ones before made), with the mean MAC before and
    after: ``[(column, mac_before, mac_after), ...]``.  A sensor mounted the wrong way
    round, or a direction entered with the wrong sign.

    With ``weighted``, ``A`` is in units of its noise (each row divided by the scatter of
    one entry) and a flip must lower the shape chi-square ``sum |a|^2 (1 - MAC)`` by at
    least ``min_gain`` times the chi-square per observation it leaves (at least 1): a
    channel that carries a few per cent of every shape moves the mean MAC by little, yet
    far more than its noise, while a model error spread over all channels inflates the
    chi-square the gain is weighed against.

    Examples
    --------
    >>> B = np.array([[1.0, 2.0, 1.0], [1.0, -1.0, 2.0]])
    >>> A = B * [1.0, -1.0, 1.0]  # channel 1 reversed
    >>> [(c, round(a, 2), round(b, 2)) for c, a, b in reversed_channels(A, B)]
    [(1, 0.28, 1.0)]
    >>> [c for c, _, _ in reversed_channels(100 * A, B, min_gain=25.0, weighted=True)]
    [1]
    """
    A, B = np.atleast_2d(np.array(A)), np.atleast_2d(B)
    # the weight of a row's MAC: its share of the mean, or its chi-square |a|^2
    w = (np.abs(A)**2).sum(axis=1) if weighted else np.full(len(A), 1.0 / max(len(A), 1))
    dof = max(A.size - len(A), 1)  # one scale fitted per row
    out = []
    while len(A) and len(out) < A.shape[1]:
        before = np.diag(mac(A, B))
        trials = []
        for i in range(A.shape[1]):
            A[:, i] = -A[:, i]
            trials.append(np.diag(mac(A, B)))
            A[:, i] = -A[:, i]
        T = np.array(trials)  # (m, n): every row's MAC with channel i flipped
        score = (T - before) @ w
        if weighted:
            score = score / np.maximum(1.0, (1.0 - T) @ w / dof)
        i = int(np.argmax(score))
        if score[i] < min_gain:
            break
        out.append((i, float(before.mean()), float(T[i].mean())))
        A[:, i] = -A[:, i]  # greedy: the next flip is judged with this one made
    return out


def real_shapes(A: ArrayLike) -> FloatArray:
    """(n, m) real shapes: each row of ``A`` turned by the phase that makes it as real
    as possible (the principal axis of its entries in the complex plane), then its real
    part; real input comes back unchanged.

    Examples
    --------
    >>> real_shapes([[1j, -2j, 0.5j]]).round(6).tolist()
    [[1.0, -2.0, 0.5]]
    """
    A = np.atleast_2d(np.asarray(A))
    if not np.iscomplexobj(A):
        return A.astype(float)
    theta = 0.5 * np.angle(np.sum(A * A, axis=1))
    return (A * np.exp(-1j * theta)[:, None]).real


def plot_mac(path, M: ArrayLike, f_rows: ArrayLike, f_cols: ArrayLike, title: str,
             row_label: str = "measured", col_label: str = "model") -> None:
    """Write the MAC matrix ``M`` as a heat map PNG, modes labelled by frequency [Hz]."""
    from ...fe.plotting import pyplot

    plt = pyplot()
    M = np.asarray(M, float)
    fig, ax = plt.subplots(figsize=(1.6 + 0.45 * M.shape[1], 1.2 + 0.4 * M.shape[0]))
    im = ax.imshow(M, vmin=0.0, vmax=1.0, cmap="viridis")
    ax.set_xticks(np.arange(M.shape[1]), [f"{f:.1f}" for f in f_cols], rotation=90,
                  fontsize=7)
    ax.set_yticks(np.arange(M.shape[0]), [f"{f:.1f}" for f in f_rows], fontsize=7)
    for (i, j), v in np.ndenumerate(M):
        ax.text(j, i, f"{v:.2f}", ha="center", va="center", fontsize=6,
                color="k" if v > 0.6 else "w")
    ax.set_xlabel(f"{col_label} mode [Hz]", fontsize=8)
    ax.set_ylabel(f"{row_label} mode [Hz]", fontsize=8)
    ax.set_title(title, fontsize=9)
    fig.colorbar(im, ax=ax, fraction=0.046, pad=0.04, label="MAC")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
