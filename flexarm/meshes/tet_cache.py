"""On-disk cache of tetrahedralisations, keyed by the surface and the settings.

Files live in ``cache_dir()/tets/<sha256>.npz`` (the flexarm ``.npz`` mesh
format), written atomically, so an interrupted run never leaves a bad entry.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..fe.errors import FlexarmError
from ..fe.files import cache_dir, digest
from ..fe.mesh import TetMesh
from ..fe.tolerances import tol
from .formats import npz

__all__ = [
    "tet_cache_key",
    "tet_cache_path",
    "load_cached",
    "store_cached",
    "CACHE_VERSION",
    "MESHERS",
    "cached_tetrahedralization",
]

logger = logging.getLogger(__name__)

#: Bump when the meshing procedure changes so old entries are not reused.
CACHE_VERSION = 1
#: The tetrahedralisers (``mesher=`` settings); pytetwild is the default.
MESHERS = ("tetwild", "gmsh")


def tet_cache_key(
    vertices: np.ndarray,
    faces: np.ndarray,
    size: float,
    optimize: bool,
    order: int,
    mesher: str = "tetwild",
    settings: tuple = (),
) -> str:
    """SHA-256 hex key of a tetrahedralisation request.

    The two meshers never share an entry: any other mesher than ``"tetwild"`` adds
    its name and ``settings`` to the key (pytetwild keys are those of before the
    ``mesher`` setting existed, so existing cache entries stay valid).

    Parameters
    ----------
    vertices : (n, 3) float
        Surface vertices [m] (hashed as float64 bytes).
    faces : (k, 3) int
        Surface triangles (hashed as int64 bytes).
    size : float
        Target edge length [m].
    optimize : bool
    order : {1, 2}
    mesher : {"tetwild", "gmsh"}
    settings : tuple
        What else decides the mesher's output (e.g. its version and options); must
        have a stable ``repr``.

    Examples
    --------
    >>> import numpy as np
    >>> v, f = np.eye(3), np.array([[0, 1, 2]])
    >>> tet_cache_key(v, f, 0.01, True, 1) == tet_cache_key(v, f, 0.01, True, 2)
    False
    >>> tet_cache_key(v, f, 0.01, True, 1) == tet_cache_key(v, f, 0.01, True, 1, mesher="gmsh")
    False
    """
    if mesher not in MESHERS:
        raise ValueError(f"mesher must be one of {', '.join(map(repr, MESHERS))}, got {mesher!r}")
    extra = () if mesher == "tetwild" and not settings else (mesher, tuple(settings))
    return digest(
        "tets",
        CACHE_VERSION,
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.ascontiguousarray(faces, dtype=np.int64),
        float(size),
        bool(optimize),
        int(order),
        tol.tet_envelope,
        tol.sliver_dihedral_deg,
        tol.degenerate_volume,
        *extra,
    )


def tet_cache_path(key: str) -> Path:
    """Where the entry for ``key`` lives (the folder is created)."""
    folder = cache_dir() / "tets"
    folder.mkdir(parents=True, exist_ok=True)
    return folder / f"{key}.npz"


def load_cached(key: str) -> TetMesh | None:
    """The cached mesh for ``key``, or None if absent or unreadable (then it is removed)."""
    path = tet_cache_path(key)
    if not path.is_file():
        return None
    try:
        mesh = npz.read(path).check(str(path))
    except (FlexarmError, OSError, ValueError, KeyError) as exc:
        logger.warning("ignoring unreadable tet cache entry %s: %s", path, exc)
        path.unlink(missing_ok=True)
        return None
    logger.info("tet cache hit %s (%d elements)", path.name, mesh.n_tets)
    return mesh


def store_cached(key: str, mesh: TetMesh) -> Path:
    """Write ``mesh`` under ``key`` atomically; return the file path."""
    path = tet_cache_path(key)
    npz.write(path, mesh)
    logger.info("tet cache stored %s", path)
    return path


def cached_tetrahedralization(
    surface,
    size: float,
    optimize: bool,
    order: int,
    cache: bool,
    name: str,
    progress: Callable[[str], None] | None,
    make: Callable[[np.ndarray, np.ndarray, Callable[[str], None]], TetMesh],
    mesher: str = "tetwild",
    settings: tuple = (),
) -> TetMesh:
    """What every mesher shares around its own ``make(vertices, faces, report) -> Tet4``:
    argument checks, the cache lookup and store, the volume check against the
    surface, and the Tet10 promotion (see :func:`~flexarm.meshes.tetwild.tetrahedralize`
    for the parameters)."""
    size = float(size)
    if not np.isfinite(size) or size <= 0:
        raise ValueError(f"size must be a positive edge length [m], got {size}")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 (Tet4) or 2 (Tet10), got {order}")
    report = progress or (lambda message: None)
    vertices = np.asarray(surface.vertices, dtype=np.float64)
    faces = np.asarray(surface.faces, dtype=np.int64)
    key = None
    if cache:
        key = tet_cache_key(vertices, faces, size, optimize, order, mesher=mesher,
                            settings=settings)
        cached = load_cached(key)
        if cached is not None:
            report(f"{name}: tetrahedral mesh from cache ({cached.n_tets} elements)")
            return cached
    mesh = make(vertices, faces, report)
    reference = float(surface.volume)
    error = (float(mesh.volumes().sum()) - reference) / reference
    if abs(error) > tol.tet_volume_warn:
        logger.warning("%s: tetrahedra differ from the surface volume by %.2g%%", name, 100 * error)
    if order == 2:
        mesh = mesh.to_tet10()
    if key is not None:
        store_cached(key, mesh)
    report(f"{name}: {mesh.n_tets} elements, {mesh.n_nodes} nodes")
    logger.info("tetrahedralized %s (%s): %d elements, %d nodes", name, mesher, mesh.n_tets,
                mesh.n_nodes)
    return mesh
