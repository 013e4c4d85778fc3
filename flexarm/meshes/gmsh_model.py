"""Gmsh's side of :mod:`.gmsh_mesher`: the fixed settings, a quiet session, the planar model.

Everything here decides *what* Gmsh is asked to mesh and *how Gmsh is set up*; the
meshing passes, the retry ladder and the checks of the result stay in
:mod:`.gmsh_mesher`.  Keeping every mesh-deciding setting in this one module keeps
:func:`gmsh_settings` (the cache key) next to the values it has to list.

Gmsh is GPL-2.0-or-later (its exception only covers combining it with Netgen,
METIS, OpenCASCADE and ParaView): it is an optional dependency, imported here
only when used.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
from collections.abc import Iterator

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..fe.errors import MissingDependencyError

__all__ = [
    "gmsh_settings",
    "FEATURE_ANGLE_DEG",
    "PREMESH_FRACTIONS",
    "COPLANAR_ANGLE",
    "FLATNESS",
]

#: Adjacent triangles meeting at more than this angle [deg] keep a sharp edge between them.
FEATURE_ANGLE_DEG = 40.0
#: Pre-mesh edge lengths tried in turn, as fractions of the target edge length.
PREMESH_FRACTIONS = (1.0 / 2.0, 1.0 / 3.0, 1.0 / 4.0)
#: Adjacent triangles whose normals differ by less than this [rad] may share a planar facet
#: (loose enough for float32 STL coordinates on needle triangles, far below any CAD chord) ...
COPLANAR_ANGLE = 1e-3
#: ... if the facet's vertices lie within this times the part's diagonal of one plane.
FLATNESS = 1e-6

#: Options fixed for every run (General.Terminal first: nothing reaches the terminal).
_FIXED_OPTIONS = {
    "General.Terminal": 0,
    "General.NumThreads": 1,
    "Mesh.MaxNumThreads1D": 1,
    "Mesh.MaxNumThreads2D": 1,
    "Mesh.MaxNumThreads3D": 1,
    "Mesh.RandomSeed": 1,
    "Mesh.RandomFactor": 1e-9,
    "Mesh.RandomFactor3D": 1e-12,
    "Mesh.Algorithm": 6,  # Frontal-Delaunay surfaces
    "Mesh.Algorithm3D": 1,  # Delaunay (sequential; HXT is the parallel one)
    "Mesh.MeshSizeMin": 0.0,
    "Mesh.MeshSizeFactor": 1.0,
    "Mesh.MeshSizeFromPoints": 0,
    "Mesh.MeshSizeFromCurvature": 0,
    "Mesh.MeshSizeExtendFromBoundary": 1,
    "Mesh.ElementOrder": 1,
    "Mesh.OptimizeThreshold": 0.3,
    "Mesh.Smoothing": 1,
}
_OPTIMIZE_OPTIONS = ("Mesh.Optimize", "Mesh.OptimizeNetgen")
_SIZE_OPTION = "Mesh.MeshSizeMax"

# Gmsh is one global state per process: one mesher at a time.
_LOCK = threading.Lock()

_MISSING = "gmsh is not installed: pip install gmsh (or use mesher='tetwild')"


class _GmshFailed(Exception):
    """A Gmsh call failed; the message is Gmsh's last error."""


# ----------------------------------------------------------------------- gmsh session
def _import_gmsh():
    try:
        import gmsh
    except (ImportError, OSError) as exc:  # OSError: the wheel's libgmsh cannot load
        error = MissingDependencyError("gmsh", "tetrahedralisation")
        error.args = (_MISSING if isinstance(exc, ImportError) else f"{_MISSING} ({exc})",)
        raise error from exc
    return gmsh


def gmsh_settings() -> tuple:
    """Everything besides the surface, size and order that decides the mesh (cache key).

    Raises :class:`MissingDependencyError` if gmsh is not installed.

    Examples
    --------
    >>> gmsh_settings()[0].startswith("gmsh ")
    True
    """
    gmsh = _import_gmsh()
    return (
        f"gmsh {gmsh.__version__}",
        tuple(sorted(_FIXED_OPTIONS.items())),
        FEATURE_ANGLE_DEG,
        PREMESH_FRACTIONS,
        COPLANAR_ANGLE,
        FLATNESS,
    )


@contextlib.contextmanager
def _quiet_fds() -> Iterator[None]:
    """Point file descriptors 1 and 2 at /dev/null (Netgen's optimiser prints there)."""
    for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
        with contextlib.suppress(AttributeError, OSError, ValueError):
            stream.flush()
    saved = []
    try:
        with open(os.devnull, "wb") as null:
            for fd in (1, 2):
                with contextlib.suppress(OSError):
                    saved.append((fd, os.dup(fd)))
                    os.dup2(null.fileno(), fd)
        yield
    finally:
        for fd, copy in saved:
            os.dup2(copy, fd)
            os.close(copy)


@contextlib.contextmanager
def _session(gmsh) -> Iterator[None]:
    """Gmsh initialised with the fixed options; afterwards as it was before.

    If the caller already runs Gmsh, the options changed here are restored and the
    models made here removed; otherwise Gmsh is finalised again.
    """
    with _LOCK:
        owned = not gmsh.isInitialized()
        saved, models, current = {}, [], None
        if owned:
            gmsh.initialize([], readConfigFiles=False, run=False, interruptible=False)
        else:
            names = [*_FIXED_OPTIONS, *_OPTIMIZE_OPTIONS, _SIZE_OPTION]
            saved = {name: gmsh.option.getNumber(name) for name in names}
            models = gmsh.model.list()
            current = gmsh.model.getCurrent() if models else None
        try:
            for name, value in _FIXED_OPTIONS.items():
                gmsh.option.setNumber(name, value)
            gmsh.logger.start()
            yield
        finally:
            with contextlib.suppress(Exception):
                gmsh.logger.stop()
            if owned:
                gmsh.finalize()
            else:
                for model in gmsh.model.list():
                    if model not in models:
                        gmsh.model.setCurrent(model)
                        gmsh.model.remove()
                if current is not None:
                    gmsh.model.setCurrent(current)
                for name, value in saved.items():
                    gmsh.option.setNumber(name, value)


def _call(gmsh, function, *args, quiet: bool = False):
    """Run one Gmsh API call; failures become :class:`_GmshFailed` with Gmsh's last error."""
    try:
        if quiet:
            with _quiet_fds():
                return function(*args)
        return function(*args)
    except Exception as exc:  # the API raises a bare Exception
        errors = [m for m in gmsh.logger.get() if m.startswith("Error")]
        text = errors[-1].partition(":")[2].strip() if errors else str(exc)
        raise _GmshFailed(" ".join((text or type(exc).__name__).split())) from exc


# ------------------------------------------------------------------- planar facets
def _facet_labels(surface) -> np.ndarray:
    """(k,) int: the planar facet of each triangle.

    Coplanar neighbours are joined at a loose angle first (float32 STL coordinates
    tilt needle triangles by up to ~1e-4 rad); a group whose vertices stray more than
    ``FLATNESS`` times the part's diagonal from its mean plane is split again at ten
    times tighter angles, and what is never flat stays one triangle per facet.
    """
    vertices = np.asarray(surface.vertices, dtype=np.float64)
    faces = np.asarray(surface.faces, dtype=np.int64)
    pairs = np.asarray(surface.face_adjacency, dtype=np.int64).reshape(-1, 2)
    angles = np.asarray(surface.face_adjacency_angles, dtype=np.float64)
    n = len(faces)
    limit = FLATNESS * float(np.linalg.norm(np.ptp(vertices, axis=0)))
    labels = np.full(n, -1, dtype=np.int64)
    n_labels = 0
    angle = COPLANAR_ANGLE
    while angle >= COPLANAR_ANGLE * 1e-6 and (labels < 0).any():
        free = labels < 0
        joined = pairs[(angles < angle) & free[pairs[:, 0]] & free[pairs[:, 1]]]
        graph = coo_matrix((np.ones(len(joined)), (joined[:, 0], joined[:, 1])), shape=(n, n))
        groups = connected_components(graph, directed=False)[1]
        candidates = np.flatnonzero(free)
        candidates = candidates[np.argsort(groups[candidates], kind="stable")]
        bounds = np.flatnonzero(np.diff(groups[candidates])) + 1
        for members in np.split(candidates, bounds):
            points = vertices[np.unique(faces[members])]
            centred = points - points.mean(axis=0)
            if len(members) == 1 or np.linalg.svd(centred, compute_uv=False)[-1] <= limit:
                labels[members] = n_labels
                n_labels += 1
        angle /= 10.0
    lonely = np.flatnonzero(labels < 0)
    labels[lonely] = n_labels + np.arange(len(lonely))
    return labels


def _outlines(faces: np.ndarray) -> list[list[int]] | None:
    """Closed vertex cycles bounding a group of consistently wound triangles.

    None when the outline touches itself at a vertex (Gmsh loops cannot).
    """
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    inner = {(int(a), int(b)) for a, b in directed}
    following: dict[int, int] = {}
    for a, b in sorted(inner):
        if (b, a) in inner:
            continue
        if a in following:
            return None
        following[a] = b
    cycles, seen = [], set()
    for start in sorted(following):
        if start in seen:
            continue
        cycle, v = [], start
        while v not in seen:
            seen.add(v)
            cycle.append(v)
            v = following[v]
        if v != start:
            return None
        cycles.append(cycle)
    return cycles


def _planar_brep(gmsh, vertices: np.ndarray, faces: np.ndarray, labels: np.ndarray) -> int:
    """Build the facets as plane surfaces of one volume in Gmsh's built-in kernel.

    Returns the number of facets split into single triangles (pinched outlines).
    """
    geo = gmsh.model.geo
    points: dict[int, int] = {}
    lines: dict[tuple[int, int], int] = {}

    def point(i: int) -> int:
        if i not in points:
            points[i] = geo.addPoint(*vertices[i])
        return points[i]

    def line(a: int, b: int) -> int:
        if (b, a) in lines:
            return -lines[(b, a)]
        if (a, b) not in lines:
            lines[(a, b)] = geo.addLine(point(a), point(b))
        return lines[(a, b)]

    def plane_surface(group: np.ndarray, cycles: list[list[int]]) -> int:
        p = vertices[group]
        normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]).sum(axis=0)

        def area(cycle):  # projected on the facet normal: the outer cycle is the largest
            q = vertices[cycle]
            return abs(np.cross(q, np.roll(q, -1, axis=0)).sum(axis=0) @ normal)

        loops = [geo.addCurveLoop([line(c[k], c[(k + 1) % len(c)]) for k in range(len(c))])
                 for c in sorted(cycles, key=area, reverse=True)]
        return geo.addPlaneSurface(loops)

    order = np.argsort(labels, kind="stable")
    groups = np.split(faces[order], np.flatnonzero(np.diff(labels[order])) + 1)
    surfaces, n_split = [], 0
    for group in groups:
        cycles = _outlines(group)
        if cycles is None:
            n_split += 1
            surfaces += [plane_surface(tri[None], _outlines(tri[None])) for tri in group]
        else:
            surfaces.append(plane_surface(group, cycles))
    geo.addVolume([geo.addSurfaceLoop(surfaces)])
    geo.synchronize()
    return n_split
