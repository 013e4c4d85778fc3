"""Which tetrahedraliser meshes a surface, and the mesh it made: the ``mesher`` settings.

``"gmsh"`` and ``"tetwild"`` name one mesher.  ``"auto"`` (the setting of imported
robots) takes the deterministic one wherever the CAD allows, so that the same robot
gives the same model: Gmsh on a closed, consistently wound surface (one whose sheets
touch or cross each other is replaced by the surface of its union:
:mod:`.self_intersections`); fTetWild only for dirty CAD (an open or inconsistently
wound surface, one whose union cannot be formed, or a surface Gmsh fails on: then the
union, where there is one), with the reason in :attr:`SurfaceMesh.note`, where Gmsh
meshing the volume on its pre-mesh (no remesh of the surface) is named too.

Under ``"auto"`` the choice is kept in the package cache (``mesher-choice``) with the key
of the mesh it gave, so a warm run neither checks the surface nor meshes again.
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..fe.cache import cache_key, cached
from ..fe.errors import MeshError, MissingDependencyError
from ..fe.mesh import TetMesh
from .gmsh_mesher import _gmsh_mesh, tetrahedralize_gmsh
from .local_size import LocalSize, local_sizes_key
from .self_intersections import united_surface
from .tet_cache import (
    MESHER_LIBRARY,
    MESHER_SETTINGS,
    MESHERS,
    cached_mesh,
    check_mesh_request,
    mesher_key_parts,
    tet_cache_key,
)
from .tetwild import tetrahedralize
from .tolerances import tol

__all__ = ["MESHER_SETTINGS", "SurfaceMesh", "mesh_surface", "cached_surface_mesh",
           "mesh_time_estimate", "TETS_PER_SECOND"]

logger = logging.getLogger(__name__)


#: Part of the choice entry's key: a new recipe never reuses an old choice.
_CHOICE_VERSION = 1
#: Tetrahedra a mesher makes per CPU second, surface passes included (IRB 4600 links at
#: 30 mm, 2026-11-27): the base of :func:`mesh_time_estimate`, good to a factor of two.
TETS_PER_SECOND = {"gmsh": 800.0, "tetwild": 150.0}
#: Elements per (area / edge^2) that a surface forces besides the volume's: a shell
#: thinner than the edge still gets a layer of elements (IRB 4600 shells: 3.3 to 4.1).
_SURFACE_LAYER = 4.0


@dataclass(frozen=True, eq=False)
class SurfaceMesh:
    """A tetrahedral mesh and how it was made.

    Attributes
    ----------
    mesh : TetMesh
        [m]
    mesher : {"gmsh", "tetwild"}
        The tetrahedraliser that made it.
    note : str
        The fallback ``"auto"`` took: why fTetWild meshed the surface, or how Gmsh did
        without remeshing it (empty otherwise).
    seconds : float
        Wall time of this call [s] (reading the cache included).
    is_cached : bool
        Read from the package cache.
    """

    mesh: TetMesh
    mesher: str
    note: str = ""
    seconds: float = 0.0
    is_cached: bool = False

    @property
    def is_reproducible(self) -> bool:
        """True when meshing the same surface again gives the same elements (Gmsh)."""
        return self.mesher == "gmsh"


def _check_setting(mesher: str) -> None:
    if mesher not in MESHER_SETTINGS:
        raise ValueError(f"mesher must be one of {', '.join(map(repr, MESHER_SETTINGS))}, "
                         f"got {mesher!r}")


def _choice_key(surface, size: float, optimize: bool, order: int, local=()) -> str:
    from .gmsh_model import gmsh_settings

    return cache_key("mesher-choice", _CHOICE_VERSION,
                     np.ascontiguousarray(surface.vertices, dtype=np.float64),
                     np.ascontiguousarray(surface.faces, dtype=np.int64), float(size),
                     bool(optimize), int(order), tol.self_intersection_gap,
                     tol.self_intersection_merge, tol.self_intersection_volume,
                     *mesher_key_parts("gmsh", gmsh_settings() + local_sizes_key(local)),
                     *mesher_key_parts("tetwild"),
                     libraries=(*MESHER_LIBRARY.values(), "manifold3d"))


def _gmsh_surface(surface, name: str) -> tuple[object | None, str]:
    """The surface Gmsh can mesh (a self-touching one united), or None and why not."""
    try:
        from .gmsh_model import _import_gmsh

        _import_gmsh()
    except MissingDependencyError:
        return None, "gmsh is not installed"
    if len(surface.faces) == 0 or not surface.is_watertight:
        return None, "the surface is not closed"
    if not surface.is_winding_consistent:
        return None, "the surface is not consistently wound"
    clean = united_surface(surface, name)
    if clean is None:
        return None, "the surface intersects itself and its union cannot be formed"
    return clean, ""


def _auto(surface, size, optimize, order, cache, name, progress,
          local=()) -> tuple[TetMesh, str, str, str]:
    """(mesh, mesher, note, tet-cache key) of the ``"auto"`` rule (``local`` sizes: Gmsh's
    only)."""
    clean, note = _gmsh_surface(surface, name)
    if clean is not None:
        from .gmsh_model import gmsh_settings

        try:
            mesh, fallback = _gmsh_mesh(clean, size, optimize, order, cache, name, progress,
                                        local)
        except MeshError as exc:  # "<name>: gmsh failed (...); try mesher='tetwild'"
            why = str(exc).removeprefix(f"{name}: ")
            for advice in ("; try mesher='tetwild'", " (try mesher='tetwild')"):
                why = why.replace(advice, "")
            note = why if why.startswith("gmsh") else f"gmsh failed: {why}"
        else:
            note = f"the {fallback}" if fallback else ""
            return mesh, "gmsh", note, tet_cache_key(clean.vertices, clean.faces, size, optimize,
                                                   order, mesher="gmsh",
                                                   settings=gmsh_settings()
                                                   + local_sizes_key(local))
    # one line on stderr: the user learns why this part will not mesh twice alike
    warnings.warn(f"{name}: meshed by fTetWild ({note}): not reproducible between fresh "
                  f"caches", stacklevel=4)
    # the union where there is one: the same solid without the faces of overlapping
    # bodies inside it, which fTetWild would refine along (the UR10's upper arm: 22 CPU-s
    # and 18,204 tetrahedra instead of 36 CPU-s and 26,560)
    solid = surface if clean is None else clean
    mesh = tetrahedralize(solid, size, optimize, order, cache, name, progress)
    return mesh, "tetwild", note, tet_cache_key(solid.vertices, solid.faces, size, optimize,
                                                order)


def mesh_surface(
    surface,
    size: float,
    mesher: str = "auto",
    optimize: bool = True,
    order: int = 1,
    cache: bool = True,
    name: str = "surface",
    progress: Callable[[str], None] | None = None,
    local_sizes: tuple[LocalSize, ...] = (),
) -> SurfaceMesh:
    """Tetrahedral mesh of the solid inside ``surface`` by the ``mesher`` setting.

    Parameters
    ----------
    surface : trimesh.Trimesh
        Closed surface [m] (e.g. from :func:`~flexarm.meshes.surface.load_surface`).
    size : float
        Target edge length [m].
    mesher : {"auto", "gmsh", "tetwild"}
        ``"auto"``: Gmsh where the CAD allows, fTetWild for dirty CAD (one warning naming
        the surface and the reason).
    optimize, order, cache, name, progress
        As for :func:`~flexarm.meshes.tetwild.tetrahedralize`.
    local_sizes : tuple of LocalSize
        Where the edge must be finer (:mod:`.local_size`): Gmsh takes them, fTetWild
        meshes at ``size``.

    Returns
    -------
    SurfaceMesh

    Examples
    --------
    >>> from flexarm.meshes.primitives import bar_surface
    >>> made = mesh_surface(bar_surface(0.2, 0.1, 0.05), 0.05, cache=False)
    >>> made.mesher, made.note, round(float(made.mesh.volumes().sum()), 12)
    ('gmsh', '', 0.001)
    """
    _check_setting(mesher)
    start = time.perf_counter()
    local = tuple(local_sizes)
    if mesher == "gmsh":
        mesh = tetrahedralize_gmsh(surface, size, optimize, order, cache, name, progress, local)
        return SurfaceMesh(mesh, mesher, "", time.perf_counter() - start)
    if mesher != "auto":
        mesh = tetrahedralize(surface, size, optimize, order, cache, name, progress)
        return SurfaceMesh(mesh, mesher, "", time.perf_counter() - start)
    check_mesh_request(surface, float(size), name)  # before the surface checks: wrong units
    if not cache:
        mesh, used, note, _ = _auto(surface, size, optimize, order, False, name, progress, local)
        return SurfaceMesh(mesh, used, note, time.perf_counter() - start)
    made = {}

    def choose() -> dict:
        made["mesh"], used, note, key = _auto(surface, size, optimize, order, True, name,
                                              progress, local)
        return {"mesher": used, "note": note, "tets": key}

    entry = cached("mesher-choice", _choice_key(surface, size, optimize, order, local), choose)
    choice = entry.value
    mesh = made["mesh"] if "mesh" in made else cached_mesh(choice["tets"])
    if mesh is None:  # the mesh entry was removed since: mesh again by the same rule
        mesh = made["mesh"] = _auto(surface, size, optimize, order, True, name, progress,
                                    local)[0]
    return SurfaceMesh(mesh, choice["mesher"], choice["note"], time.perf_counter() - start,
                       "mesh" not in made)


def cached_surface_mesh(surface, size: float, mesher: str = "auto", optimize: bool = True,
                        order: int = 1, local_sizes: tuple[LocalSize, ...] = ()
                        ) -> SurfaceMesh | None:
    """The :class:`SurfaceMesh` of :func:`mesh_surface` if the package cache holds it, else
    None (nothing is meshed; under ``"auto"`` a known choice is needed)."""
    from ..fe.cache import lookup

    _check_setting(mesher)
    start = time.perf_counter()
    local = tuple(local_sizes)
    if mesher == "auto":
        choice = lookup("mesher-choice", _choice_key(surface, size, optimize, order, local))
        if choice is None:
            return None
        mesh, used, note = cached_mesh(choice["tets"]), choice["mesher"], choice["note"]
    else:
        settings = ()
        if mesher == "gmsh":
            from .gmsh_model import gmsh_settings

            settings = gmsh_settings() + local_sizes_key(local)
        key = tet_cache_key(surface.vertices, surface.faces, size, optimize, order,
                            mesher=mesher, settings=settings)
        mesh, used, note = cached_mesh(key), mesher, ""
    if mesh is None:
        return None
    return SurfaceMesh(mesh, used, note, time.perf_counter() - start, True)


def mesh_time_estimate(surface, size: float, mesher: str = "auto") -> tuple[float, float]:
    """About how many tetrahedra of edge ``size`` [m] fill ``surface``, and how many CPU
    seconds ``mesher`` takes for them (``"auto"``: Gmsh's).

    The volume's elements (:func:`~flexarm.meshes.tet_cache.estimated_tets`) plus a layer
    along the surface; times from :data:`TETS_PER_SECOND`.

    Examples
    --------
    >>> import trimesh
    >>> n, seconds = mesh_time_estimate(trimesh.creation.box((0.4, 0.2, 0.1)), 0.02)
    >>> round(n), round(seconds, 1)
    (11285, 14.1)
    """
    from .tet_cache import estimated_tets

    _check_setting(mesher)
    size = float(size)
    n = (estimated_tets(abs(float(surface.volume)), size)
         + _SURFACE_LAYER * float(surface.area) / size**2)
    return n, n / TETS_PER_SECOND["gmsh" if mesher == "auto" else mesher]
