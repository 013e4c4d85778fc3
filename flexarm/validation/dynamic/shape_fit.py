"""Mode shapes in the diagnosis: pairing by MAC and frequency, and a shape residual in
every fit.

When the modal data carry shapes at measurement points
(:class:`~flexarm.validation.data.shape_data.ShapeData`), :class:`ShapeProblem` pairs each
measured mode with a model mode of the model being evaluated, as
:mod:`~flexarm.validation.dynamic.pairing` does for frequencies, with two more terms: a pair
needs ``MAC >= MAC_THRESHOLD`` as well as the frequency window, and its cost adds the
shape chi-square, so two close modes whose order the model gets wrong are compared with
the model modes of their own shapes.  A measured mode without a partner stays in the data
at a fixed cost and is named with words for its shape (``the whole arm rocks about base
x``).

Each mode adds a shape residual to the frequency residual of
:class:`~flexarm.validation.dynamic.modal.ModalProblem`: the measured shape ``a`` (m DOFs,
complex shapes turned real by removing their best phase) minus the partner's shape ``b``
scaled onto it (modal scale factor ``s = b.a / b.b``; a zero shape without a partner), per
DOF, divided by the stated shape noise ``shape_noise * max|a|`` (the scatter of one DOF,
as a fraction of the shape's largest entry).  Its square sum is
``|a|^2 (1 - MAC) / sigma^2``, so it is ``1 - MAC`` weighted by the noise, but smooth in
the model parameters.  The fitted scale uses one degree of freedom per mode: a mode adds
``m - 1`` observations.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ...assembly.system import ArmModel
from ..data.shape_data import Points, ShapeData
from ..static.fit import Problem
from ..tolerances import tol
from .mac import MAC_THRESHOLD, mac, pair_modes, real_shapes, reversed_channels
from .modal import ModalProblem
from .pairing import describe_shape, lonely_lines
from .shapes import model_shapes

__all__ = ["SHAPE_NOISE", "ShapeMatch", "ShapeProblem", "real_shapes", "pair_by_shape"]

log = logging.getLogger(__name__)

#: Default scatter of a measured shape entry, as a fraction of the shape's largest entry [-].
SHAPE_NOISE = 0.02
#: Model modes computed beyond the measured count of a pose, so a pairing can skip some.
_EXTRA_MODES = 4


@dataclass(frozen=True, eq=False)
class ShapeMatch:
    """Measured modes paired with model modes by MAC (:func:`pair_by_shape`).

    ``model_hz`` (n,): frequency of each row's partner [Hz] (NaN for rows not asked
    for); ``model_mode`` (n,): its 1-based number (0 if none); ``matched`` (n,) bool;
    ``mac`` (n,): MAC of the pair (of the best candidate when unpaired); ``shapes``
    (n, m): the partner's shape at the measured DOFs (zeros if none).
    """

    model_hz: np.ndarray
    model_mode: np.ndarray
    matched: np.ndarray
    mac: np.ndarray
    shapes: np.ndarray
    threshold: float = MAC_THRESHOLD

    def unmatched(self, modal: ShapeData) -> list[str]:
        """One line per measured mode without a partner (pose, mode, frequency, MAC)."""
        return [f"pose {p} mode {m}: {f:.4g} Hz has no model mode with MAC >= "
                f"{self.threshold:g} (best {c:.2f})"
                for p, m, f, c, ok in zip(modal.poses, modal.modes, modal.freq_hz, self.mac,
                                          self.matched, strict=True) if not ok]


def pair_by_shape(arm: ArmModel, data: ShapeData, points: Points, builds=None,
                  rows: np.ndarray | None = None,
                  threshold: float = MAC_THRESHOLD) -> ShapeMatch:
    """Pair the measured modes of ``data`` with model modes of ``arm`` by MAC, pose by
    pose; ``rows`` (bool (n,)) restricts the pairing to those rows.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> from flexarm.validation.dynamic.shapes import model_shape_data
    >>> pts = Points(nodes=[1, 2], links=[1, 2], positions=[[0.5, 0, 0], [1.0, 0, 0]])
    >>> d = model_shape_data(two_link_arm(), {"A": np.zeros(2)}, pts, 2)
    >>> d = ShapeData(poses=d.poses, q=d.q, modes=d.modes, freq_hz=d.freq_hz[::-1],
    ...               nodes=d.nodes, dirs=d.dirs, shapes=-d.shapes[::-1])
    >>> pair_by_shape(two_link_arm(), d, pts).model_mode.tolist()
    [2, 1]
    """
    n = arm.chain.n_joints
    rows = np.ones(len(data.freq_hz), bool) if rows is None else np.asarray(rows, bool)
    f_meas = np.asarray(data.freq_hz, float)
    A = real_shapes(data.shapes)
    hz, pairs = np.full(len(f_meas), np.nan), np.zeros(len(f_meas), int)
    ok, best = np.zeros(len(f_meas), bool), np.zeros(len(f_meas))
    B = np.zeros(A.shape)
    for pose in dict.fromkeys(np.asarray(data.poses)[rows].tolist()):
        r = np.flatnonzero((data.poses == pose) & rows)
        f, _, phi = model_shapes(arm, data.q[r[0], :n], points, data.nodes, data.dirs,
                                 len(r) + _EXTRA_MODES, builds)
        p = pair_modes(mac(A[r], phi), f_meas[r], f, threshold)
        k = np.where(p.paired, p.model, 0)
        hz[r], pairs[r], ok[r], best[r] = f[k], np.where(p.paired, k + 1, 0), p.paired, p.mac
        B[r] = np.where(p.paired[:, None], phi[k], 0.0)
    return ShapeMatch(hz, pairs, ok, best, B, threshold)


class ShapeProblem(ModalProblem):
    """A :class:`~flexarm.validation.dynamic.modal.ModalProblem` whose modes carry shapes:
    a pair needs ``MAC >= mac_threshold`` as well as the frequency window, costs the shape
    chi-square on top of the frequency's, and a mode without a partner costs the shape
    chi-square of a zero shape (module docstring; :mod:`~.pairing`).

    Parameters
    ----------
    arm, data, sigma, noise_model, flexible, freq_noise
        As for :class:`~flexarm.validation.dynamic.modal.ModalProblem`.
    modal : ShapeData
        Measured frequencies and shapes at measurement DOFs.
    points : Points
        Where the measured nodes sit on the arm.
    shape_noise : float
        Scatter of one shape entry as a fraction of the shape's largest entry [-].
    builds : tuple of LinkBuild, optional
        Recovery of flexible bodies (needed once link flexibility enters the model).
    mac_threshold : float
        The MAC a pair needs [-].
    """

    def __init__(self, arm: ArmModel, data, sigma: float = tol.tracker_sigma,
                 noise_model: str = "shared", flexible: ArmModel | None = None,
                 modal: ShapeData | None = None, freq_noise: float = tol.freq_noise,
                 points: Points | None = None, shape_noise: float = SHAPE_NOISE,
                 builds=None, mac_threshold: float = MAC_THRESHOLD):
        if not isinstance(modal, ShapeData) or points is None:
            raise ValueError("ShapeProblem needs modal data with shapes and their points")
        if not shape_noise > 0:
            raise ValueError(f"shape_noise must be > 0, got {shape_noise}")
        self.points, self.builds, self.shape_noise = points, builds, float(shape_noise)
        self.mac_threshold = float(mac_threshold)
        A = real_shapes(modal.shapes)
        self.a_sd = self.shape_noise * np.abs(A).max(axis=1)
        self.a_w = A / self.a_sd[:, None]
        super().__init__(arm, data, sigma, noise_model, flexible, modal, freq_noise)

    def pose_terms(self, arm: ArmModel, p: int, r: np.ndarray) -> dict:
        n = arm.chain.n_joints
        f, _, phi = model_shapes(arm, self.modal.q[r[0], :n], self.points, self.modal.nodes,
                                 self.modal.dirs, len(r) + _EXTRA_MODES, self.builds)
        B = phi / self.a_sd[r, None, None]  # (m, N, dofs): each model shape, whitened per row
        a = self.a_w[r]
        aa = np.einsum("ij,ij->i", a, a)
        ab = np.einsum("ij,ikj->ik", a, B)
        bb = np.maximum(np.einsum("ikj,ikj->ik", B, B), np.finfo(float).tiny)
        M = ab**2 / np.maximum(aa[:, None] * bb, np.finfo(float).tiny)
        return {"f": f, "shape_cost": aa[:, None] - ab**2 / bb, "lonely_shape_cost": aa,
                "mac": M, "mac_threshold": self.mac_threshold, "shapes": phi}

    @property
    def n_shape_obs(self) -> int:
        """Shape observations: ``m - 1`` per measured mode (the scale is fitted)."""
        return int(self.a_w.size - len(self.a_w))

    @property
    def n_obs(self) -> int:
        return super().n_obs + self.n_shape_obs

    def n_obs_rows(self, rows: np.ndarray | None = None) -> int:
        return super().n_obs_rows(rows) + self.n_shape_obs

    def observations_per_mode(self) -> int:
        return self.a_w.shape[1]

    def modal_prediction(self, effects) -> tuple[np.ndarray, np.ndarray]:
        """(n_modal,) model frequencies [Hz] of each measured mode's partner and
        (n_modal, m) its whitened shape scaled onto the measured one; a mode without a
        partner gets the frequency of the fixed cost and a zero shape."""
        pr = self.pairing(effects)
        S = np.zeros(self.a_w.shape)
        for p, tp in pr["terms"].items():
            r = np.flatnonzero(self.modal_pose == p)
            k = pr["model_mode"][r] - 1
            ok = k >= 0
            B = tp["shapes"][np.maximum(k, 0)] / self.a_sd[r, None]
            s = np.einsum("ij,ij->i", B, self.a_w[r]) / np.maximum(
                np.einsum("ij,ij->i", B, B), np.finfo(float).tiny)
            S[r] = np.where(ok[:, None], B * s[:, None], 0.0)
        return self.frequencies(effects), S

    def wpredict(self, effects, rows: np.ndarray | None = None) -> np.ndarray:
        f, S = self.modal_prediction(effects)
        return np.r_[Problem.wpredict(self, effects, rows), f / self.f_sd, S.ravel()]

    def wy(self, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wy(rows), self.a_w.ravel()]

    def pair_mac(self, effects) -> np.ndarray:
        """(n_modal,) MAC of each measured mode with its partner (NaN without one)."""
        pr = self.pairing(effects)
        out = np.full(len(self.f_meas), np.nan)
        for p, tp in pr["terms"].items():
            r = np.flatnonzero(self.modal_pose == p)
            k = pr["model_mode"][r] - 1
            out[r] = np.where(k >= 0, tp["mac"][np.arange(len(r)), np.maximum(k, 0)], np.nan)
        return out

    def lonely_lines(self, effects) -> list[str]:
        pr = self.pairing(effects)
        return lonely_lines(self.modal.poses, self.f_meas, pr["paired"], self._shape_words)

    def reversed_channels(self, effects) -> list[tuple[int, str]]:
        """``(column, line)`` per measured channel whose sign flip raises the mean MAC of
        each measured mode with its most alike model mode within the frequency window, in
        the model with ``effects`` (:func:`~.mac.reversed_channels`): a sensor mounted the
        wrong way round drops the MAC of every mode it sees, so the modes may have no
        partner at all until it is turned.  A flip is judged by the shape chi-square it
        removes (``tol.reversed_channel_chi2``), so a channel that carries a few per cent
        of every shape is found as surely as one at the tool; a measured mode with no
        model mode in the window has no shape to be judged against and is left out."""
        pr = self.pairing(effects)
        A, B = [], []
        for p, tp in pr["terms"].items():
            r = np.flatnonzero(self.modal_pose == p)
            rel = np.abs(tp["f"][None, :] - self.f_meas[r, None]) / self.f_meas[r, None]
            near = (rel <= self.window).any(axis=1)
            k = np.argmax(np.where(rel <= self.window, tp["mac"], -1.0), axis=1)
            A.append(self.a_w[r][near])
            B.append(tp["shapes"][k][near])
        flips = reversed_channels(np.concatenate(A), np.concatenate(B),
                                  tol.reversed_channel_chi2, weighted=True)
        return [(i, f"channel node {int(self.modal.nodes[i])} {self.modal.dirs[i]} looks "
                    f"reversed: flipping its sign raises the mean MAC from {before:.3f} to "
                    f"{after:.3f}")
                for i, before, after in flips]

    def _shape_words(self, i: int) -> str:
        from ...robot.kinematics import link_frames

        n = self.arm.chain.n_joints
        q = self.modal.q[i, :n]
        frames = link_frames(self.arm.chain, q)
        index = {int(nd): k for k, nd in enumerate(self.points.nodes)}
        P, labels = [], []
        for nd in self.modal.nodes:
            k = index[int(nd)]
            body = int(self.points.links[k])
            T = frames[body]
            P.append(T[:3, :3] @ self.points.positions[k] + T[:3, 3])
            labels.append(f"node {int(nd)} on {'the base' if body == 0 else f'link {body}'}")
        dirs = ["xyz".index(str(d)) for d in self.modal.dirs]
        return describe_shape(real_shapes(self.modal.shapes[i:i + 1])[0], np.array(P), dirs,
                              labels)

    def shape_note(self, effects) -> str:
        """One line on the shapes in the fit of ``effects``: pairs, their lowest MAC and
        the shape chi^2 per observation (far below 1: the stated shape noise is too
        large, ``--shape-noise``)."""
        m = self.pair_mac(effects)
        paired = m[np.isfinite(m)]
        c = self.shape_chi2(effects) / max(self.n_shape_obs, 1)
        low = f"lowest {paired.min():.3f}" if paired.size else "none"
        return (f"mode shapes: {paired.size} of {len(m)} measured modes paired by MAC and "
                f"frequency ({low}); shape chi2 per observation {c:.2f} with a stated scatter "
                f"of {100 * self.shape_noise:g} % of each shape's peak (about "
                f"{100 * self.shape_noise * np.sqrt(c):.2g} % fits)")

    def shape_chi2(self, effects) -> float:
        """chi^2 of the shapes alone (``sum |a|^2 (1 - MAC) / sigma^2`` over the pairs,
        ``|a|^2 / sigma^2`` for a mode without a partner)."""
        r = self.a_w - self.modal_prediction(effects)[1]
        return float(np.sum(r**2))
