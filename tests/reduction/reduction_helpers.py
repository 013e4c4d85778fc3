"""Shared helpers of the reduction tests (imported as a plain module)."""

from __future__ import annotations

import numpy as np

from flexarm.fe import MATERIALS
from flexarm.reduction.interfaces import CylinderRegion

STEEL = MATERIALS["steel"]


def end_regions(length: float, width: float, name_a: str = "a", name_b: str = "b"):
    """Discs covering the two end faces of a bar along x (centres on the bar axis)."""
    c = width / 2
    return [CylinderRegion(name_a, (0.0, c, c), (1, 0, 0), 0.0, width, 1e-6),
            CylinderRegion(name_b, (length, c, c), (1, 0, 0), 0.0, width, 1e-6)]


def rel(a, b) -> float:
    """Largest absolute difference relative to the largest entry of ``b``."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.abs(a - b).max() / np.abs(b).max())
