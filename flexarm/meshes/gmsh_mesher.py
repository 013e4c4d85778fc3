"""Closed surface -> tetrahedral mesh with Gmsh: the same input gives the same bytes.

fTetWild (:mod:`.tetwild`) differs between identical calls, so two fresh builds of
the same robot differ by a few per cent in compliance.  This mesher runs Gmsh's
Python API single-threaded with every option fixed, so a surface, an edge length
and a Gmsh version give a bit-identical mesh on every run.

CAD triangulations (long needles, fans) are too poor for Gmsh's reparametrisation
of discrete surfaces, so the surface is meshed twice:

1. *pre-mesh*: each planar facet (coplanar adjacent triangles) becomes an exact
   plane surface bounded by its outline, meshed with well-shaped triangles at a
   fraction of the target edge length;
2. *remesh*: Gmsh classifies that triangulation into smooth patches (sharp edges
   above ``FEATURE_ANGLE_DEG``), reparametrises them and remeshes them at the
   target edge length; the volume inside is meshed with Delaunay and optimised
   (Gmsh's optimiser, then Netgen's).

Gmsh's reparametrisation fails on some triangulations and not on close ones, so
the pre-mesh fractions in ``PREMESH_FRACTIONS`` are tried in turn (a fixed ladder:
still deterministic).  If all fail, the volume is meshed on the first pre-mesh
surface itself: exact planar facets, but finer near curved faces.

Limits (measured on the demo arm at 20-30 mm edges): the mesh conforms to the
CAD, so knife edges and CAD features smaller than the edge length leave a few flat
elements (logged, not refused: a rerun gives the same mesh); curved faces are
remeshed with chords of the target length, so a cylinder loses about
``h**2 / (6 r**2)`` of its volume (-1.3 % at h = 0.4 r).  pytetwild stays the
robust path for dirty CAD.

Gmsh is GPL-2.0-or-later (its exception only covers combining it with Netgen,
METIS, OpenCASCADE and ParaView): it is an optional dependency, imported here
only when used.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..fe.errors import MeshError, MissingDependencyError
from ..fe.mesh import TetMesh
from ..fe.tolerances import tol
from .quality import dihedral_angles
from .tet_cache import cached_tetrahedralization
from .tetwild import _compact

__all__ = [
    "tetrahedralize_gmsh",
    "gmsh_settings",
    "FEATURE_ANGLE_DEG",
    "PREMESH_FRACTIONS",
    "COPLANAR_ANGLE",
    "FLATNESS",
]

logger = logging.getLogger(__name__)

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

Progress = Callable[[str], None]


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


# ----------------------------------------------------------------------- meshing
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


def _premesh(gmsh, vertices, faces, labels, size: float) -> int:
    """Pass 1: well-shaped triangles on the exact planar facets (a volume is defined too)."""
    gmsh.model.add("flexarm-premesh")
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


def _remeshed(gmsh, vertices, faces, labels, size, fraction, optimize):
    """Pass 1, then pass 2: classify the pre-mesh, remesh the patches, mesh the volume."""
    with _session(gmsh):
        _premesh(gmsh, vertices, faces, labels, fraction * size)
        points, triangles = _mesh_arrays(gmsh, 2)
        gmsh.model.add("flexarm-remesh")
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


def _on_premesh(gmsh, vertices, faces, labels, size, fraction, optimize):
    """The volume meshed on the pre-mesh surface itself (no reparametrisation)."""
    with _session(gmsh):
        _premesh(gmsh, vertices, faces, labels, fraction * size)
        return _volume(gmsh, size, optimize)


def _oriented(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unused nodes dropped, negative elements turned (VTK order, positive volumes)."""
    points, tets = _compact(points, tets)
    p = points[tets]
    d = p[:, 1:] - p[:, :1]
    negative = np.einsum("ij,ij->i", d[:, 0], np.cross(d[:, 1], d[:, 2])) < 0
    tets = tets.copy()
    tets[negative] = tets[negative][:, [0, 2, 1, 3]]
    return points, tets


def _run(gmsh, surface, size: float, optimize: bool, name: str, report: Progress) -> TetMesh:
    """The first pre-mesh fraction whose remesh works, else the volume on the pre-mesh."""
    vertices = np.asarray(surface.vertices, dtype=np.float64)
    faces = np.asarray(surface.faces, dtype=np.int64)
    labels = _facet_labels(surface)
    tries = [(_remeshed, f) for f in PREMESH_FRACTIONS] + [(_on_premesh, PREMESH_FRACTIONS[0])]
    failures = []
    for i, (attempt, fraction) in enumerate(tries, start=1):
        how = "remesh" if attempt is _remeshed else "volume on the pre-mesh"
        report(f"{name}: gmsh try {i}/{len(tries)}: {how} (pre-mesh edge {fraction * size:.3g} m)")
        try:
            points, tets = attempt(gmsh, vertices, faces, labels, size, fraction, optimize)
        except _GmshFailed as exc:
            logger.info("%s: gmsh try %d (%s) failed: %s", name, i, how, exc)
            failures.append(f"try {i}: {exc}")
            continue
        if attempt is _on_premesh:
            logger.warning("%s: gmsh meshed the volume on the pre-mesh surface (%s)", name,
                           "; ".join(failures))
        elif i > 1:
            logger.info("%s: gmsh needed try %d", name, i)
        return TetMesh(*_oriented(points, tets))
    raise MeshError(f"{name}: gmsh failed ({'; '.join(failures)}); try mesher='tetwild'")


def _defects(mesh: TetMesh) -> tuple[str | None, int, float]:
    """(why the mesh is unusable or None, number of slivers, smallest dihedral [deg])."""
    vol = mesh.volumes()
    scale = np.abs(vol).mean()
    n_flat = int((np.abs(vol) <= tol.degenerate_volume * scale).sum())
    angles = dihedral_angles(mesh.points, mesh.tets).min(axis=1)
    n_slivers = int((angles < tol.sliver_dihedral_deg).sum())
    problem = f"{n_flat} zero-volume tetrahedra" if n_flat else None
    return problem, n_slivers, float(angles.min())


def tetrahedralize_gmsh(
    surface,
    size: float,
    optimize: bool = True,
    order: int = 1,
    cache: bool = True,
    name: str = "surface",
    progress: Progress | None = None,
) -> TetMesh:
    """Tetrahedral mesh of the solid inside a closed surface, made by Gmsh (deterministic).

    Same call shape as :func:`~flexarm.meshes.tetwild.tetrahedralize`.  Gmsh conforms
    to the surface, so a knife edge of the CAD (two faces meeting at a few degrees)
    or a CAD feature much smaller than ``size`` forces a few flat elements: they are
    logged, not refused (a rerun would give the same mesh).  Zero-volume elements
    are refused.

    Parameters
    ----------
    surface : trimesh.Trimesh
        Closed, outward-wound surface [m] (e.g. from :func:`load_surface`).
    size : float
        Target edge length [m].
    optimize : bool
        Optimise element quality (Gmsh's optimiser, then Netgen's).
    order : {1, 2}
        Tet4, or Tet10 with straight mid-edge nodes.
    cache : bool
        Reuse / store the result in ``cache_dir()/tets``; the key holds the Gmsh
        version and :func:`gmsh_settings`, never shared with pytetwild's entries.
    name : str
        What to call the part in messages (e.g. the file name).
    progress : callable (str) -> None, optional
        Receives a few coarse progress messages.

    Returns
    -------
    TetMesh
        Positively oriented elements (VTK order), no unused nodes.

    Raises
    ------
    MissingDependencyError
        gmsh is not installed.
    MeshError
        The surface is open, or Gmsh failed (the message names ``name``).

    Examples
    --------
    >>> from flexarm.meshes.primitives import bar_surface
    >>> mesh = tetrahedralize_gmsh(bar_surface(0.2, 0.1, 0.05), 0.05, cache=False)
    >>> round(float(mesh.volumes().sum()), 12), bool((mesh.volumes() > 0).all())
    (0.001, True)
    """
    if len(surface.faces) == 0 or not surface.is_watertight:
        raise MeshError(f"{name}: the surface is not closed (gmsh needs a watertight surface)")
    gmsh = _import_gmsh()

    def make(vertices, faces, report):
        logger.info("gmsh tetrahedralizing %s: %d faces, edge %.4g m", name, len(faces), size)
        report(f"{name}: gmsh tetrahedralizing (edge {size:.4g} m, optimize={bool(optimize)})")
        start = time.perf_counter()
        mesh = _run(gmsh, surface, float(size), optimize, name, report)
        problem, n_slivers, min_angle = _defects(mesh)
        if problem is not None:
            raise MeshError(f"{name}: gmsh gave {problem} (try mesher='tetwild')")
        if n_slivers:
            logger.warning("%s: %d sliver tetrahedra (smallest dihedral %.2f deg < %g deg)",
                           name, n_slivers, min_angle, tol.sliver_dihedral_deg)
        logger.info("%s: gmsh took %.1f s", name, time.perf_counter() - start)
        return mesh

    return cached_tetrahedralization(surface, size, optimize, order, cache, name, progress, make,
                                     mesher="gmsh", settings=gmsh_settings())
