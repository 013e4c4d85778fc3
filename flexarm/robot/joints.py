"""Joint models: a 6×6 spring in the joint frame, rigid directions eliminated exactly.

The joint frame has its first axis along the joint axis.  Its six relative DOFs
are ordered (u_axial, u_radial1, u_radial2, theta_torsion, theta_tilt1,
theta_tilt2).  A direction with infinite stiffness is *rigid*: it never becomes a
coordinate of the assembled system (no penalty numbers).  Finite directions become
independent coordinates ``delta`` carrying the diagonal spring.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numpy as np

from ..fe.typing import ArrayLike, FloatArray

__all__ = ["JointModel", "joint_basis", "DOF_NAMES", "SOURCES"]

#: Names of the six relative joint DOFs, in the order of :attr:`JointModel.stiffness`.
DOF_NAMES = ("axial", "radial1", "radial2", "torsion", "tilt1", "tilt2")
#: Where a joint model's stiffness comes from: given (a datasheet, a measurement, an
#: identification) or a placeholder (a default that nobody measured, e.g. a URDF import).
SOURCES = ("given", "placeholder")


@dataclass(frozen=True)
class JointModel:
    """Linear spring of one revolute joint in its joint frame.

    Parameters
    ----------
    torsion : float
        Gear (drive-train) torsional stiffness about the axis [N m/rad]; ``inf`` = locked.
    tilt : float
        Bearing tilt stiffness about each axis perpendicular to the joint axis
        [N m/rad]; ``inf`` (default) = rigid.
    tilt2 : float or None
        Tilt stiffness about the second perpendicular axis (``radial2`` of
        :func:`joint_basis`) [N m/rad] when it differs from ``tilt`` (equivalent
        E-model joints, :mod:`~flexarm.assembly.equivalent`); None = ``tilt``.
    radial : float
        Bearing radial stiffness [N/m]; ``inf`` = rigid.
    axial : float
        Bearing axial stiffness [N/m]; ``inf`` = rigid.
    damping_ratio : float
        Modal damping ratio [-] of the energy stored in this joint.
    rayleigh : (2,) float or None
        ``(alpha [1/s], beta [s])``: if given, the joint's ratio at angular frequency
        omega is ``alpha / (2 omega) + beta omega / 2`` instead of ``damping_ratio``.
    source : {"given", "placeholder"}
        Where the stiffness values come from (:data:`SOURCES`); ``"placeholder"`` marks
        defaults nobody measured (a URDF has no joint stiffness).  It does not take part
        in comparisons: two models with the same springs are equal.

    Examples
    --------
    >>> jm = JointModel(torsion=5e5, tilt=2e7)
    >>> jm.free_dofs.tolist(), jm.free_stiffness.tolist()
    ([3, 4, 5], [500000.0, 20000000.0, 20000000.0])
    >>> JointModel(torsion=1e6, source="placeholder").is_placeholder
    True
    """

    torsion: float
    tilt: float = math.inf
    radial: float = math.inf
    axial: float = math.inf
    damping_ratio: float = 0.02
    rayleigh: tuple[float, float] | None = None
    tilt2: float | None = None
    source: str = field(default="given", compare=False)

    def __post_init__(self) -> None:
        if self.source not in SOURCES:
            raise ValueError(f"joint stiffness source must be one of {', '.join(SOURCES)}, "
                             f"got '{self.source}'")
        for name in ("torsion", "tilt", "radial", "axial", "tilt_2"):
            v = float(getattr(self, name))
            if not v > 0:
                label = "tilt2" if name == "tilt_2" else name
                raise ValueError(f"joint {label} stiffness must be > 0 (or inf for rigid), got {v}")
        if not 0 <= self.damping_ratio < 1:
            raise ValueError(f"joint damping_ratio must be in [0, 1), got {self.damping_ratio}")
        if self.rayleigh is not None:
            a, b = (float(v) for v in self.rayleigh)
            if a < 0 or b < 0:
                raise ValueError(f"joint rayleigh (alpha, beta) must be >= 0, got {self.rayleigh}")
            object.__setattr__(self, "rayleigh", (a, b))
        if np.isfinite(self.tilt) != np.isfinite(self.tilt_2):
            raise ValueError(f"joint tilt and tilt2 must both be finite or both rigid, got "
                             f"{self.tilt} and {self.tilt2}")

    @property
    def is_placeholder(self) -> bool:
        """True when the stiffness values are unmeasured defaults (``source="placeholder"``)."""
        return self.source == "placeholder"

    @property
    def tilt_2(self) -> float:
        """Tilt stiffness about ``radial2`` [N m/rad] (``tilt2``, or ``tilt`` if None)."""
        return float(self.tilt if self.tilt2 is None else self.tilt2)

    @property
    def stiffness(self) -> FloatArray:
        """(6,) diagonal stiffness in the joint frame, ``inf`` for rigid directions."""
        return np.array(
            [self.axial, self.radial, self.radial, self.torsion, self.tilt, self.tilt_2], float
        )

    @cached_property
    def free_dofs(self) -> np.ndarray:
        """(k,) int: joint-frame DOFs that are coordinates of the assembled system
        (read-only: kept with the frozen joint, which every pose's assembly asks)."""
        dofs = np.flatnonzero(np.isfinite(self.stiffness))
        dofs.setflags(write=False)
        return dofs

    @property
    def free_stiffness(self) -> FloatArray:
        """(k,) float: spring stiffness of the free DOFs [N/m or N m/rad]."""
        return self.stiffness[self.free_dofs]

    def ratio(self, omega: ArrayLike) -> FloatArray:
        """Damping ratio [-] at angular frequency ``omega`` [rad/s]."""
        omega = np.asarray(omega, dtype=float)
        if self.rayleigh is None:
            return np.full(omega.shape, self.damping_ratio)
        a, b = self.rayleigh
        return a / (2 * np.maximum(omega, np.finfo(float).tiny)) + b * omega / 2


def joint_basis(axis: ArrayLike) -> FloatArray:
    """(3, 3) right-handed orthonormal basis with columns (axis, radial1, radial2).

    ``radial1`` is the unit vector of the coordinate axis least aligned with ``axis``
    made orthogonal to it, so the basis is deterministic.  Read-only, and the same array
    for the same axis: a chain's axes are fixed, and every pose's assembly asks for them.

    Examples
    --------
    >>> joint_basis([0.0, 0.0, 2.0]).tolist()
    [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
    """
    return _basis(tuple(float(v) for v in np.asarray(axis, dtype=float).reshape(3)))


@lru_cache(maxsize=1024)
def _basis(axis: tuple[float, float, float]) -> FloatArray:
    a = np.asarray(axis)
    a = a / np.linalg.norm(a)
    helper = np.eye(3)[int(np.argmin(np.abs(a)))]
    b = helper - (helper @ a) * a
    b /= np.linalg.norm(b)
    basis = np.column_stack([a, b, np.cross(a, b)])
    basis.setflags(write=False)
    return basis
