"""Modal data in the diagnosis: natural frequencies as extra observations, and a modal lab.

A measured frequency at a pose is compared with the model mode it is *assigned* to, not
with the model mode of the same number: the file's mode numbers are the lab's labels,
and two close modes may be listed in the other order (or the model's two modes may swap
places as the fit changes a stiffness).  :func:`match_modes` assigns, per pose, the
measured frequencies to distinct model modes by minimising the sum of squared relative
differences ``((f_model - f_meas) / f_meas)^2`` (``scipy.optimize.linear_sum_assignment``),
which is the frequencies' chi-square: the assignment is the most likely one, and the
modal chi-square stays continuous when modes cross.  A measured mode with no model mode
within a factor ``1 + MATCH_WINDOW`` of it (in the starting model) is *unmatched*: it is
reported and left out of the diagnosis.  The noise is relative,
``sd = freq_noise * f_k`` (0.5 % by default, ``tol.freq_noise``), independent between
modes and poses.  :class:`ModalProblem` appends these whitened residuals to the static
GLS residuals of :class:`~flexarm.validation.static.fit.Problem`, so every fit, score test and
held-out check of the diagnosis uses both.  Frequency sensitivities to the parameters are finite
differences of the model eigenvalues (as for the static part).

Why this separates link flexibility: static TCP compliance is a sum of joint and link
compliances, so fitted joint compliances can absorb the links; the frequencies weigh
the same compliances with the mass distribution, differently per mode and pose, so the
E-model whose joints were softened to match the statics cannot match them.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ...assembly.analyses import natural_frequencies
from ...assembly.effects import apply_effects
from ...assembly.linkflex import links_arm, split_links
from ...assembly.system import ArmModel
from ...robot.effects import Effect
from ..data.measurements import DIRECTIONS, ModalData, StaticData
from ..data.shape_data import Points, ShapeData
from ..static.fit import Problem
from ..tolerances import tol

__all__ = ["ModalProblem", "ModeMatch", "MATCH_WINDOW", "match_modes", "match_frequencies",
           "model_frequencies", "static_start", "virtual_modal", "virtual_shapes",
           "virtual_frfs"]

log = logging.getLogger(__name__)

#: A matched pair's frequencies lie within a factor ``1 + MATCH_WINDOW`` of each other [-].
#: Wide enough for a nominal model with +-30 % joint stiffness errors (+-15 % in
#: frequency) and rigid links (scenario 7: the E-model's third mode at P1 is 30 % above
#: the measured one); a measured mode farther from every model mode (a fixture
#: resonance, a sensor mode) is reported as unmatched.
MATCH_WINDOW = 0.5

_OUTSIDE = 1e6  # cost added to a pair outside the window (used only when unavoidable)


def _assign(f_meas: np.ndarray, f_model: np.ndarray, window: float | None):
    """(k, inside): one-to-one assignment minimising the summed squared relative
    differences (pairs outside ``window`` only when nothing else is left); ``k = -1``
    only when the model has fewer modes than were measured."""
    k = np.full(len(f_meas), -1)
    inside = np.zeros(len(f_meas), bool)
    if not len(f_meas) or not len(f_model):
        return k, inside
    rel = (f_model[None, :] - f_meas[:, None]) / f_meas[:, None]
    cost = rel**2
    far = np.zeros(rel.shape, bool)
    if window is not None:
        ratio = np.maximum(f_model[None, :] / f_meas[:, None], f_meas[:, None] / f_model[None, :])
        far = ratio > 1 + window
        cost = cost + _OUTSIDE * far
    rows, cols = linear_sum_assignment(cost)
    k[rows] = cols
    inside[rows] = ~far[rows, cols]
    return k, inside


def match_modes(f_meas, f_model, window: float | None = MATCH_WINDOW) -> np.ndarray:
    """Assign measured frequencies of one pose to distinct model modes.

    Parameters
    ----------
    f_meas : (m,) float
        Measured natural frequencies [Hz] (any order).
    f_model : (N,) float
        Model natural frequencies [Hz].
    window : float or None
        A match's frequencies lie within a factor ``1 + window`` of each other;
        ``None``: every measured mode is assigned (if the model has enough modes).

    Returns
    -------
    (m,) int
        Index into ``f_model`` of each measured mode, ``-1`` when unmatched.  The
        assignment minimises ``sum ((f_model - f_meas) / f_meas)^2`` over one-to-one
        assignments, pairs outside the window only when nothing else is left.

    Examples
    --------
    >>> match_modes([16.9, 16.1, 7.6], [7.5, 16.0, 17.0, 40.0]).tolist()
    [2, 1, 0]
    >>> match_modes([7.6, 3.0], [7.5, 16.0]).tolist()
    [0, -1]
    """
    k, inside = _assign(np.asarray(f_meas, float), np.asarray(f_model, float), window)
    return np.where(inside, k, -1)


@dataclass(frozen=True)
class ModeMatch:
    """Measured modes assigned to model modes (:func:`match_frequencies`).

    ``model_hz`` (n,): the model frequency assigned to each row of the modal data (an
    unmatched row keeps the model mode the assignment left it, so the array stays
    finite); ``model_mode`` (n,): its 1-based model mode number; ``matched`` (n,) bool:
    within the window.
    """

    model_hz: np.ndarray
    model_mode: np.ndarray
    matched: np.ndarray
    window: float | None = MATCH_WINDOW

    def unmatched(self, modal: ModalData) -> list[str]:
        """One line per unmatched measured mode (pose, mode number, frequency)."""
        w = "" if self.window is None else f" within a factor {1 + self.window:.3g}"
        return [f"pose {p} mode {m}: {f:.4g} Hz has no model mode{w} (model modes are "
                f"all taken or farther; assigned {fm:.4g} Hz)"
                for p, m, f, fm, ok in zip(modal.poses, modal.modes, modal.freq_hz,
                                           self.model_hz, self.matched, strict=True) if not ok]


def match_frequencies(arm: ArmModel, modal: ModalData, window: float | None = MATCH_WINDOW,
                      rows: np.ndarray | None = None) -> ModeMatch:
    """Assign the measured modes of ``modal`` to model modes of ``arm``, pose by pose
    (:func:`match_modes`); ``rows`` (bool (n,)) restricts the assignment to those rows
    (the others come back unmatched, NaN)."""
    n = arm.chain.n_joints
    uq, inv = np.unique(np.asarray(modal.q, float)[:, :n], axis=0, return_inverse=True)
    F = np.atleast_2d(natural_frequencies(arm, uq))
    pose = inv.ravel()
    f_meas = np.asarray(modal.freq_hz, float)
    rows = np.ones(len(f_meas), bool) if rows is None else np.asarray(rows, bool)
    mode = np.zeros(len(f_meas), int)
    hz = np.full(len(f_meas), np.nan)
    matched = np.zeros(len(f_meas), bool)
    for p in np.unique(pose[rows]):
        r = np.flatnonzero((pose == p) & rows)
        if len(r) > F.shape[1]:
            raise ValueError(f"modal data give {len(r)} modes at pose "
                             f"'{modal.poses[r[0]]}'; the model has {F.shape[1]}")
        k, inside = _assign(f_meas[r], F[p], window)
        mode[r], hz[r], matched[r] = k + 1, F[p][k], inside
    return ModeMatch(hz, mode, matched, window)


def model_frequencies(arm: ArmModel, modal: ModalData,
                      window: float | None = MATCH_WINDOW) -> np.ndarray:
    """(n,) model natural frequency [Hz] assigned to each row (pose, mode) of ``modal``.

    The measured modes of a pose are matched to model modes by frequency
    (:func:`match_frequencies`), not by their mode numbers; an unmatched row keeps the
    model mode the assignment left it (:attr:`ModeMatch.matched` tells).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> m = ModalData(poses=["a"], q=np.zeros((1, 6)), modes=[1], freq_hz=[10.0])
    >>> model_frequencies(arm, m).shape
    (1,)
    """
    return match_frequencies(arm, modal, window).model_hz


def static_start(static: Problem) -> list:
    """The baseline (torsion scale per joint) fitted to the static data alone: where a
    search with modal data starts.  Frequencies (and shapes) are far from linear in the
    scales, and when the nominal model has two close modes in the wrong order, Gauss-Newton
    from it pairs them wrongly and strays (joint 4 at 0.3 of its stiffness: 8 of 10 seeds
    ended off, chi2_red above its band, from the nominal start).  Nominal scales when the
    static fit gives a scale <= 0."""
    from ..static.fit import baseline_effects, fit_model

    effects, free = baseline_effects(static.arm)
    prior = {f: (1.0, tol.baseline_prior_sd) for f in free}
    fr = fit_model(static, effects, free, np.ones(len(free)), prior)
    return list(fr.effects) if np.all(fr.theta > 0) else effects


class ModalProblem(Problem):
    """A static :class:`Problem` plus measured natural frequencies.

    Parameters
    ----------
    arm, data, sigma, noise_model, flexible
        As for :class:`~flexarm.validation.static.fit.Problem`.
    modal : ModalData
        Measured frequencies (one row per pose and mode).
    freq_noise : float
        Relative standard uncertainty of a frequency [-].
    """

    def __init__(self, arm: ArmModel, data: StaticData, sigma: float = tol.tracker_sigma,
                 noise_model: str = "shared", flexible: ArmModel | None = None,
                 modal: ModalData | None = None, freq_noise: float = tol.freq_noise):
        super().__init__(arm, data, sigma, noise_model, flexible)
        if modal is None:
            raise ValueError("ModalProblem needs modal data")
        if not freq_noise > 0:
            raise ValueError(f"freq_noise must be > 0, got {freq_noise}")
        self.modal, self.freq_noise = modal, float(freq_noise)
        self.start_effects = static_start(Problem(arm, data, sigma, noise_model, flexible))
        # measured modes without a model mode within the window (against the starting
        # model) are reported and left out, so the number of observations stays fixed
        match = self.initial_match(arm, modal)
        self.modal_keep = match.matched
        self.unmatched = tuple(match.unmatched(modal))
        if self.unmatched:
            log.warning("%d measured mode(s) left out, not matched to the model: %s",
                        len(self.unmatched), "; ".join(self.unmatched))
        self.f_meas = np.asarray(modal.freq_hz, float)[self.modal_keep]
        self.f_sd = self.freq_noise * self.f_meas

    def initial_match(self, arm: ArmModel, modal: ModalData):
        """The measured modes' partners in the starting model (frequency only here:
        :func:`match_frequencies`); a subclass pairs them otherwise."""
        return match_frequencies(arm, modal)

    @property
    def n_modal(self) -> int:
        """Number of measured frequencies in the fit (the matched ones)."""
        return len(self.f_sd)

    @property
    def n_obs(self) -> int:
        return super().n_obs + self.n_modal

    def frequencies(self, effects) -> np.ndarray:
        """(n_modal,) model frequencies [Hz] with ``effects``, assigned to the kept measured
        modes afresh for this model (no window: the assignment that minimises the modal
        chi-square, so it is continuous when two model modes cross)."""
        arm, _ = self.model(effects)
        keep = self.modal_keep
        return match_frequencies(arm, self.modal, None, keep).model_hz[keep]

    def wpredict(self, effects, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wpredict(effects, rows), self.frequencies(effects) / self.f_sd]

    def wy(self, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wy(rows), self.f_meas / self.f_sd]

    def n_obs_rows(self, rows: np.ndarray | None = None) -> int:
        return super().n_obs_rows(rows) + self.n_modal

    def modal_chi2(self, effects) -> float:
        """chi^2 of the frequencies alone."""
        r = (self.f_meas - self.frequencies(effects)) / self.f_sd
        return float(r @ r)


def virtual_modal(arm: ArmModel, poses: dict, effects: list[Effect] = (), n_modes: int = 4,
                  freq_noise: float = tol.freq_noise, seed: int = 0,
                  flexible: ArmModel | None = None) -> ModalData:
    """Measured-like natural frequencies of ``arm`` with ``effects`` (relative noise).

    Nonlinear joint laws do not enter (small-amplitude modal tests about the pose).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> q = np.zeros(arm.chain.n_joints)
    >>> virtual_modal(arm, {"A": q}, n_modes=2, freq_noise=0.0).freq_hz.shape
    (2,)
    """
    c, rest = split_links(effects)
    truth, _ = apply_effects(links_arm(arm, flexible, c), rest)
    names = list(poses)
    Q = np.array([np.asarray(poses[p], float) for p in names])
    F = np.atleast_2d(natural_frequencies(truth, Q))[:, :n_modes]
    rng = np.random.default_rng(seed)
    F = F * (1 + freq_noise * rng.standard_normal(F.shape))
    n = F.shape[1]
    q6 = np.zeros((len(names), 6))
    q6[:, :Q.shape[1]] = Q
    log.info("virtual modal lab: %d poses x %d modes", len(names), n)
    return ModalData(poses=np.repeat(names, n), q=np.repeat(q6, n, axis=0),
                     modes=np.tile(np.arange(1, n + 1), len(names)), freq_hz=F.ravel())


def _truth(arm: ArmModel, effects, flexible: ArmModel | None) -> ArmModel:
    c, rest = split_links(effects)
    return apply_effects(links_arm(arm, flexible, c), rest)[0]


def virtual_shapes(arm: ArmModel, poses: dict, points: Points, effects: list[Effect] = (),
                   n_modes: int = 6, freq_noise: float = tol.freq_noise,
                   shape_noise: float = 0.0, seed: int = 0, flexible: ArmModel | None = None,
                   builds=None) -> ShapeData:
    """Measured-like frequencies, damping ratios and mode shapes at every point (x, y,
    z) of ``arm`` with ``effects``: relative frequency noise, and shape noise
    ``shape_noise`` times each shape's largest entry (independent per DOF).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> pts = Points(nodes=[1, 2], links=[1, 2], positions=[[0.5, 0, 0], [1.0, 0, 0]])
    >>> s = virtual_shapes(two_link_arm(), {"A": np.zeros(2)}, pts, n_modes=2)
    >>> s.shapes.shape, s.dofs[:2]
    ((2, 6), ['1x', '1y'])
    """
    from .shapes import model_shape_data

    data = model_shape_data(_truth(arm, effects, flexible), poses, points, n_modes, builds)
    rng = np.random.default_rng(seed)
    f = data.freq_hz * (1 + freq_noise * rng.standard_normal(data.freq_hz.shape))
    peak = np.abs(data.shapes).max(axis=1, keepdims=True)
    phi = data.shapes + shape_noise * peak * rng.standard_normal(data.shapes.shape)
    log.info("virtual modal lab: %d poses x %d modes at %d DOFs", len(poses),
             len(data.freq_hz) // max(len(poses), 1), data.n_dofs)
    return ShapeData(poses=data.poses, q=data.q, modes=data.modes, freq_hz=f,
                     damping_ratio=data.damping_ratio, nodes=data.nodes, dirs=data.dirs,
                     shapes=phi)


def virtual_frfs(arm: ArmModel, poses: dict, points: Points, inputs, freq_hz,
                 effects: list[Effect] = (), noise: float = 0.02, seed: int = 0,
                 flexible: ArmModel | None = None, builds=None) -> list:
    """Measured-like receptances [m/N] at every point (x, y, z) per force at the
    ``inputs`` DOFs (``[(node, "y"), ...]``), one
    :class:`~flexarm.validation.data.formats.uff.UffFrf` per pose.

    Modal superposition over all modes with the model's modal damping; ``noise`` is a
    relative complex Gaussian error per frequency line, ``noise |H|`` (an averaged
    H1 estimate's scatter).
    """
    from ..data.formats.uff import UffFrf
    from .shapes import model_shapes

    truth = _truth(arm, effects, flexible)
    rng = np.random.default_rng(seed)
    out_nodes = np.repeat(points.nodes, 3)
    out_dirs = np.tile(list(DIRECTIONS), points.n_points)
    in_nodes = np.array([int(n) for n, _ in inputs])
    in_dirs = np.array([str(d) for _, d in inputs])
    w = 2 * np.pi * np.asarray(freq_hz, float)
    frfs = []
    for label, q in poses.items():
        f, zeta, phi = model_shapes(truth, q, points, np.r_[out_nodes, in_nodes],
                                    np.r_[out_dirs, in_dirs], None, builds)
        wr = 2 * np.pi * f
        den = wr[None, :] ** 2 - w[:, None] ** 2 + 2j * zeta * wr[None, :] * w[:, None]
        po, pi = phi[:, :len(out_nodes)], phi[:, len(out_nodes):]
        H = np.einsum("ro,fr,ri->oif", po, 1.0 / den, pi)  # (n_out, n_in, nf)
        H = H * (1 + noise / np.sqrt(2) * (rng.standard_normal(H.shape)
                                           + 1j * rng.standard_normal(H.shape)))
        q6 = np.zeros(6)
        q6[:len(q)] = q
        frfs.append(UffFrf(label, q6, np.asarray(freq_hz, float),
                           np.repeat(out_nodes, len(in_nodes)), np.repeat(out_dirs, len(in_nodes)),
                           np.tile(in_nodes, len(out_nodes)), np.tile(in_dirs, len(out_nodes)),
                           H.reshape(-1, len(w))))
    return frfs
