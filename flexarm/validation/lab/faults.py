"""Faults of a measurement that no candidate effect models, for rehearsing the
diagnosis's "unexplained misfit" verdict on virtual-lab data
(:func:`~flexarm.validation.lab.virtual_lab.virtual_lab`).

Each function returns new :class:`~flexarm.validation.data.measurements.StaticData`:
a tracker that drifts in reading order, isolated glitches, a noise level larger than
the file states, and a smooth joint law outside the library.  Displacements stay
relative to each series' first reading, as the tracker file holds them.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...assembly.statics import joint_moments, series_starts
from ...assembly.system import ArmModel
from ...robot.kinematics import jacobian
from ..data.measurements import StaticData

__all__ = ["with_drift", "with_outliers", "with_stated_sigma", "with_joint_law"]


def _relative(data: StaticData, raw: np.ndarray) -> np.ndarray:
    """``raw`` (n, 3) errors of each reading as they enter relative displacements."""
    return raw - raw[series_starts(data.series)]


def with_drift(data: StaticData, rate) -> StaticData:
    """The tracker drifts by ``rate`` (3,) [m] per reading, in file order.

    Examples
    --------
    >>> d = StaticData(["a"] * 3, [0, 1, 2], np.zeros((3, 6)), np.zeros((3, 3)),
    ...                np.zeros((3, 3)))
    >>> with_drift(d, [5e-6, 0, 0]).disp[:, 0].tolist()
    [0.0, 5e-06, 1e-05]
    """
    t = np.arange(len(data.series), dtype=float)[:, None]
    return replace(data, disp=data.disp + _relative(data, t * np.asarray(rate, float)))


def with_outliers(data: StaticData, n: int, size: float, seed: int = 0) -> tuple[StaticData,
                                                                                np.ndarray]:
    """``n`` readings (not a series' first) off by ``size`` [m] in random directions.

    Returns the data and the rows of the glitched readings.
    """
    rng = np.random.default_rng(seed)
    ref = series_starts(data.series)
    rows = np.sort(rng.choice(np.flatnonzero(ref != np.arange(len(ref))), n, replace=False))
    v = rng.standard_normal((n, 3))
    raw = np.zeros_like(np.asarray(data.disp, float))
    raw[rows] = size * v / np.linalg.norm(v, axis=1, keepdims=True)
    return replace(data, disp=data.disp + _relative(data, raw)), rows


def with_stated_sigma(data: StaticData, sigma: float) -> StaticData:
    """The file states ``sigma`` [m] for every reading (whatever the true noise)."""
    return replace(data, sigma=np.full(len(data.series), float(sigma)))


def with_joint_law(data: StaticData, arm: ArmModel, joint: int, law) -> StaticData:
    """Joint ``joint`` turns ``law(tau)`` [rad] more at total torque ``tau`` [N m]
    (gravity included); seen at the TCP through the Jacobian of ``arm``."""
    tau = joint_moments(arm, data.q, data.force, data.moment)[:, joint, 0]
    J = jacobian(arm.chain, data.q)[:, :3, joint]
    return replace(data, disp=data.disp + _relative(data, J * law(tau)[:, None]))
