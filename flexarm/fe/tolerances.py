"""Numerical tolerances of the base layer (like trimesh's ``constants.tol``): algorithms
read ``tol.<name>``, never a literal; every layer keeps its own in its ``tolerances``."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Relative volume below which a tetrahedron counts as degenerate (``|V| / mean |V|``).
    degenerate_volume: float = 1e-12
    #: A Tet10 is straight-sided when every mid-edge node is within this fraction of the
    #: largest corner coordinate difference of its edge's centre.
    straight_midside: float = 1e-12
    #: Rigid-body modes: ``|omega^2|`` below this fraction of median(K_ii / M_ii) counts as zero.
    rigid_mode: float = 1e-12
    #: Eigenvalue shift for free parts, as a fraction of median(K_ii / M_ii): small, so that
    #: thin parts (first elastic omega^2 ~ 1e-9 of the mesh scale) still converge quickly.
    auto_shift: float = 1e-10
    #: ARPACK relative accuracy (0 = machine precision).
    arpack: float = 0.0
    #: SuperLU pivot below this fraction of the largest: the matrix counts as singular.
    singular_pivot: float = 1e-12
    #: Geometric coincidence of points [m].
    point_merge: float = 1e-9
    #: Mixed-precision refinement stops a column at this normwise backward error (a
    #: double-precision direct solve reaches 1e-17..1e-16).
    refinement: float = 1e-15
    #: ... and rejects the single-precision factor when a column stays above this.
    refinement_fail: float = 1e-12


tol = Tolerances()
