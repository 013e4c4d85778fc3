"""CAD surface in -> checked, unit-scaled -> tetrahedra out (the ``meshes`` layer).

Imports only :mod:`flexarm.fe`.
"""

from .auto_mesher import SurfaceMesh, cached_surface_mesh, mesh_surface
from .gmsh_mesher import tetrahedralize_gmsh
from .hollow import HollowShell, hollow_surface
from .pipeline import MESHER_SETTINGS, MESHERS, mesh_part, tetrahedralizer
from .primitives import bar_surface, cylinder_surface, hollow_link_surface, write_surface
from .quality import QualityReport, dihedral_angles, mesh_quality, radius_ratios
from .repair import check_surface, repair_surface
from .surface import load_surface
from .tetwild import tetrahedralize
from .volume_io import read_volume_mesh, write_volume_mesh
from .wall import bending_ratio, wall_for_mass

__all__ = [
    "MESHERS",
    "MESHER_SETTINGS",
    "SurfaceMesh",
    "HollowShell",
    "QualityReport",
    "bar_surface",
    "bending_ratio",
    "cached_surface_mesh",
    "check_surface",
    "cylinder_surface",
    "dihedral_angles",
    "hollow_link_surface",
    "hollow_surface",
    "load_surface",
    "mesh_surface",
    "mesh_part",
    "mesh_quality",
    "radius_ratios",
    "read_volume_mesh",
    "repair_surface",
    "tetrahedralize",
    "tetrahedralize_gmsh",
    "tetrahedralizer",
    "wall_for_mass",
    "write_surface",
    "write_volume_mesh",
]
