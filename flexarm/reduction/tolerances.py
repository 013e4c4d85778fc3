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
    #: Most negative eigenvalue of a loaded K accepted, relative to its largest.
    file_psd: float = 1e-8
    #: Largest ``|A_ij - A_ji| / sqrt(|A_ii A_jj|)`` of a matrix written to OP4 as
    #: symmetric (form 6): round-off of an assembly, far below any modelling asymmetry.
    op4_symmetry: float = 1e-12
    #: Render-probe subprocess time limit [s].
    render_probe_seconds: float = 60.0


tol = Tolerances()
