"""Modal data in the diagnosis: natural frequencies as extra observations, and a modal lab.

A measured frequency ``f_k`` of mode ``k`` (1 = lowest) at a pose is compared with the
``k``-th natural frequency of the model at that pose; the noise is relative,
``sd = freq_noise * f_k`` (0.5 % by default, ``tol.freq_noise``), independent between
modes and poses.  :class:`ModalProblem` appends these whitened residuals to the static
GLS residuals of :class:`~flexarm.validation.fit.Problem`, so every fit, score test and
held-out check of the diagnosis uses both.  Frequency sensitivities to the parameters
are finite differences of the model eigenvalues (as for the static part).

Why this separates link flexibility: static TCP compliance is a sum of joint and link
compliances, so fitted joint compliances can absorb the links; the frequencies weigh
the same compliances with the mass distribution, differently per mode and pose, so the
E-model whose joints were softened to match the statics cannot match them.
"""

from __future__ import annotations

import logging

import numpy as np

from ..assembly.analyses import natural_frequencies
from ..assembly.system import ArmModel
from ..fe.tolerances import tol
from .effects import Effect, apply_effects
from .fit import Problem
from .linkflex import links_arm, split_links
from .measurements import ModalData, StaticData

__all__ = ["ModalProblem", "model_frequencies", "virtual_modal"]

log = logging.getLogger(__name__)


def model_frequencies(arm: ArmModel, modal: ModalData) -> np.ndarray:
    """(n,) model natural frequency [Hz] for each row (pose, mode) of ``modal``.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> m = ModalData(poses=["a"], q=np.zeros((1, 6)), modes=[1], freq_hz=[10.0])
    >>> model_frequencies(arm, m).shape
    (1,)
    """
    n = arm.chain.n_joints
    uq, inv = np.unique(np.asarray(modal.q, float)[:, :n], axis=0, return_inverse=True)
    F = np.atleast_2d(natural_frequencies(arm, uq))
    k = np.asarray(modal.modes) - 1
    if k.min() < 0 or k.max() >= F.shape[1]:
        raise ValueError(f"modal data ask for modes 1..{k.max() + 1}; the model has "
                         f"{F.shape[1]}")
    return F[inv.ravel(), k]


class ModalProblem(Problem):
    """A static :class:`Problem` plus measured natural frequencies.

    Parameters
    ----------
    arm, data, sigma, noise_model, flexible
        As for :class:`~flexarm.validation.fit.Problem`.
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
        self.f_sd = self.freq_noise * np.asarray(modal.freq_hz, float)

    @property
    def n_modal(self) -> int:
        return len(self.f_sd)

    @property
    def n_obs(self) -> int:
        return super().n_obs + self.n_modal

    def frequencies(self, effects) -> np.ndarray:
        """(n_modal,) model frequencies [Hz] with ``effects``."""
        arm, _ = self.model(effects)
        return model_frequencies(arm, self.modal)

    def wpredict(self, effects, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wpredict(effects, rows), self.frequencies(effects) / self.f_sd]

    def wy(self, rows: np.ndarray | None = None) -> np.ndarray:
        return np.r_[super().wy(rows), np.asarray(self.modal.freq_hz, float) / self.f_sd]

    def n_obs_rows(self, rows: np.ndarray | None = None) -> int:
        return super().n_obs_rows(rows) + self.n_modal

    def modal_chi2(self, effects) -> float:
        """chi^2 of the frequencies alone."""
        r = (np.asarray(self.modal.freq_hz) - self.frequencies(effects)) / self.f_sd
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
