"""Mode shapes in the diagnosis: pairing by MAC and a shape residual in every fit.

When the modal data carry shapes at measurement points
(:class:`~flexarm.validation.data.shape_data.ShapeData`), :class:`ShapeProblem` pairs each
measured mode with a model mode by MAC, frequency only breaking ties
(:func:`~flexarm.validation.dynamic.mac.pair_modes`, the pairing ``compare`` uses), instead of
by frequency alone: two close modes whose order the model gets wrong are then compared
with the model modes of their own shapes.  A measured mode without a partner at
``MAC >= MAC_THRESHOLD`` in the starting model is reported and left out.

Each paired mode adds a shape residual to the frequency residual of
:class:`~flexarm.validation.dynamic.modal.ModalProblem`: the measured shape ``a`` (m DOFs,
complex shapes turned real by removing their best phase) minus the model shape ``b``
scaled onto it (modal scale factor ``s = b.a / b.b``), per DOF, divided by the stated
shape noise ``shape_noise * max|a|`` (the scatter of one DOF, as a fraction of the
shape's largest entry).  Its square sum is ``|a|^2 (1 - MAC) / sigma^2``, so it is
``1 - MAC`` weighted by the noise, but smooth in the model parameters.  The fitted scale
uses one degree of freedom per mode: a mode adds ``m - 1`` observations.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ...assembly.system import ArmModel
from ...fe.typing import ArrayLike, FloatArray
from ..data.shape_data import Points, ShapeData
from ..static.fit import Problem
from ..tolerances import tol
from .mac import MAC_THRESHOLD, mac, pair_modes
from .modal import ModalProblem
from .shapes import model_shapes

__all__ = ["SHAPE_NOISE", "ShapeMatch", "ShapeProblem", "real_shapes", "pair_by_shape"]

log = logging.getLogger(__name__)

#: Default scatter of a measured shape entry, as a fraction of the shape's largest entry [-].
SHAPE_NOISE = 0.02
#: Model modes computed beyond the measured count of a pose, so a pairing can skip some.
_EXTRA_MODES = 4


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
    pairing by MAC and a shape residual per paired mode (module docstring).

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
    """

    def __init__(self, arm: ArmModel, data, sigma: float = tol.tracker_sigma,
                 noise_model: str = "shared", flexible: ArmModel | None = None,
                 modal: ShapeData | None = None, freq_noise: float = tol.freq_noise,
                 points: Points | None = None, shape_noise: float = SHAPE_NOISE,
                 builds=None):
        if not isinstance(modal, ShapeData) or points is None:
            raise ValueError("ShapeProblem needs modal data with shapes and their points")
        if not shape_noise > 0:
            raise ValueError(f"shape_noise must be > 0, got {shape_noise}")
        self.points, self.builds, self.shape_noise = points, builds, float(shape_noise)
        super().__init__(arm, data, sigma, noise_model, flexible, modal, freq_noise)
        A = real_shapes(modal.shapes)[self.modal_keep]
        self.a_sd = self.shape_noise * np.abs(A).max(axis=1)
        self.a_w = A / self.a_sd[:, None]

    def initial_match(self, arm: ArmModel, modal) -> ShapeMatch:
        """Pairs by MAC in the baseline fitted to the static data alone
        (:attr:`start_effects`, :func:`~.modal.static_start`): shapes of close modes mix
        as the joint stiffnesses move, so the nominal model would leave out modes the
        fitted one pairs."""
        return pair_by_shape(self.model(self.start_effects)[0], modal, self.points,
                             self.builds)

    @property
    def n_shape_obs(self) -> int:
        """Shape observations: ``m - 1`` per paired mode (the scale is fitted)."""
        return int(self.a_w.size - len(self.a_w))

    @property
    def n_obs(self) -> int:
        return super().n_obs + self.n_shape_obs

    def n_obs_rows(self, rows: np.ndarray | None = None) -> int:
        return super().n_obs_rows(rows) + self.n_shape_obs

    def modal_prediction(self, effects) -> tuple[np.ndarray, np.ndarray]:
        """(n_modal,) model frequencies [Hz] of the paired modes and (n_modal, m) their
        whitened shapes scaled onto the measured ones, pairing afresh by MAC for this
        model (no threshold, so the prediction stays continuous)."""
        arm, _ = self.model(effects)
        keep = self.modal_keep
        match = pair_by_shape(arm, self.modal, self.points, self.builds, keep, 0.0)
        B = match.shapes[keep] / self.a_sd[:, None]
        s = np.einsum("ij,ij->i", B, self.a_w) / np.maximum(np.einsum("ij,ij->i", B, B),
                                                            np.finfo(float).tiny)
        return match.model_hz[keep], B * s[:, None]

    def frequencies(self, effects) -> np.ndarray:
        return self.modal_prediction(effects)[0]

    def wpredict(self, effects, rows: np.ndarray | None = None) -> np.ndarray:
        f, S = self.modal_prediction(effects)
        return np.r_[Problem.wpredict(self, effects, rows), f / self.f_sd, S.ravel()]

    def wy(self, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wy(rows), self.a_w.ravel()]

    def shape_note(self, effects) -> str:
        """One line on the shapes in the fit of ``effects``: pairs, their lowest MAC and
        the shape chi^2 per observation (far below 1: the stated shape noise is too
        large, ``--shape-noise``)."""
        arm, _ = self.model(effects)
        keep = self.modal_keep
        m = pair_by_shape(arm, self.modal, self.points, self.builds, keep, 0.0).mac[keep]
        c = self.shape_chi2(effects) / max(self.n_shape_obs, 1)
        return (f"mode shapes: {len(m)} measured modes paired by MAC (lowest {m.min():.3f}); "
                f"shape chi2 per observation {c:.2f} with a stated scatter of "
                f"{100 * self.shape_noise:g} % of each shape's peak (about "
                f"{100 * self.shape_noise * np.sqrt(c):.2g} % fits)")

    def shape_chi2(self, effects) -> float:
        """chi^2 of the shapes alone (``sum |a|^2 (1 - MAC) / sigma^2`` over the pairs)."""
        r = self.a_w - self.modal_prediction(effects)[1]
        return float(np.sum(r**2))
