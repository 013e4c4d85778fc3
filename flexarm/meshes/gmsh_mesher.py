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

On some clean surfaces Gmsh's remesh never returns (the UR10's base_link at a 30 mm
edge; 1.3 s at 20 mm), so every try runs in a child process
(:func:`~flexarm.fe.processes.run_child`) with a CPU-time budget that grows with the
elements it makes (:func:`try_cpu_seconds`): a try that spends it is stopped and counts
as failed, and the next rung runs.  The budget is no part of the cache key: it is set
well above the time of any try that finishes, and a try either finishes within it, giving
the mesh it always gave, or never finishes.  Each try costs the child's start (about a
second of imports).

Limits (measured on the demo arm at 20-30 mm edges): the mesh conforms to the
CAD, so knife edges and CAD features smaller than the edge length leave a few flat
elements (logged, not refused: a rerun gives the same mesh); curved faces are
remeshed with chords of the target length, so a cylinder loses about
``h**2 / (6 r**2)`` of its volume (-1.3 % at h = 0.4 r).  pytetwild stays the
robust path for dirty CAD.

Gmsh is GPL-2.0-or-later (its exception only covers combining it with Netgen,
METIS, OpenCASCADE and ParaView): it is an optional dependency, imported here
only when used.

The settings, the Gmsh session and the planar pre-mesh model live in
:mod:`.gmsh_model`, the passes each try runs in :mod:`.gmsh_passes`; this module runs
the ladder of tries and checks the result.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable

import numpy as np

from ..fe.errors import FlexarmError, MeshError
from ..fe.mesh import TetMesh
from ..fe.processes import ChildTimeout, run_child
from ..fe.tolerances import tol as fe_tol
from .gmsh_model import (
    COPLANAR_ANGLE,
    FEATURE_ANGLE_DEG,
    FLATNESS,
    PREMESH_FRACTIONS,
    _facet_labels,
    _GmshFailed,
    _import_gmsh,
    gmsh_settings,
)
from .gmsh_passes import PREMESH, gmsh_try
from .local_size import LocalSize, local_sizes_key
from .quality import dihedral_angles
from .tet_cache import cached_tetrahedralization, estimated_tets
from .tetwild import _compact
from .tolerances import tol

__all__ = [
    "tetrahedralize_gmsh",
    "try_cpu_seconds",
    "gmsh_settings",
    "FEATURE_ANGLE_DEG",
    "PREMESH_FRACTIONS",
    "COPLANAR_ANGLE",
    "FLATNESS",
]

logger = logging.getLogger(__name__)

Progress = Callable[[str], None]


def _oriented(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unused nodes dropped, negative elements turned (VTK order, positive volumes)."""
    points, tets = _compact(points, tets)
    p = points[tets]
    d = p[:, 1:] - p[:, :1]
    negative = np.einsum("ij,ij->i", d[:, 0], np.cross(d[:, 1], d[:, 2])) < 0
    tets = tets.copy()
    tets[negative] = tets[negative][:, [0, 2, 1, 3]]
    return points, tets


#: Remesh failures that come from the patches Gmsh classifies the facets into, which are
#: the same at every pre-mesh edge (a pre-mesh splits planar facets into coplanar
#: triangles, so the sharp edges between them stay where they were): after one, the other
#: remesh tries are skipped (the published UR10's hulls: all three fail alike).
_FACET_FAILURES = ("Wrong topology",)
_SKIPPED = "skipped (the same patches at every pre-mesh edge)"


def try_cpu_seconds(surface, size: float, fraction: float) -> float:
    """CPU time [s] one Gmsh try on ``surface`` may take: ``tol.gmsh_try_cpu_floor`` plus
    ``tol.gmsh_try_cpu_per_element`` per element it makes (the CAD triangles, the pre-mesh
    triangles at ``fraction * size`` and the tetrahedra at ``size`` [m]).

    Examples
    --------
    >>> import trimesh
    >>> round(try_cpu_seconds(trimesh.creation.box((0.4, 0.2, 0.1)), 0.02, 0.5))
    207
    """
    premesh = 4.0 / np.sqrt(3.0) * float(surface.area) / (fraction * size) ** 2
    n = len(surface.faces) + premesh + estimated_tets(abs(float(surface.volume)), size)
    return tol.gmsh_try_cpu_floor + tol.gmsh_try_cpu_per_element * n


def _run(surface, size: float, optimize: bool, name: str, report: Progress,
         local: tuple = ()) -> tuple[TetMesh, str]:
    """The first pre-mesh fraction whose remesh works, else the volume on the pre-mesh;
    and ``""``, or the fallback taken and why.

    Each try runs in a child process with :func:`try_cpu_seconds`: one that spends them
    (or whose process dies) has failed like one Gmsh refuses.  With ``local`` sizes a try
    that gives zero-volume elements counts as failed too: the grading from a fine seat to
    the coarse edge can flatten one (the M-20iA's link_6 at 80 mm), and the next pre-mesh
    is as deterministic as the first.  A remesh that fails for its patches
    (``_FACET_FAILURES``) is not tried at another pre-mesh edge.  The volume on the
    pre-mesh fails with a single sliver, and before it is meshed with a needle triangle in
    the pre-mesh (:func:`_refuse_needles`): the pre-mesh keeps every CAD triangle of a
    curved face (a level-set cavity's thousands), and fTetWild meshes such a surface
    better (the UR10's upper arm: 8,695 slivers in 78,405 tetrahedra)."""
    vertices = np.asarray(surface.vertices, dtype=np.float64)
    faces = np.asarray(surface.faces, dtype=np.int64)
    labels = _facet_labels(surface)
    tries = [("remesh", f) for f in PREMESH_FRACTIONS] + [(PREMESH, PREMESH_FRACTIONS[0])]
    failures = []
    for i, (how, fraction) in enumerate(tries, start=1):
        if how == "remesh" and failures and failures[-1].startswith((*_FACET_FAILURES,
                                                                      _SKIPPED)):
            failures.append(_SKIPPED)
            report(f"{name}: gmsh try {i}/{len(tries)}: {_SKIPPED}")
            continue
        budget = try_cpu_seconds(surface, size, fraction)
        report(f"{name}: gmsh try {i}/{len(tries)}: {how} (pre-mesh edge {fraction * size:.3g} "
               f"m, at most {budget:.0f} CPU-s)")
        spent = _children_cpu()
        try:
            points, tets = run_child(gmsh_try, (how, vertices, faces, labels, size, fraction,
                                                 optimize, local),
                                     cpu_seconds=budget, name=f"{name}: gmsh try {i}")
            logger.info("%s: gmsh try %d took %.1f CPU-s of %.0f", name, i,
                        _children_cpu() - spent, budget)
            mesh = TetMesh(*_oriented(points, tets))
            if local or how == PREMESH:
                problem, n_slivers, _ = _defects(mesh)
                if problem is not None and local:
                    raise _GmshFailed(f"{problem} with local sizes")
                if how == PREMESH and (problem or n_slivers):
                    raise _GmshFailed(problem or f"{n_slivers} sliver tetrahedra")
        except (_GmshFailed, ChildTimeout, FlexarmError) as exc:
            why = str(exc).removeprefix(f"{name}: gmsh try {i}: ")
            if isinstance(exc, ChildTimeout):
                why = f"no answer in {budget:.0f} CPU-s"
            logger.info("%s: gmsh try %d (%s) failed: %s", name, i, how, why)
            failures.append(why)
            continue
        fallback = ""
        if how == PREMESH:
            fallback = f"{how} surface ({_tries_text(failures)})"
            logger.warning("%s: gmsh meshed the %s", name, fallback)
        elif i > 1:
            logger.info("%s: gmsh needed try %d", name, i)
        return mesh, fallback
    raise MeshError(f"{name}: gmsh failed ({_tries_text(failures)}); try mesher='tetwild'")


def _children_cpu() -> float:
    """CPU time [s] of this process's ended children (POSIX; elsewhere 0)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not POSIX
        return 0.0
    return sum(resource.getrusage(resource.RUSAGE_CHILDREN)[:2])


def _tries_text(failures: list[str]) -> str:
    """"tries 1-3: why; try 4: why": the failure of each try, the same ones once.

    Examples
    --------
    >>> _tries_text(["Wrong topology", "Wrong topology", "2 sliver tetrahedra"])
    'tries 1-2: Wrong topology; try 3: 2 sliver tetrahedra'
    """
    parts, first = [], 0
    for i in range(1, len(failures) + 1):
        if i == len(failures) or failures[i] != failures[first]:
            tries = f"try {i}" if i == first + 1 else f"tries {first + 1}-{i}"
            parts.append(f"{tries}: {failures[first]}")
            first = i
    return "; ".join(parts)


def _defects(mesh: TetMesh) -> tuple[str | None, int, float]:
    """(why the mesh is unusable or None, number of slivers, smallest dihedral [deg])."""
    vol = mesh.volumes()
    scale = np.abs(vol).mean()
    n_flat = int((np.abs(vol) <= fe_tol.degenerate_volume * scale).sum())
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
    local_sizes: tuple[LocalSize, ...] = (),
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
        Reuse / store the result in the package cache (``tets``); the key holds the Gmsh
        version and :func:`gmsh_settings`, never shared with pytetwild's entries.
    name : str
        What to call the part in messages (e.g. the file name).
    progress : callable (str) -> None, optional
        Receives a few coarse progress messages.
    local_sizes : tuple of LocalSize
        Cylinders where the edge must be finer than ``size`` (:mod:`.local_size`; seats
        that would otherwise hold too few nodes); part of the cache key when given.

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
    return _gmsh_mesh(surface, size, optimize, order, cache, name, progress, local_sizes)[0]


def _gmsh_mesh(surface, size, optimize=True, order=1, cache=True, name="surface",
               progress=None, local_sizes=()) -> tuple[TetMesh, str]:
    """:func:`tetrahedralize_gmsh`, and the fallback its tries took and why (``""`` for
    the remesh, and for a mesh read from the cache)."""
    if len(surface.faces) == 0 or not surface.is_watertight:
        raise MeshError(f"{name}: the surface is not closed (gmsh needs a watertight surface)")
    _import_gmsh()  # here: a missing gmsh says so before any child starts
    local = tuple(local_sizes)
    taken = {"fallback": ""}

    def make(vertices, faces, report):
        logger.info("gmsh tetrahedralizing %s: %d faces, edge %.4g m", name, len(faces), size)
        report(f"{name}: gmsh tetrahedralizing (edge {size:.4g} m, optimize={bool(optimize)})")
        start = time.perf_counter()
        mesh, taken["fallback"] = _run(surface, float(size), optimize, name, report, local)
        problem, n_slivers, min_angle = _defects(mesh)
        if problem is not None:
            raise MeshError(f"{name}: gmsh gave {problem} (try mesher='tetwild')")
        if n_slivers:
            logger.warning("%s: %d sliver tetrahedra (smallest dihedral %.2f deg < %g deg)",
                           name, n_slivers, min_angle, tol.sliver_dihedral_deg)
        logger.info("%s: gmsh took %.1f s", name, time.perf_counter() - start)
        return mesh

    mesh = cached_tetrahedralization(surface, size, optimize, order, cache, name, progress,
                                     make, mesher="gmsh",
                                     settings=gmsh_settings() + local_sizes_key(local))
    return mesh, taken["fallback"]
