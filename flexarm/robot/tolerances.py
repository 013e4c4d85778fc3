"""Tolerances of paths, quaternions and RAPID values (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Unit-quaternion check of RAPID robtargets (they are printed to ~1e-4..1e-9).
    quaternion_norm: float = 1e-4
    #: Three points are collinear when the triangle area is below this times |a||b|.
    collinear: float = 1e-9
    #: Below this angle [rad] SLERP falls back to normalised linear interpolation.
    slerp_small_angle: float = 1e-9


tol = Tolerances()
