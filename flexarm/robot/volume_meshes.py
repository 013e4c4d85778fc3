"""A link's volume meshes given as files: tetrahedra read instead of meshed.

A link may name, per tet edge length, a volume-mesh file (``.vtu``, ``.msh``, ``.vtk``
or flexarm ``.npz``, read by :func:`~flexarm.meshes.volume_io.read_volume_mesh`) in
metres and in the link frame::

    [[links]]
    name = "base"
    mesh = "meshes/base.stl"
    volume_meshes = { "0.03" = "tets/base_30mm.vtu" }

Every analysis that meshes the link at that edge length (builds, full-FE references,
mass properties, studies) then uses those elements.  Two uses: a mesh made in another
pre-processor, and *pinned* meshes: fTetWild does not give the same tetrahedra twice,
so a shipped robot whose figures must reproduce to the printed digits (the demo arm)
pins the meshes it was published with.  A Tet4 file serves ``element_order = 2`` by
adding straight-edge mid-side nodes.

A file that is not a mesh of the link's CAD is refused: its bounding box must be the
CAD's within :data:`BOX_TOLERANCE` of the CAD's diagonal, and its volume within
:data:`VOLUME_TOLERANCE` of the solid the CAD encloses.
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..fe.mesh import TetMesh
from .description import Link

__all__ = ["BOX_TOLERANCE", "VOLUME_TOLERANCE", "pinned_mesh", "pinned_size"]

#: Largest relative difference between a volume mesh's volume and its CAD's [-]: a mesh
#: whose edge is coarse for the part loses its curved faces' segments (Gmsh's chords on
#: the UR10's 0.13 m wrist_3_link at a 30 mm edge: -9 %, its base_link -6 %); a file in
#: the wrong units is off by a factor of 1e9.
VOLUME_TOLERANCE = 0.25
#: Largest distance between a volume mesh's bounding box and its CAD's, over the CAD's
#: diagonal [-]: the meshes flexarm makes stay within 0.15 % (fTetWild's envelope, Gmsh's
#: chords touch the CAD's extreme points); another link's mesh is off by far more.
BOX_TOLERANCE = 0.01


def pinned_size(link: Link, mesh_size: float) -> float | None:
    """The key of ``link.volume_meshes`` equal to ``mesh_size`` [m] (to 1e-9), or None.

    Examples
    --------
    >>> from pathlib import Path
    >>> from flexarm.fe.material import material_from_string
    >>> lk = Link("arm", None, material_from_string("steel"),
    ...           volume_meshes={0.03: Path("arm_30mm.vtu")})
    >>> pinned_size(lk, 0.030000000001), pinned_size(lk, 0.045)
    (0.03, None)
    """
    return next((h for h in link.volume_meshes if math.isclose(h, mesh_size, rel_tol=1e-9)),
                None)


def pinned_mesh(link: Link, mesh_size: float, order: int = 1) -> TetMesh | None:
    """The link's tetrahedra at ``mesh_size`` [m] read from its volume-mesh file, or None
    when the link names no file for that size.

    Parameters
    ----------
    link : Link
    mesh_size : float
        Tet edge length [m] the caller would mesh at.
    order : {1, 2}
        Element order wanted; a Tet4 file is promoted to Tet10.

    Raises
    ------
    ValueError
        The file holds Tet10 where Tet4 is wanted, or its volume is not the CAD's.
    """
    h = pinned_size(link, mesh_size)
    if h is None:
        return None
    path = Path(link.volume_meshes[h])
    stat = path.stat()
    mesh = _read_checked(str(path), stat.st_mtime_ns, stat.st_size, link.name, f"{h:g}",
                         str(link.mesh) if link.mesh else "", link.units)
    if mesh.order == order:
        return mesh
    if mesh.order == 1 and order == 2:
        return mesh.to_tet10()
    raise ValueError(f"links.{link.name}.volume_meshes.'{h:g}': {path.name} holds Tet10 "
                     f"elements, the model asks for element_order = {order}")


@lru_cache(maxsize=64)
def _read_checked(path: str, mtime_ns: int, n_bytes: int, name: str, key: str, cad: str,
                  units: str) -> TetMesh:
    """Read once per file version; check the volume against the CAD's."""
    from ..meshes.volume_io import read_volume_mesh

    mesh = read_volume_mesh(path)
    if cad:
        solid, bounds = _cad_volume_and_bounds(cad, units)
        volume = float(mesh.volumes().sum())
        off = max(np.abs(mesh.points.min(axis=0) - bounds[0]).max(),
                  np.abs(mesh.points.max(axis=0) - bounds[1]).max())
        what = ""
        if abs(volume / solid - 1.0) > VOLUME_TOLERANCE:
            what = f"holds {volume:.4g} m^3 of tetrahedra but the CAD encloses {solid:.4g} m^3"
        elif off > BOX_TOLERANCE * float(np.linalg.norm(bounds[1] - bounds[0])):
            what = f"reaches {1e3 * off:.1f} mm past or short of the CAD's bounding box"
        if what:
            raise ValueError(f"links.{name}.volume_meshes.'{key}': {Path(path).name} {what}: "
                             f"not a mesh of this link in metres and the link frame")
    return mesh


def _cad_volume_and_bounds(cad: str, units: str) -> tuple[float, np.ndarray]:
    """Volume [m^3] the CAD file encloses and its (2, 3) bounding box [m], cached by the
    file's bytes: a command on a robot with pinned meshes need not read its CAD again."""
    from ..fe.cache import cache_key, cached
    from ..fe.files import file_digest

    def measure() -> dict:
        from ..meshes import load_surface

        surface = load_surface(cad, units=units)
        return {"volume": float(surface.volume),
                "bounds": np.asarray(surface.bounds, dtype=np.float64).tolist()}

    d = cached("cad-extent", cache_key("cad-extent", file_digest(cad), units), measure).value
    return float(d["volume"]), np.asarray(d["bounds"], dtype=np.float64)
