"""The passes Gmsh runs for :mod:`.gmsh_mesher`, each in one child process.

A *try* is one of :data:`ATTEMPTS`: the remesh of the planar pre-mesh (classify it
into smooth patches, reparametrise, remesh, mesh the volume), or the volume meshed on
the pre-mesh itself.  Each opens its own Gmsh session and returns plain arrays, so
that :func:`gmsh_try` can run in a child (:func:`~flexarm.fe.processes.run_child`)
and its result be pickled back; the ladder of tries, their budgets and the checks of
the result stay in :mod:`.gmsh_mesher`.
"""

from __future__ import annotations

import logging

import numpy as np

from .gmsh_model import (
    _OPTIMIZE_OPTIONS,
    _SIZE_OPTION,
    FEATURE_ANGLE_DEG,
    _call,
    _GmshFailed,
    _import_gmsh,
    _planar_brep,
    _session,
)
from .local_size import size_callback
from .quality import triangle_min_angles
from .tolerances import tol

__all__ = ["ATTEMPTS", "PREMESH", "gmsh_try"]

logger = logging.getLogger(__name__)


def _mesh_arrays(gmsh, element_type: int) -> tuple[np.ndarray, np.ndarray]:
    """All nodes (in tag order) and the elements of one type as 0-based node indices."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    _, connectivity = gmsh.model.mesh.getElementsByType(element_type)
    tags = np.asarray(tags, dtype=np.int64)
    order = np.argsort(tags, kind="stable")
    index = np.full(int(tags.max()) + 1 if len(tags) else 1, -1, dtype=np.int64)
    index[tags[order]] = np.arange(len(tags))
    points = np.asarray(coords, dtype=np.float64).reshape(-1, 3)[order]
    n_corners = {2: 3, 4: 4}[element_type]
    return points, index[np.asarray(connectivity, dtype=np.int64).reshape(-1, n_corners)]


def _premesh(gmsh, vertices, faces, labels, size: float, fraction: float = 1.0,
             local=()) -> int:
    """Pass 1: well-shaped triangles on the exact planar facets (a volume is defined too),
    with ``local`` sizes (:class:`~.local_size.LocalSize`) scaled by the pre-mesh
    ``fraction`` where this surface is the final one."""
    gmsh.model.add("flexarm-premesh")
    if local:
        gmsh.model.mesh.setSizeCallback(size_callback(local, fraction))
    n_split = _planar_brep(gmsh, vertices, faces, labels)
    if n_split:
        logger.info("%d facets with a pinched outline pre-meshed triangle by triangle", n_split)
    gmsh.option.setNumber(_SIZE_OPTION, size)
    _call(gmsh, gmsh.model.mesh.generate, 2)
    return n_split


def _volume(gmsh, size: float, optimize: bool) -> tuple[np.ndarray, np.ndarray]:
    """Mesh the current model's volume; its nodes and tetrahedra."""
    gmsh.option.setNumber(_SIZE_OPTION, size)
    for option in _OPTIMIZE_OPTIONS:
        gmsh.option.setNumber(option, int(bool(optimize)))
    _call(gmsh, gmsh.model.mesh.generate, 3, quiet=True)
    points, tets = _mesh_arrays(gmsh, 4)
    if len(tets) == 0:
        raise _GmshFailed("no tetrahedra")
    return points, tets


def _remeshed(gmsh, vertices, faces, labels, size, fraction, optimize, local=()):
    """Pass 1, then pass 2: classify the pre-mesh, remesh the patches, mesh the volume."""
    with _session(gmsh):
        # the pre-mesh only carries the geometry here: the same one with or without local
        # sizes, so that they refine the seats and change nothing else
        _premesh(gmsh, vertices, faces, labels, fraction * size)
        points, triangles = _mesh_arrays(gmsh, 2)
        gmsh.model.add("flexarm-remesh")
        if local:
            gmsh.model.mesh.setSizeCallback(size_callback(local))
        surface = gmsh.model.addDiscreteEntity(2)
        gmsh.model.mesh.addNodes(2, surface, np.arange(1, len(points) + 1), points.ravel())
        gmsh.model.mesh.addElementsByType(surface, 2, [], (triangles + 1).ravel())
        angle = np.radians(FEATURE_ANGLE_DEG)
        _call(gmsh, gmsh.model.mesh.classifySurfaces, angle, True, True, np.pi)
        _call(gmsh, gmsh.model.mesh.createGeometry)
        patches = [tag for _, tag in gmsh.model.getEntities(2)]
        gmsh.model.geo.addVolume([gmsh.model.geo.addSurfaceLoop(patches)])
        gmsh.model.geo.synchronize()
        return _volume(gmsh, size, optimize)


def _on_premesh(gmsh, vertices, faces, labels, size, fraction, optimize, local=()):
    """The volume meshed on the pre-mesh surface itself (no reparametrisation), unless a
    pre-mesh triangle is a needle (:func:`_refuse_needles`)."""
    with _session(gmsh):
        _premesh(gmsh, vertices, faces, labels, fraction * size, fraction, local)
        _refuse_needles(gmsh)
        return _volume(gmsh, size, optimize)


def _refuse_needles(gmsh) -> None:
    """Fail before the volume when a pre-mesh triangle has an angle below
    ``tol.premesh_needle_deg``: every tetrahedron on it would be a sliver, which the
    volume on the pre-mesh refuses anyway (the CAD's slivers of a union, where two bodies
    meet at a grazing angle, are kept as facets of their own)."""
    points, triangles = _mesh_arrays(gmsh, 2)
    angles = triangle_min_angles(points, triangles)
    n_needles = int((angles < tol.premesh_needle_deg).sum())
    if n_needles:
        raise _GmshFailed(f"{n_needles} needle triangles in the pre-mesh (smallest angle "
                          f"{angles.min():.2g} deg)")


#: The last try of :mod:`.gmsh_mesher`'s ladder: no remesh of the surface.
PREMESH = "volume on the pre-mesh"
#: The tries, by name (a child process calls them by name).
ATTEMPTS = {"remesh": _remeshed, PREMESH: _on_premesh}

def gmsh_try(how: str, vertices, faces, labels, size, fraction, optimize, local):
    """One try (``how``, a key of :data:`ATTEMPTS`), run in a child process: its nodes
    [m] and tetrahedra (0-based, unoriented)."""
    return ATTEMPTS[how](_import_gmsh(), vertices, faces, labels, size, fraction, optimize,
                          local)
