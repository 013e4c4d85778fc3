"""Tetrahedralisations in the package cache (:mod:`flexarm.fe.cache`), keyed by the
surface, the settings, the mesher and its version.

Entries live in ``<cache root>/tets/<key>.npz`` (the flexarm ``.npz`` mesh format); an
entry that does not read back as a valid mesh is removed and meshed again.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np

from ..fe.cache import Codec, cache_key, cached, lookup
from ..fe.errors import MeshError
from ..fe.mesh import TetMesh
from ..fe.tolerances import tol as fe_tol
from .formats import npz
from .tolerances import tol

__all__ = ["tet_cache_key", "mesher_key_parts", "TET_CODEC", "MESHERS", "MESHER_SETTINGS",
           "MESHER_LIBRARY",
           "cached_tetrahedralization", "cached_mesh", "estimated_tets", "check_mesh_request",
           "MAX_TETS", "BYTES_PER_TET"]

logger = logging.getLogger(__name__)

#: The tetrahedralisers (``mesher=`` settings) and the PyPI package that does the work.
MESHERS = ("tetwild", "gmsh")
MESHER_LIBRARY = {"tetwild": "pytetwild", "gmsh": "gmsh"}
#: The values of a ``mesher`` setting: a tetrahedraliser, or ``"auto"`` (here, with the
#: meshers, so that checking a robot file's setting loads no mesher).
MESHER_SETTINGS = ("auto", *MESHERS)
#: Most tetrahedra a request may be estimated to give: more would not fit a workstation's
#: memory in the mesher, let alone in the FE solve that follows.
MAX_TETS = 2_000_000
#: Peak mesher memory per tetrahedron [bytes] (pytetwild: 1.9 kB at 160,000 tetrahedra).
BYTES_PER_TET = 2000
#: Regular tetrahedra of edge h fill a volume V with 6 sqrt(2) V / h^3 elements (the
#: meshers give 1.2 to 1.4 times this: the estimate is a lower bound).
_TETS_PER_EDGE_CUBE = 6.0 * np.sqrt(2.0)
#: An edge this many times the part's largest extent cannot describe it (a coarse mesh of
#: a small flange, edge about its size, is still allowed): usually the units are wrong.
_MAX_EDGE_OVER_PART = 2.0


def _read_checked(path) -> TetMesh:
    return npz.read(path).check(str(path))


#: How a mesh is stored: flexarm ``.npz``, checked (orientation, finite nodes) on reading.
TET_CODEC = Codec(".npz", npz.write, _read_checked)


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
        Its name and installed version enter the key: the meshers never share an entry.
    settings : tuple
        What else decides the mesher's output (its options); must have a stable ``repr``.

    Examples
    --------
    >>> import numpy as np
    >>> v, f = np.eye(3), np.array([[0, 1, 2]])
    >>> tet_cache_key(v, f, 0.01, True, 1) == tet_cache_key(v, f, 0.01, True, 2)
    False
    >>> tet_cache_key(v, f, 0.01, True, 1) == tet_cache_key(v, f, 0.01, True, 1, mesher="gmsh")
    False
    """
    return cache_key(
        "tets",
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.ascontiguousarray(faces, dtype=np.int64),
        float(size),
        bool(optimize),
        int(order),
        *mesher_key_parts(mesher, settings),
        libraries=(MESHER_LIBRARY[mesher],),
    )


def mesher_key_parts(mesher: str, settings: tuple = ()) -> tuple:
    """What decides a mesher's output besides the surface, size and order: its name, its
    ``settings`` and the meshing tolerances (cache-key parts; the version goes in through
    ``libraries=(MESHER_LIBRARY[mesher],)``)."""
    if mesher not in MESHERS:
        raise ValueError(f"mesher must be one of {', '.join(map(repr, MESHERS))}, got {mesher!r}")
    parts = (tol.tet_envelope, tol.sliver_dihedral_deg, fe_tol.degenerate_volume, mesher,
             tuple(settings))
    # only fTetWild's envelope follows the edge: Gmsh's keys stay as they were
    return parts + ((tol.tet_envelope_edge,) if mesher == "tetwild" else ())


def estimated_tets(volume: float, size: float) -> float:
    """About how many tetrahedra of edge ``size`` [m] fill ``volume`` [m^3] (a lower bound).

    Examples
    --------
    >>> round(estimated_tets(1e-3, 0.01))  # a litre at 10 mm
    8485
    """
    return _TETS_PER_EDGE_CUBE * float(volume) / float(size) ** 3


def check_mesh_request(surface, size: float, name: str) -> None:
    """Refuse an edge length that cannot give a useful mesh of ``surface``, before meshing.

    Raises
    ------
    MeshError
        ``size`` [m] more than twice the part's largest extent (no element would
        resolve it: often wrong units), or an estimated element count above
        :data:`MAX_TETS` (the figure, the memory it would take and the smallest edge
        length that fits).

    Examples
    --------
    >>> import trimesh
    >>> check_mesh_request(trimesh.creation.box((0.1, 0.1, 0.1)), 0.01, "box")
    >>> check_mesh_request(trimesh.creation.box((0.1, 0.1, 0.1)), 1e-5, "box")
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.MeshError: box: edge 1e-05 m on a part of 0.001 m^3 gives about ...
    """
    extent = float(np.max(surface.extents))
    if size > _MAX_EDGE_OVER_PART * extent:
        raise MeshError(f"{name}: edge {size:.4g} m is larger than the part ({extent:.4g} m "
                        f"across): use a smaller edge, or check the units")
    volume = abs(float(surface.volume))
    n = estimated_tets(volume, size)
    if n > MAX_TETS:
        smallest = (_TETS_PER_EDGE_CUBE * volume / MAX_TETS) ** (1 / 3)
        raise MeshError(f"{name}: edge {size:.4g} m on a part of {volume:.3g} m^3 gives about "
                        f"{n:.2g} tetrahedra (limit {MAX_TETS:.0e}, about "
                        f"{n * BYTES_PER_TET / 1e9:.2g} GB to mesh): use an edge of at least "
                        f"{smallest:.2g} m, or check the units")


def cached_mesh(key: str) -> TetMesh | None:
    """The cached mesh of ``key`` if there is a valid one (nothing is meshed)."""
    return lookup("tets", key, TET_CODEC)


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
    check_mesh_request(surface, size, name)
    report = progress or (lambda message: None)
    vertices = np.asarray(surface.vertices, dtype=np.float64)
    faces = np.asarray(surface.faces, dtype=np.int64)
    key = tet_cache_key(vertices, faces, size, optimize, order, mesher=mesher, settings=settings)
    entry = cached("tets", key, lambda: _mesh_and_check(surface, vertices, faces, order, name,
                                                          report, make, mesher),
                   TET_CODEC, enabled=cache)
    mesh = entry.value
    if entry.is_hit:
        report(f"{name}: tetrahedral mesh from cache ({mesh.n_tets} elements)")
    else:
        report(f"{name}: {mesh.n_tets} elements, {mesh.n_nodes} nodes")
    return mesh


def _mesh_and_check(surface, vertices, faces, order, name, report, make, mesher) -> TetMesh:
    """Run the mesher, compare the volume with the surface's, promote to Tet10."""
    mesh = make(vertices, faces, report)
    reference = float(surface.volume)
    error = (float(mesh.volumes().sum()) - reference) / reference
    if abs(error) > tol.tet_volume_warn:
        logger.warning("%s: tetrahedra differ from the surface volume by %.2g%%", name, 100 * error)
    if order == 2:
        mesh = mesh.to_tet10()
    logger.info("tetrahedralized %s (%s): %d elements, %d nodes", name, mesher, mesh.n_tets,
                mesh.n_nodes)
    return mesh
