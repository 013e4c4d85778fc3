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
    #: Rigid-body modes: |omega^2| below this fraction of median(K_ii / M_ii) counts as zero.
    rigid_mode: float = 1e-12
    #: Eigenvalue shift for free parts, as a fraction of median(K_ii / M_ii): small, so that
    #: thin parts (first elastic omega^2 ~ 1e-9 of the mesh scale) still converge quickly.
    auto_shift: float = 1e-10
    #: ARPACK relative accuracy (0 = machine precision).
    arpack: float = 0.0
    #: Plausible size of one robot part [m]: outside this, the units are probably wrong.
    part_size_min: float = 1e-3
    part_size_max: float = 20.0
    #: SuperLU pivot below this fraction of the largest: the matrix counts as singular.
    singular_pivot: float = 1e-12
    #: Geometric coincidence of points [m].
    point_merge: float = 1e-9
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

    #: Region nodes: smallest / largest eigenvalue of the (weighted) second-moment tensor
    #: about the centroid below which they count as collinear (cannot carry a rotation).
    region_collinear: float = 1e-8
    #: Nodes needed at least in a region to carry 6 DOFs (3 non-collinear points).
    min_region_nodes: int = 3
    #: Relative asymmetry accepted when loading a superelement file.
    file_symmetry: float = 1e-10
    #: Most negative eigenvalue of a loaded K accepted, relative to its largest.
    file_psd: float = 1e-8
    #: Render-probe subprocess time limit [s].
    render_probe_seconds: float = 60.0



tol = Tolerances()
