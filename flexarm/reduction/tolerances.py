"""Tolerances of interface regions and superelement files (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Region nodes: smallest / largest eigenvalue of the (weighted) second-moment tensor
    #: about the centroid below which they count as collinear (cannot carry a rotation).
    region_collinear: float = 1e-8
    #: Nodes needed at least in a region to carry 6 DOFs (3 non-collinear points).
    min_region_nodes: int = 3
    #: Relative asymmetry accepted when loading a superelement file.
    file_symmetry: float = 1e-10
    #: Loaded superelements: ``omega^2`` of ``K phi = omega^2 M phi`` below this times the
    #: largest counts as zero (a rigid-body mode; reduced links keep them below ~1e-10);
    #: more negative is refused (K not positive semi-definite).
    file_psd: float = 1e-8
    #: Smallest eigenvalue of a loaded M accepted, relative to its largest.
    file_mass_definite: float = 1e-12
    #: Largest ``|K R| / (|K| |R|)`` of the rigid motions ``R`` of a loaded superelement's
    #: boundary nodes (reduced links: below 1e-10).
    file_rigid: float = 1e-8
    #: Largest relative difference of the mass a loaded M holds and the file's ``mass``
    #: (both come from the same matrix when written: ~1e-16).
    file_mass: float = 1e-9
    #: Largest ``|A_ij - A_ji| / sqrt(|A_ii A_jj|)`` of a matrix written to OP4 as
    #: symmetric (form 6): round-off of an assembly, far below any modelling asymmetry.
    op4_symmetry: float = 1e-12
    #: Render-probe subprocess time limit [s].
    render_probe_seconds: float = 60.0


tol = Tolerances()
