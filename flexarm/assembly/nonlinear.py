"""Nonlinear joint laws for static solves with gravity preload.

Each law gives the joint's *extra* torsional deflection [rad] on top of its linear
gear spring ``tau / k`` as a function of the joint's total torque history
``tau`` [N m] (gravity + external load, about the joint axis, in measurement order).
The history is the last axis; leading axes are independent histories.  Laws are
frozen dataclasses and evaluate vectorised over all readings.

* :class:`Backlash` -- a dead band of width ``b``: the gear rests on the flank that
  gravity loads; when the total torque changes sign the joint crosses the band.
* :class:`Hardening` -- piecewise-linear gear stiffness: ``K1`` for
  ``|tau| < threshold``, ``K2`` (the linear model's stiffness) above.
* :class:`Hysteresis` -- lost motion with memory (a Prandtl play operator of torque
  radius ``r``): the extra deflection changes by ``lost_motion`` only after the
  torque has reversed by ``2 r``.  The state starts on the branch of the first load
  change (the lab preconditions each series), so monotonic loading shows nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.typing import ArrayLike, FloatArray

__all__ = ["Backlash", "Hardening", "Hysteresis", "JointLaw", "play_operator"]


@dataclass(frozen=True)
class Backlash:
    """Dead band of total width ``width`` [rad] about the gravity-loaded flank.

    Parameters
    ----------
    width : float
        Backlash (total play) [rad], >= 0.
    smoothing : float
        Torque [N m] over which the crossing is smoothed (``tanh``); 0 = a sharp step.

    Examples
    --------
    >>> Backlash(1e-4).deflection([-10.0, 5.0]).tolist()
    [-5e-05, 5e-05]
    """

    width: float
    smoothing: float = 0.0

    def __post_init__(self) -> None:
        if not self.width >= 0 or not self.smoothing >= 0:
            raise ValueError(f"backlash width and smoothing must be >= 0, got "
                             f"{self.width}, {self.smoothing}")

    def shape(self, tau: ArrayLike) -> FloatArray:
        """Unit-width extra deflection [-] (``b = 1``): ``sign(tau) / 2``."""
        tau = np.asarray(tau, dtype=float)
        if self.smoothing > 0:
            return 0.5 * np.tanh(tau / self.smoothing)
        return 0.5 * np.sign(tau)

    def deflection(self, tau: ArrayLike) -> FloatArray:
        """Extra deflection [rad] for torques ``tau`` (..., n) [N m]."""
        return self.width * self.shape(tau)


@dataclass(frozen=True)
class Hardening:
    """Softer gear below a torque threshold (piecewise-linear stiffness K1 -> K2).

    Parameters
    ----------
    threshold : float
        Torque [N m] above which the stiffness is ``K2`` (the linear spring).
    extra_compliance : float
        ``1/K1 - 1/K2`` [rad/(N m)], >= 0 for a gear that stiffens with load.

    Examples
    --------
    >>> h = Hardening.from_stiffness(k1=1e5, k2=2e5, threshold=100.0)
    >>> h.deflection([50.0, 300.0]).tolist()
    [0.00025, 0.0005]
    """

    threshold: float
    extra_compliance: float

    def __post_init__(self) -> None:
        if not self.threshold > 0:
            raise ValueError(f"hardening threshold must be > 0 N m, got {self.threshold}")

    @classmethod
    def from_stiffness(cls, k1: float, k2: float, threshold: float) -> Hardening:
        """Law from the low-torque and high-torque stiffness [N m/rad]."""
        return cls(threshold, 1.0 / k1 - 1.0 / k2)

    def shape(self, tau: ArrayLike) -> FloatArray:
        """Torque carried by the soft part [N m]: ``clip(tau, -threshold, threshold)``."""
        return np.clip(np.asarray(tau, dtype=float), -self.threshold, self.threshold)

    def deflection(self, tau: ArrayLike) -> FloatArray:
        """Extra deflection [rad] for torques ``tau`` (..., n) [N m]."""
        return self.extra_compliance * self.shape(tau)


def play_operator(tau: ArrayLike, radius: float) -> FloatArray:
    """Prandtl play operator ``z - tau`` along the last axis, in [-radius, radius] [N m].

    ``z`` follows ``tau`` with a dead zone of half-width ``radius``; its initial state is
    on the branch of the first load change (``z0 = tau0 - radius sign(tau1 - tau0)``).
    """
    tau = np.asarray(tau, dtype=float)
    if tau.shape[-1] == 0:
        return np.zeros_like(tau)
    z = np.zeros_like(tau)
    first = tau[..., 1] - tau[..., 0] if tau.shape[-1] > 1 else np.zeros(tau.shape[:-1])
    z[..., 0] = tau[..., 0] - radius * np.where(first < 0, -1.0, 1.0)
    for k in range(1, tau.shape[-1]):
        z[..., k] = np.clip(z[..., k - 1], tau[..., k] - radius, tau[..., k] + radius)
    return z - tau


@dataclass(frozen=True)
class Hysteresis:
    """Lost motion with memory: a loop of width ``lost_motion`` [rad].

    Parameters
    ----------
    lost_motion : float
        Width of the deflection loop [rad], >= 0.
    radius : float
        Torque reversal [N m] needed to cross half the loop (friction torque).

    Examples
    --------
    >>> h = Hysteresis(2e-4, radius=10.0)
    >>> h.deflection([0.0, 100.0, 200.0, 100.0, 0.0]).round(6).tolist()  # unload moves it
    [-0.0001, -0.0001, -0.0001, 0.0001, 0.0001]
    """

    lost_motion: float
    radius: float

    def __post_init__(self) -> None:
        if not self.radius > 0:
            raise ValueError(f"hysteresis radius must be > 0 N m, got {self.radius}")

    def shape(self, tau: ArrayLike) -> FloatArray:
        """Unit-width loop [-] in [-1/2, 1/2] along the last axis (history)."""
        return play_operator(tau, self.radius) / (2 * self.radius)

    def deflection(self, tau: ArrayLike) -> FloatArray:
        """Extra deflection [rad] for a torque history ``tau`` (..., n) [N m]."""
        return self.lost_motion * self.shape(tau)


JointLaw = Backlash | Hardening | Hysteresis
