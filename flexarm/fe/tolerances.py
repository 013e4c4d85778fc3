"""All numerical tolerances in one place (like trimesh's ``constants.tol``).

Algorithms read ``tol.<name>``; tests may build their own :class:`Tolerances` with
``dataclasses.replace``.  No tolerance literal lives inside an algorithm.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Relative volume below which a tetrahedron counts as degenerate (|V| / mean |V|).
    degenerate_volume: float = 1e-12
    #: Relative asymmetry ||A - A^T||_max / ||A||_max accepted for "symmetric" matrices.
    symmetry: float = 1e-10
    #: Rigid-body modes: |omega^2| below this fraction of the shift scale counts as zero.
    rigid_mode: float = 1e-6
    #: Eigenvalue shift for free parts, as a fraction of median(K_ii / M_ii).
    auto_shift: float = 1e-6
    #: ARPACK relative accuracy (0 = machine precision).
    arpack: float = 0.0
    #: Plausible size of one robot part [m]: outside this, the units are probably wrong.
    part_size_min: float = 1e-3
    part_size_max: float = 20.0
    #: Geometric coincidence of points [m].
    point_merge: float = 1e-9


tol = Tolerances()
