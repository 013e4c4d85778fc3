"""Read a CAD triangle surface (STL/OBJ/PLY/DAE), scale it to metres, repair and check it.

A COLLADA (``.dae``) file is read with its scene transforms applied; its ``<unit>`` and
``<up_axis>`` are not (the caller's ``units`` say what a coordinate is, as for every other
format; robot descriptions pass the factor they resolved).  It needs ``pycollada``.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import trimesh

from ..fe.errors import MeshError, ReadError
from ..fe.typing import PathType
from ..fe.units import length_factor
from .repair import check_surface, merge_digits, repair_surface
from .tolerances import tol

__all__ = ["load_surface", "SURFACE_EXTENSIONS"]

logger = logging.getLogger(__name__)
#: Cache keys of the filled-hole notes this process has logged.
_SAID: set[str] = set()

#: Surface file types :func:`load_surface` reads.
SURFACE_EXTENSIONS = (".stl", ".obj", ".ply", ".dae")
_SUPPORTED = "supported: " + ", ".join(SURFACE_EXTENSIONS)


def _signature_problem(path: Path, ext: str) -> str | None:
    """Why the file cannot be a surface of type ``ext`` (None if it may be one).

    trimesh returns an *empty* mesh for garbage ``.stl``/``.obj`` bytes instead of
    raising, so the cheap format signatures are checked here first.
    """
    head = _head(path)
    if ext == ".stl":
        size = path.stat().st_size
        if size >= 84:
            count = int(np.frombuffer(head[80:84], dtype="<u4")[0])
            if 84 + 50 * count == size:
                return None
        if head.lstrip().lower().startswith(b"solid"):
            return None
        return "neither a binary STL of consistent length nor an ASCII STL ('solid ...')"
    if ext == ".ply":
        return None if head.startswith(b"ply") else "no 'ply' header"
    if ext == ".dae" and b"<collada" not in head.lower():
        return "no '<COLLADA' element in its first 4096 bytes"
    if b"\x00" in head:
        return "binary bytes in a text format"
    try:
        head.decode("utf-8")
    except UnicodeDecodeError:
        # A cut multi-byte character at the 4096-byte boundary is still text.
        try:
            head[:-3].decode("utf-8")
        except UnicodeDecodeError:
            return "not UTF-8 text"
    return None


def _head(path: Path) -> bytes:
    with open(path, "rb") as f:
        return f.read(4096)


def _read(path: Path) -> trimesh.Trimesh:
    ext = path.suffix.lower()
    if ext not in SURFACE_EXTENSIONS:
        raise ReadError(f"{path}: cannot read '{ext}' files ({_SUPPORTED})")
    problem = _signature_problem(path, ext)
    if problem:
        raise ReadError(f"{path}: cannot read it as {ext}: {problem} ({_SUPPORTED})")
    try:
        mesh = trimesh.load(path, file_type=ext[1:], force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types for bad bytes
        raise ReadError(f"{path}: cannot read it as {ext}: {exc} ({_SUPPORTED})") from exc
    if not isinstance(mesh, trimesh.Trimesh):
        raise ReadError(f"{path}: cannot read a triangle surface from it ({_SUPPORTED})")
    return mesh


def _check_size(mesh: trimesh.Trimesh, name: str, units: str) -> None:
    extent = float(np.ptp(mesh.vertices, axis=0).max())
    if not tol.part_size_min <= extent <= tol.part_size_max:
        raise MeshError(
            f"{name}: part is {extent:.3g} m across with units={units!r} (expected "
            f"{tol.part_size_min:g} to {tol.part_size_max:g} m): are the units right?"
        )


def _check_flat(mesh: trimesh.Trimesh, name: str) -> None:
    centred = np.asarray(mesh.vertices) - np.asarray(mesh.vertices).mean(axis=0)
    spread = np.linalg.svd(centred, compute_uv=False)
    if spread[-1] <= tol.surface_flatness * spread[0]:
        raise MeshError(f"{name}: the surface encloses zero volume (all its points lie in a plane)")


def load_surface(path: PathType, units: str = "m", repair: bool = True) -> trimesh.Trimesh:
    """Read a closed CAD surface, scaled to metres, repaired and checked.

    Parameters
    ----------
    path : path-like
        ``.stl``, ``.obj``, ``.ply`` or ``.dae`` file.
    units : {"m", "mm", "cm", "in"}
        Length unit of the file's coordinates.
    repair : bool
        Try :func:`~flexarm.meshes.repair.repair_surface` before checking (what it
        did is logged; a filled hole as a warning).  A hole whose patch would exceed
        :data:`~flexarm.meshes.repair.MAX_FILLED_AREA` of the area or
        :data:`~flexarm.meshes.repair.MAX_FILLED_VOLUME` of the volume is refused.
        Coincident vertices are merged either way (an STL stores every triangle's
        corners separately).

    Returns
    -------
    trimesh.Trimesh
        Watertight, consistently wound surface enclosing a positive volume [m].

    Raises
    ------
    ValueError
        Unknown ``units``.
    ReadError
        Missing, unreadable or unsupported file.
    MeshError
        Empty, flat, open, non-manifold, inconsistently wound, zero/negative volume,
        or implausibly sized for the units.

    Examples
    --------
    >>> import tempfile, pathlib, trimesh
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "cube.stl"
    >>> _ = trimesh.creation.box((20.0, 20.0, 20.0)).export(path)  # 20 mm cube
    >>> surface = load_surface(path, units="mm")
    >>> [float(x) for x in surface.extents], round(float(surface.volume), 12)
    ([0.02, 0.02, 0.02], 8e-06)
    """
    scale = length_factor(units)
    path = Path(path)
    name = str(path)
    if not path.is_file():
        raise ReadError(f"{path}: no such file")
    logger.info("reading surface %s (units=%s)", path, units)
    mesh = _read(path)
    if len(mesh.faces) == 0:
        raise MeshError(f"{name}: the surface has no faces")
    if scale != 1.0:
        mesh.apply_scale(scale)
    _check_size(mesh, name, units)
    _check_flat(mesh, name)
    if repair:
        mesh, notes = repair_surface(mesh, name)
        for note in notes:
            _log_repair(path, units, note)
    else:
        mesh.merge_vertices(merge_tex=True, merge_norm=True, digits_vertex=merge_digits())
    check_surface(mesh, name, repaired=repair)
    logger.info(
        "surface %s: %d vertices, %d faces, %.4g m^3",
        name,
        len(mesh.vertices),
        len(mesh.faces),
        mesh.volume,
    )
    return mesh


def _log_repair(path: Path, units: str, note: str) -> None:
    """Log what the repair did to ``path``: a filled hole changes the geometry, so it is
    a warning, but only the first time this file's content is read (by this process or
    an earlier command: the cache remembers it), since every command that meshes or
    measures the link reads it again; the rest is bookkeeping (info)."""
    if not note.startswith("filled holes"):
        logger.info("%s: %s", path, note)
        return
    from ..fe.cache import cache_key, cached
    from ..fe.files import file_digest

    key = cache_key("surface-note", str(path.resolve()), file_digest(path), units, note)
    said = key in _SAID or cached("surface-notes", key, lambda: True).is_hit
    _SAID.add(key)
    (logger.info if said else logger.warning)("%s: %s", path, note)
