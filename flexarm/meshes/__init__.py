"""CAD surface in -> checked, unit-scaled -> tetrahedra out (the ``meshes`` layer).

Imports only :mod:`flexarm.fe`.  Each name below is imported from its module when first
used (:func:`~flexarm.fe.lazy.lazy_exports`): reading a volume mesh or running one Gmsh
try does not load trimesh.
"""

from ..fe.lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    ".auto_mesher": ("SurfaceMesh", "cached_surface_mesh", "mesh_surface"),
    ".gmsh_mesher": ("tetrahedralize_gmsh",),
    ".hollow": ("HollowShell", "hollow_surface"),
    ".pipeline": ("mesh_part", "tetrahedralizer"),
    ".primitives": ("bar_surface", "cylinder_surface", "hollow_link_surface", "write_surface"),
    ".quality": ("QualityReport", "dihedral_angles", "mesh_quality", "radius_ratios"),
    ".repair": ("check_surface", "repair_surface"),
    ".surface": ("load_surface",),
    ".tet_cache": ("MESHER_SETTINGS", "MESHERS"),
    ".tetwild": ("tetrahedralize",),
    ".volume_io": ("read_volume_mesh", "write_volume_mesh"),
    ".wall": ("bending_ratio", "wall_for_mass"),
})
