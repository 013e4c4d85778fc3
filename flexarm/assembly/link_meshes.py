"""A link's tetrahedra: read from the volume-mesh file it names, or meshed from its CAD by
the robot's ``model.mesher`` (cached on disk), and which mesher made them.

Every analysis (builds, full-FE references, mass properties, studies) takes a link's
elements from here, so all of them see the same solid.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from ..fe.files import digest
from ..fe.mesh import TetMesh
from ..robot.description import Link

__all__ = ["LinkMesh", "Mesher", "meshed_link", "cached_link_mesh", "meshing_work",
           "link_mesh", "link_mesh_id", "FILE_MESHER"]

#: ``mesher(link, mesh_size [m], order) -> TetMesh`` in the link frame [m].
Mesher = Callable[[Link, float, int], TetMesh]

#: The mesher name of tetrahedra read from the link's ``volume_meshes`` file.
FILE_MESHER = "file"


@dataclass(frozen=True, eq=False)
class LinkMesh:
    """A link's tetrahedra and where they came from.

    Attributes
    ----------
    mesh : TetMesh
        Link frame [m].
    mesher : str
        ``"gmsh"``, ``"tetwild"``, ``"file"`` (the link's ``volume_meshes``) or the name of
        a given :data:`Mesher` callable.
    note : str
        Why ``model.mesher = "auto"`` fell back: to fTetWild, or to Gmsh's volume on its
        pre-mesh (else empty).
    seconds : float
        Wall time [s] of this call (reading included).
    is_cached : bool
        Read from the package cache or a file rather than meshed.
    """

    mesh: TetMesh
    mesher: str
    note: str = ""
    seconds: float = 0.0
    is_cached: bool = False


def _surface(link: Link):
    from ..meshes import load_surface

    if link.mesh is None:
        raise ValueError(f"links.{link.name}: no mesh to build a flexible link from")
    return load_surface(link.mesh, units=link.units)


def _local_sizes(link: Link, mesh_size: float) -> tuple:
    """Where the link's seats need a finer edge than ``mesh_size`` [m] (Gmsh takes them)."""
    from ..robot.seat_mesh import seat_local_sizes

    return seat_local_sizes(link, mesh_size)


def _pinned(link: Link, mesh_size: float, order: int) -> LinkMesh | None:
    from ..robot.volume_meshes import pinned_mesh

    start = time.perf_counter()
    mesh = pinned_mesh(link, mesh_size, order)
    return None if mesh is None else LinkMesh(mesh, FILE_MESHER, "", time.perf_counter() - start,
                                              True)


def meshed_link(link: Link, mesh_size: float, order: int = 1, progress=None,
                mesher: str | Mesher = "tetwild") -> LinkMesh:
    """The link's tetrahedra at ``mesh_size`` [m] and ``order`` and how they were made.

    Parameters
    ----------
    link : Link
    mesh_size : float
        Tet edge length [m].
    order : {1, 2}
    progress : callable (str) -> None, optional
    mesher : {"tetwild", "gmsh", "auto"} or Mesher
        The robot's ``model.mesher``, or a :data:`Mesher` callable (tests use structured
        box meshes).  A volume mesh the link names for ``mesh_size`` is read instead
        (:func:`~flexarm.robot.volume_meshes.pinned_mesh`).  Gmsh refines the edge over
        the seats that would hold too few nodes at ``mesh_size``
        (:func:`~flexarm.robot.seat_mesh.seat_local_sizes`).

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> made = meshed_link(load_robot().links[2], 0.03)  # the demo arm pins its meshes
    >>> made.mesher, made.mesh.n_tets > 1000
    ('file', True)
    """
    if callable(mesher):
        start = time.perf_counter()
        mesh = mesher(link, mesh_size, order)
        return LinkMesh(mesh, getattr(mesher, "__name__", "given"), "",
                        time.perf_counter() - start)
    pinned = _pinned(link, mesh_size, order)
    if pinned is not None:
        return pinned
    from ..meshes import mesh_surface

    made = mesh_surface(_surface(link), mesh_size, mesher, order=order, name=link.name,
                        progress=progress, local_sizes=_local_sizes(link, mesh_size))
    return LinkMesh(made.mesh, made.mesher, made.note, made.seconds, made.is_cached)


def cached_link_mesh(link: Link, mesh_size: float, order: int = 1,
                     mesher: str = "tetwild") -> LinkMesh | None:
    """:func:`meshed_link` if nothing has to be meshed (a volume-mesh file, or the package
    cache holds the mesh), else None."""
    pinned = _pinned(link, mesh_size, order)
    if pinned is not None or link.mesh is None:
        return pinned
    from ..meshes import cached_surface_mesh

    made = cached_surface_mesh(_surface(link), mesh_size, mesher, order=order,
                               local_sizes=_local_sizes(link, mesh_size))
    return None if made is None else LinkMesh(made.mesh, made.mesher, made.note, made.seconds,
                                              True)


def meshing_work(link: Link, mesh_size: float, order: int = 1,
                 mesher: str = "tetwild") -> float | None:
    """None when :func:`meshed_link` has nothing to mesh (:func:`cached_link_mesh`), else
    a relative cost of meshing the link [-]: the elements expected plus the CAD triangles
    (the surface passes of Gmsh scale with the one, the volume pass with the other)."""
    from ..meshes.tet_cache import estimated_tets

    if cached_link_mesh(link, mesh_size, order, mesher) is not None or link.mesh is None:
        return None
    surface = _surface(link)
    return estimated_tets(abs(float(surface.volume)), mesh_size) + len(surface.faces)


def link_mesh(link: Link, mesh_size: float, order: int = 1, progress=None,
              mesher: str = "tetwild") -> TetMesh:
    """Tetrahedral mesh of the link's CAD [m], link frame (cached on disk): the mesh of
    :func:`meshed_link`.

    ``mesher`` is the robot's ``model.mesher`` (``"tetwild"``, ``"gmsh"`` or ``"auto"``).
    """
    return meshed_link(link, mesh_size, order, progress, mesher).mesh


def link_mesh_id(link: Link, mesher: str | Mesher = "tetwild", mesh_size: float = 0.0,
                 order: int = 1) -> str:
    """Digest of the link's tetrahedra at ``mesh_size`` [m] and ``order``: the key of every
    cache entry computed from them.

    ``mesher`` is the robot's ``model.mesher`` (the mesh comes from the tet cache, so a
    mesh made again, which pytetwild makes differently, gets new keys downstream) or a
    :data:`Mesher` callable.
    """
    mesh = meshed_link(link, mesh_size, order, mesher=mesher).mesh
    return digest(mesh.points, mesh.tets)
