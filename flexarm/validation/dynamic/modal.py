"""Modal data in the diagnosis: natural frequencies as extra observations, and a modal lab.

A measured frequency at a pose is compared with the model mode it is *assigned* to, not
with the model mode of the same number: the file's mode numbers are the lab's labels,
and two close modes may be listed in the other order (or the model's two modes may swap
places as the fit changes a stiffness).  :func:`match_modes` assigns, per pose, the
measured frequencies to distinct model modes by minimising the sum of squared relative
differences ``((f_model - f_meas) / f_meas)^2`` (``scipy.optimize.linear_sum_assignment``),
which is the frequencies' chi-square: the assignment is the most likely one.  That is
how ``compare`` tabulates them (a measured mode with no model mode within a factor
``1 + MATCH_WINDOW`` is reported *unmatched*).  Inside a diagnosis,
:class:`ModalProblem` pairs them afresh in every model it evaluates, inside a window and
with a fixed cost for a mode left without a partner
(:mod:`~flexarm.validation.dynamic.pairing`): no measured mode is dropped.  The noise is relative,
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
from ...assembly.effects import at_pose
from ...assembly.system import ArmModel
from ..data.measurements import ModalData, StaticData
from ..static.fit import Problem
from ..tolerances import tol
from .pairing import lonely_lines, pair_in_window

__all__ = ["ModalProblem", "ModeMatch", "MATCH_WINDOW", "match_modes", "match_frequencies",
           "model_frequencies", "static_start"]

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

    Every evaluation of a model pairs the measured modes with its modes afresh, pose by
    pose, inside a frequency window (:mod:`~flexarm.validation.dynamic.pairing`): a
    measured mode without a partner in that model stays in the data at a fixed cost
    (residual ``C = window / freq_noise``), so the observations never change in number and a
    model that creates the missing mode is rewarded.  That fixed cost counts in the
    chi-square a search compares (:attr:`FitResult.chi2`) but not in chi^2_red
    (:meth:`penalty`), so a measured mode that no model explains (a fixture resonance, a
    spurious pole) does not inflate the static fit's intervals; the diagnosis names it.

    Parameters
    ----------
    arm, data, sigma, noise_model, flexible
        As for :class:`~flexarm.validation.static.fit.Problem`.
    modal : ModalData
        Measured frequencies (one row per pose and mode).
    freq_noise : float
        Relative standard uncertainty of a frequency [-].
    window : float
        Largest relative frequency difference of a pair [-] (``tol.pair_window``).
    """

    def __init__(self, arm: ArmModel, data: StaticData, sigma: float = tol.tracker_sigma,
                 noise_model: str = "shared", flexible: ArmModel | None = None,
                 modal: ModalData | None = None, freq_noise: float = tol.freq_noise,
                 window: float = tol.pair_window):
        super().__init__(arm, data, sigma, noise_model, flexible)
        if modal is None:
            raise ValueError("ModalProblem needs modal data")
        if not freq_noise > 0:
            raise ValueError(f"freq_noise must be > 0, got {freq_noise}")
        if not 0 < window < 1:
            raise ValueError(f"the pairing window must lie in (0, 1), got {window}")
        self.modal, self.freq_noise, self.window = modal, float(freq_noise), float(window)
        self.f_meas = np.asarray(modal.freq_hz, float)
        self.f_sd = self.freq_noise * self.f_meas
        self.modal_keep = np.ones(len(self.f_meas), bool)
        n = arm.chain.n_joints
        self.modal_uq, inv = np.unique(np.asarray(modal.q, float)[:, :n], axis=0,
                                       return_inverse=True)
        self.modal_pose = inv.ravel()
        self._pairings: dict = {}
        self._batch = (None, None)
        #: The static data alone, as a problem of their own (starts of nonlinear fits).
        self.static_problem = Problem(arm, data, sigma, noise_model, flexible)
        self.start_effects = static_start(self.static_problem)
        self.unmatched = tuple(self.lonely_lines(self.start_effects))
        if self.unmatched:
            log.info("%d measured mode(s) without a partner in the starting model: %s",
                     len(self.unmatched), "; ".join(self.unmatched))

    def discount(self, rows) -> None:
        super().discount(rows)
        if hasattr(self, "static_problem"):
            self.static_problem.discount(rows)

    # ----- pairing
    def pose_terms(self, arm: ArmModel, p: int, r: np.ndarray) -> dict:
        """What pairing needs at unique pose ``p`` (measured rows ``r``) of ``arm`` (the
        model at that pose, :func:`~flexarm.assembly.effects.at_pose`): the model's
        frequencies ``f`` [Hz]; a subclass with shapes adds ``shape_cost``,
        ``lonely_shape_cost``, ``mac`` and the model ``shapes``."""
        if self._batch[0] is not arm:  # the same arm at every pose: one batched solve
            self._batch = (arm, np.atleast_2d(natural_frequencies(arm, self.modal_uq)))
        return {"f": self._batch[1][p]}

    def pairing(self, effects) -> dict:
        """The measured modes paired with the modes of the model with ``effects``:
        per row ``model_hz`` (NaN if none), ``model_mode`` (1-based, 0 if none),
        ``paired``, ``cost`` (its chi-square share) and the terms of
        :meth:`pose_terms` per pose (cached for the last few models)."""
        key = tuple(effects)
        if key in self._pairings:
            return self._pairings[key]
        arm, _ = self.model(effects)
        self._batch = (None, None)
        m = len(self.f_meas)
        hz, mode = np.full(m, np.nan), np.zeros(m, int)
        paired, cost = np.zeros(m, bool), np.zeros(m)
        terms = {}
        for p in np.unique(self.modal_pose):
            r = np.flatnonzero(self.modal_pose == p)
            tp = terms[p] = self.pose_terms(at_pose(arm, effects, self.modal_uq[p]), p, r)
            pr = pair_in_window(self.f_meas[r], tp["f"], self.window, self.freq_noise,
                                tp.get("shape_cost"), tp.get("lonely_shape_cost"),
                                tp.get("mac"), tp.get("mac_threshold", 0.0))
            k = pr.model
            hz[r] = np.where(k >= 0, tp["f"][np.maximum(k, 0)], np.nan)
            mode[r], paired[r], cost[r] = np.where(k >= 0, k + 1, 0), k >= 0, pr.cost
        out = {"model_hz": hz, "model_mode": mode, "paired": paired, "cost": cost,
               "terms": terms}
        if len(self._pairings) > 8:
            self._pairings.clear()
        self._pairings[key] = out
        return out

    def lonely_lines(self, effects) -> list[str]:
        """One line per measured mode without a partner in the model with ``effects``."""
        return lonely_lines(self.modal.poses, self.f_meas, self.pairing(effects)["paired"])

    @property
    def n_modal(self) -> int:
        """Number of measured frequencies in the fit (all of them)."""
        return len(self.f_sd)

    @property
    def n_obs(self) -> int:
        return super().n_obs + self.n_modal

    def frequencies(self, effects) -> np.ndarray:
        """(n_modal,) model frequency [Hz] of each measured mode's partner; a mode without
        one gets ``f_meas - C sd``, so its residual is the fixed ``C``."""
        pr = self.pairing(effects)
        lonely = self.f_meas - self.window / self.freq_noise * self.f_sd
        return np.where(pr["paired"], pr["model_hz"], lonely)

    def wpredict(self, effects, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wpredict(effects, rows), self.frequencies(effects) / self.f_sd]

    def wy(self, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wy(rows), self.f_meas / self.f_sd]

    def n_obs_rows(self, rows: np.ndarray | None = None) -> int:
        return super().n_obs_rows(rows) + self.n_modal

    def observations_per_mode(self) -> int:
        """Observations one measured mode adds (its frequency)."""
        return 1

    def penalty(self, effects) -> tuple[float, int]:
        """(chi-square, observations) of the measured modes without a partner in the model
        with ``effects``: their fixed cost, left out of chi^2_red."""
        pr = self.pairing(effects)
        lonely = ~pr["paired"]
        return float(pr["cost"][lonely].sum()), int(lonely.sum()) * self.observations_per_mode()

    def modal_chi2(self, effects) -> float:
        """chi^2 of the frequencies alone (fixed cost of unpaired modes included)."""
        r = (self.f_meas - self.frequencies(effects)) / self.f_sd
        return float(r @ r)
