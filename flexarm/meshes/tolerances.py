"""Tolerances of CAD checks and tetrahedralisation (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Plausible size of one robot part [m]: outside this, the units are probably wrong.
    part_size_min: float = 1e-3
    part_size_max: float = 20.0
    #: CAD surfaces: smallest / largest principal extent below this counts as flat.
    surface_flatness: float = 1e-9
    #: CAD surfaces: enclosed volume below this times (largest extent)^3 counts as zero.
    surface_min_volume: float = 1e-9
    #: Tetrahedra with a dihedral angle below this [deg] are slivers (the mesher retries).
    sliver_dihedral_deg: float = 5.0
    #: pytetwild envelope: allowed surface deviation / bounding-box diagonal.
    tet_envelope: float = 1e-3
    #: |V_tets - V_surface| / V_surface above which tetrahedralisation logs a warning.
    tet_volume_warn: float = 1e-2


tol = Tolerances()
