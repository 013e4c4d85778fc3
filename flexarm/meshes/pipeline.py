"""CAD file -> checked surface -> tetrahedra -> quality report, in one call."""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np

from ..fe.mesh import TetMesh
from ..fe.typing import PathType
from ..fe.units import length_factor
from .auto_mesher import MESHER_SETTINGS, mesh_surface
from .gmsh_mesher import tetrahedralize_gmsh
from .quality import QualityReport, mesh_quality
from .surface import load_surface
from .tet_cache import MESHERS
from .tetwild import tetrahedralize

__all__ = ["mesh_part", "tetrahedralizer", "DEFAULT_SIZE_FRACTION", "MESHERS", "MESHER_SETTINGS"]

logger = logging.getLogger(__name__)

#: Default edge length as a fraction of the bounding-box diagonal (pytetwild's default).
DEFAULT_SIZE_FRACTION = 0.05


def tetrahedralizer(mesher: str = "tetwild") -> Callable[..., TetMesh]:
    """The tetrahedralisation function of a ``mesher`` setting.

    All take ``(surface, size, optimize=, order=, cache=, name=, progress=)`` and
    return a Tet4/Tet10 :class:`TetMesh`; their cache entries are never shared.

    Parameters
    ----------
    mesher : {"tetwild", "gmsh", "auto"}
        ``"tetwild"`` (pytetwild/fTetWild: robust on dirty CAD, not reproducible
        between runs), ``"gmsh"`` (deterministic: same input, same mesh; needs
        a closed, clean surface and the optional ``gmsh`` package) or ``"auto"``
        (Gmsh where the CAD allows, else fTetWild: :mod:`.auto_mesher`).

    Examples
    --------
    >>> tetrahedralizer("tetwild").__name__, tetrahedralizer("gmsh").__name__
    ('tetrahedralize', 'tetrahedralize_gmsh')
    """
    if mesher == "tetwild":
        return tetrahedralize
    if mesher == "gmsh":
        return tetrahedralize_gmsh
    if mesher == "auto":
        return _auto_mesh
    raise ValueError(f"mesher must be one of {', '.join(map(repr, MESHER_SETTINGS))}, "
                     f"got {mesher!r}")


def _auto_mesh(surface, size: float, **options) -> TetMesh:
    """The mesh of :func:`~flexarm.meshes.auto_mesher.mesh_surface` under ``"auto"``."""
    return mesh_surface(surface, size, "auto", **options).mesh


def mesh_part(
    path: PathType,
    units: str = "m",
    size: float | None = None,
    order: int = 1,
    optimize: bool = True,
    cache: bool = True,
    progress: Callable[[str], None] | None = None,
    mesher: str = "tetwild",
) -> tuple[TetMesh, QualityReport]:
    """Tetrahedral mesh of a CAD part file and its quality against the surface.

    Parameters
    ----------
    path : path-like
        ``.stl``, ``.obj`` or ``.ply`` closed surface.
    units : {"m", "mm", "cm", "in"}
        Length unit of the file.
    size : float, optional
        Target edge length [m]; default ``DEFAULT_SIZE_FRACTION`` times the
        bounding-box diagonal.
    order : {1, 2}
        Tet4 or Tet10.
    optimize, cache, progress
        As for :func:`~flexarm.meshes.tetwild.tetrahedralize`.
    mesher : {"tetwild", "gmsh", "auto"}
        Which tetrahedraliser (see :func:`tetrahedralizer`).

    Returns
    -------
    mesh : TetMesh
        [m]
    report : QualityReport
        Including the volume error against the surface.
    """
    meshing = tetrahedralizer(mesher)
    try:
        length_factor(units)
    except ValueError as exc:  # the file the unit belongs to, in the message
        raise ValueError(f"{path}: {exc}") from None
    if progress is not None:
        progress(f"{path}: reading the surface (units={units})")
    surface = load_surface(path, units=units)
    if size is None:
        size = DEFAULT_SIZE_FRACTION * float(np.linalg.norm(surface.extents))
        logger.info("%s: default edge length %.4g m", path, size)
    mesh = meshing(
        surface,
        size,
        optimize=optimize,
        order=order,
        cache=cache,
        name=str(path),
        progress=progress,
    )
    report = mesh_quality(mesh, surface)
    logger.info("%s quality:\n%s", path, report.table())
    return mesh, report
