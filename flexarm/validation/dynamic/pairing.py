"""Measured modes paired with model modes inside a fit: a frequency window, a MAC
threshold when shapes were measured, and a fixed cost for a measured mode left without a
partner.

At one pose, measured mode ``j`` (frequency ``f_j``) and model mode ``k`` may pair only if
``|f_k - f_j| <= window f_j`` and, with shapes, ``MAC_jk >= mac_threshold``: a 160 Hz mode
never pairs with a model mode at 1.8 kHz, however alike their shapes.  Among the allowed
pairs the one-to-one assignment (``scipy.optimize.linear_sum_assignment``) minimises the
summed cost, where

* a pair costs its chi-square: ``r_jk^2 = ((f_k - f_j) / (noise f_j))^2``, plus the shape
  chi-square ``s_jk`` of the shape residual when shapes were measured;
* a measured mode without a partner costs ``C^2 + s_j0`` with ``C = window / noise`` (the
  largest ``|r|`` a pair can have) and ``s_j0`` the shape chi-square of a zero shape.

So the cost is continuous as a model mode drifts to the edge of the window, and it never
falls when a measured mode loses its partner: no model is rewarded for pushing a measured
mode out of reach, and a model that *creates* a mode near one that had none (a foundation,
a bearing) gains up to ``C^2`` for it.  The unpaired modes stay in the data as evidence the
model lacks something; :func:`describe_shape` says what the measured shape looks like.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ...fe.typing import ArrayLike, FloatArray

__all__ = ["Pairing", "pair_in_window", "unpaired_cost", "describe_shape"]

_FORBIDDEN = 1e30


def unpaired_cost(window: float, noise: float) -> float:
    """``C^2``: the frequency chi-square of a measured mode without a partner [-].

    Examples
    --------
    >>> unpaired_cost(0.3, 0.005)
    3600.0
    """
    return float((window / noise) ** 2)


@dataclass(frozen=True)
class Pairing:
    """The measured modes of one pose paired with model modes (:func:`pair_in_window`).

    ``model`` (m,): index of each measured mode's partner, -1 without one; ``cost`` (m,):
    each measured mode's share of the summed cost (its pair's chi-square, or the fixed cost
    of a mode without a partner).
    """

    model: np.ndarray
    cost: np.ndarray

    @property
    def paired(self) -> np.ndarray:
        """(m,) bool: the measured mode has a partner."""
        return self.model >= 0


def pair_in_window(f_meas: ArrayLike, f_model: ArrayLike, window: float, noise: float,
                   shape_cost: ArrayLike | None = None, lonely_shape_cost: ArrayLike | None = None,
                   mac: ArrayLike | None = None, mac_threshold: float = 0.0) -> Pairing:
    """Pair measured modes with model modes at one pose (module docstring).

    Parameters
    ----------
    f_meas : (m,) float
        Measured natural frequencies [Hz].
    f_model : (N,) float
        Model natural frequencies [Hz].
    window : float
        Largest relative frequency difference of a pair [-].
    noise : float
        Relative standard uncertainty of a measured frequency [-].
    shape_cost : (m, N) float, optional
        Shape chi-square of each possible pair.
    lonely_shape_cost : (m,) float, optional
        Shape chi-square of each measured mode without a partner.
    mac : (m, N) float, optional
        MAC of each possible pair; pairs below ``mac_threshold`` are not allowed.

    Examples
    --------
    A measured mode ten times above every model mode stays without a partner:

    >>> p = pair_in_window([7.6, 16.0, 160.0], [7.5, 16.2, 17.0], 0.3, 0.005)
    >>> p.model.tolist(), p.cost.round(1).tolist()
    ([0, 1, -1], [6.9, 6.2, 3600.0])
    """
    fa, fb = np.asarray(f_meas, float), np.asarray(f_model, float)
    m, n = len(fa), len(fb)
    rel = (fb[None, :] - fa[:, None]) / fa[:, None]
    pair = (rel / noise) ** 2
    lonely = np.full(m, unpaired_cost(window, noise))
    if shape_cost is not None:
        pair = pair + np.asarray(shape_cost, float)
        lonely = lonely + np.asarray(lonely_shape_cost, float)
    allowed = np.abs(rel) <= window
    if mac is not None:
        allowed &= np.asarray(mac, float) >= mac_threshold
    cost = np.full((m, n + m), _FORBIDDEN)
    cost[:, :n] = np.where(allowed, pair, _FORBIDDEN)
    cost[np.arange(m), n + np.arange(m)] = lonely
    rows, cols = linear_sum_assignment(cost)
    model = np.full(m, -1)
    share = lonely.copy()
    inside = cols < n
    model[rows[inside]] = cols[inside]
    share[rows[inside]] = pair[rows[inside], cols[inside]]
    return Pairing(model, share)


def describe_shape(shape: ArrayLike, positions: ArrayLike, dirs: ArrayLike,
                   labels: ArrayLike) -> str:
    """A few words on a measured mode shape: ``"the whole arm rocks about base x"`` when a
    rotation of the whole arm about the base origin explains over 80 % of it (its squared
    norm), ``"the whole arm moves as one body ..."`` when a rigid motion does, else where
    it moves most.

    Parameters
    ----------
    shape : (m,) float or complex
        The shape at m measured DOFs.
    positions : (m, 3) float
        Base-frame position [m] of each DOF's point at the pose.
    dirs : (m,) int
        Base-frame direction of each DOF (0, 1, 2 = x, y, z).
    labels : (m,) str
        A name for each DOF's point (``"node 12 on link 3"``).

    Examples
    --------
    >>> p = np.array([[0, 0, 1.0], [0, 0, 1.0], [1.0, 0, 1.5], [1.0, 0, 1.5]])
    >>> u = np.cross([1.0, 0, 0], p)  # a rotation about base x
    >>> describe_shape(u[[0, 1, 2, 3], [1, 2, 1, 2]], p, [1, 2, 1, 2], ["a", "a", "b", "b"])
    'the whole arm rocks about base x'
    """
    a = np.asarray(shape)
    a = np.abs(a) * np.sign(np.real(a)) if np.iscomplexobj(a) else np.asarray(a, float)
    P = np.asarray(positions, float)
    d = np.asarray(dirs, int)
    # a small rotation theta about the base origin moves point p by theta x p: the row of
    # DOF i is e_d x p... as a linear map of theta, (theta x p)_d = (p x e_d) . theta
    E = np.eye(3)[d]
    G = np.cross(P, E)

    def share(M):
        x, *_ = np.linalg.lstsq(M, a, rcond=None)
        fit = M @ x
        return float(fit @ fit / max(a @ a, np.finfo(float).tiny)), x

    rotation, theta = share(G)
    if rotation > 0.8:
        return f"the whole arm rocks about base {'xyz'[int(np.argmax(np.abs(theta)))]}"
    rigid, x = share(np.c_[G, E])
    if rigid > 0.8:
        main = int(np.argmax(np.abs(x[:3]) * np.linalg.norm(P, axis=1).max()))
        return (f"the whole arm moves as one body ({100 * rigid:.0f} % of the shape), mostly "
                f"turning about base {'xyz'[main]}")
    i = int(np.argmax(np.abs(a)))
    return f"it moves most at {np.asarray(labels)[i]} in {'xyz'[d[i]]}"


def lonely_lines(poses, f_meas: FloatArray, paired: np.ndarray, shapes=None) -> list[str]:
    """One line per measured mode without a partner: ``"the model lacks a mode near
    108 Hz at P1 (shape: ...)"``; ``shapes`` (optional) maps a row to its shape words."""
    out = []
    for i in np.flatnonzero(~np.asarray(paired, bool)):
        words = "" if shapes is None else f" (shape: {shapes(i)})"
        out.append(f"the model lacks a mode near {f_meas[i]:.4g} Hz at {poses[i]}{words}")
    return out


__all__ += ["lonely_lines"]
