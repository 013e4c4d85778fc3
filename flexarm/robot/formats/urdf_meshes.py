"""The meshes of a URDF: where a filename points, and one link mesh from many pieces.

A filename is relative to the URDF, ``file://`` (absolute) or ``package://name/...``:
the folder of the ``package.xml`` named ``name`` in or above the URDF's folder, a sibling
folder called ``name`` of one of those, or an entry of ``$ROS_PACKAGE_PATH``.

A link's CAD is used as published when it is one mesh element flexarm reads
(:data:`~flexarm.meshes.surface.SURFACE_EXTENSIONS`) at the link frame with a scale that
is a length unit.  Anything else (several elements, an ``<origin>``, a non-uniform or
odd scale, box/cylinder/sphere shapes, merged fixed links) becomes one *derived* binary
STL in metres in the link frame, named by its content so that importing again reuses it.
A COLLADA file's ``<unit meter=...>`` scales its coordinates (as ROS tools read it); its
``<up_axis>`` does not (URDF meshes are drawn in the link frame whatever it says).
A mesh file that is not a closed surface is never used as published: its derived copy is
closed by :func:`~flexarm.meshes.open_bodies.close_open_surface` (small holes within the
repair's tolerance, else the convex hull of each open body), with one warning naming the
user's file.
"""

from __future__ import annotations

import hashlib
import logging
import os
import re
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...fe.files import atomic_path, file_digest
from ...fe.typing import FloatArray
from ...fe.units import LENGTH_UNITS
from ...meshes.open_bodies import close_open_surface, is_closed
from ...meshes.surface import SURFACE_EXTENSIONS
from .urdf_tree import Geometry

__all__ = ["Piece", "resolve_mesh", "published", "merged_mesh", "write_derived"]

log = logging.getLogger(__name__)

_IDENTITY_TOL = 1e-12  # an <origin> this close to zero is the link frame itself
_UNIT_RTOL = 1e-9  # a scale this close to a unit's factor is that unit
_CYLINDER_SECTIONS = 64  # facets of a <cylinder>: 0.1 % volume error


@dataclass(frozen=True, eq=False)
class Piece:
    """One geometry element placed in the moving link's frame: ``transform`` (4, 4) of the
    element, ``link`` the URDF link it belongs to (the moving link or a fixed child)."""

    geometry: Geometry
    transform: FloatArray
    link: str


def _package_root(urdf: Path, package: str) -> Path:
    folders = [urdf.parent, *urdf.parent.parents]
    env = [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    for folder in folders + env:
        for candidate in (folder, folder / package):
            px = candidate / "package.xml"
            if not px.is_file():
                continue
            try:
                name = (ET.parse(px).getroot().findtext("name") or "").strip()
            except ET.ParseError:
                name = ""
            if name == package or candidate.name == package:
                return candidate
    raise ValueError(f"package://{package}: no package.xml named '{package}' in or above "
                     f"{urdf.parent} (nor in $ROS_PACKAGE_PATH)")


def resolve_mesh(urdf: Path, filename: str, link: str) -> Path:
    """The file a mesh ``filename`` of ``link`` points to (it must exist and be readable).

    Examples
    --------
    >>> resolve_mesh(Path("/nonexistent/r.urdf"), "m.stl", "base")
    Traceback (most recent call last):
    ...
    ValueError: link 'base': mesh file not found: /nonexistent/m.stl (from 'm.stl')
    """
    if filename.startswith("package://"):
        pkg, _, rel = filename[len("package://"):].partition("/")
        try:
            path = _package_root(urdf, pkg) / rel
        except ValueError as exc:
            raise ValueError(f"link '{link}': mesh '{filename}': {exc}") from None
    elif filename.startswith("file://"):
        path = Path(filename[len("file://"):])
    else:
        path = urdf.parent / filename
    path = path.resolve()
    if path.suffix.lower() not in SURFACE_EXTENSIONS:
        raise ValueError(f"link '{link}': mesh '{filename}': '{path.suffix}' files are not "
                         f"supported ({', '.join(SURFACE_EXTENSIONS)})")
    if not path.is_file():
        raise ValueError(f"link '{link}': mesh file not found: {path} (from '{filename}')")
    return path


def _collada_unit(path: Path) -> float:
    """Metres per coordinate of a COLLADA file (its ``<asset><unit meter=...>``, else 1)."""
    try:
        with open(path, "rb") as f:  # our handle: a parse stopped early leaves none open
            for _, el in ET.iterparse(f, events=("end",)):
                tag = el.tag.rsplit("}", 1)[-1]
                if tag == "unit":
                    return float(el.get("meter", 1.0))
                if tag == "asset":
                    break
    except (ET.ParseError, ValueError):
        pass  # trimesh reports a broken file when it reads it
    return 1.0


def _file_factor(path: Path) -> float:
    return _collada_unit(path) if path.suffix.lower() == ".dae" else 1.0


def published(piece: Piece, urdf: Path) -> tuple[Path, str] | None:
    """``(file, units)`` when ``piece`` is the whole link CAD as published: a mesh at the
    link frame with a uniform scale that is a length unit; None otherwise."""
    g = piece.geometry
    if g.shape != "mesh" or not np.allclose(piece.transform, np.eye(4), rtol=0,
                                            atol=_IDENTITY_TOL):
        return None
    path = resolve_mesh(urdf, g.filename, piece.link)
    s = np.asarray(g.scale)
    if not np.allclose(s, s[0], rtol=_UNIT_RTOL, atol=0):
        return None
    factor = float(s[0]) * _file_factor(path)
    for units, f in LENGTH_UNITS.items():
        if np.isclose(factor, f, rtol=_UNIT_RTOL, atol=0):
            # an open file is made a solid in a derived one (see _piece_mesh)
            return (path, units) if is_closed(_load(path, piece.link), path.name) else None
    return None


def _load(path: Path, link: str):
    import trimesh

    ext = path.suffix.lower()
    try:
        mesh = trimesh.load(path, file_type=ext[1:], force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types for bad bytes
        raise ValueError(f"link '{link}': cannot read mesh {path}: {exc}") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ValueError(f"link '{link}': mesh {path} holds no triangles")
    return trimesh.Trimesh(np.asarray(mesh.vertices, float), np.asarray(mesh.faces),
                           process=False)


def _primitive(g: Geometry):
    import trimesh

    if g.shape == "box":
        return trimesh.creation.box(extents=g.size)
    if g.shape == "cylinder":
        return trimesh.creation.cylinder(radius=g.size[0], height=g.size[1],
                                         sections=_CYLINDER_SECTIONS)
    return trimesh.creation.icosphere(subdivisions=3, radius=g.size[0])


def _piece_mesh(piece: Piece, urdf: Path):
    g = piece.geometry
    if g.shape != "mesh":
        mesh = _primitive(g)
    else:
        path = resolve_mesh(urdf, g.filename, piece.link)
        mesh = _load(path, piece.link)
        scale = np.asarray(g.scale, float) * _file_factor(path)
        if np.any(scale == 0):
            raise ValueError(f"link '{piece.link}': mesh '{g.filename}' has a zero scale "
                             f"{list(g.scale)}")
        S = np.diag([*scale, 1.0])
        # trimesh flips the faces of a mirroring transform, so the normals stay outward
        mesh.apply_transform(S)
        closed = close_open_surface(mesh, path.name)
        if closed.note:  # the geometry changed: say so, naming the user's file
            warnings.warn(f"{closed.note} (link '{piece.link}')", stacklevel=2)
        mesh = closed.mesh
    mesh.apply_transform(piece.transform)
    return mesh


def merged_mesh(pieces: list[Piece], urdf: Path, link: str = "link"):
    """One ``trimesh.Trimesh`` [m] in the moving link's frame of all ``pieces``: their
    union when they are closed (overlaps count once, touching pieces share a face), else
    their triangles side by side."""
    from ...meshes.union import union

    return union([_piece_mesh(p, urdf) for p in pieces], f"links.{link}")


def _ply_bytes(mesh) -> bytes:
    """Binary little-endian PLY of ``mesh`` with float64 vertices (trimesh's own export
    rounds them to float32).

    Examples
    --------
    >>> import io, trimesh
    >>> box = trimesh.creation.box((0.1, 0.2, 0.3))
    >>> back = trimesh.load(io.BytesIO(_ply_bytes(box)), file_type="ply")
    >>> bool(np.array_equal(back.vertices, box.vertices)), back.is_watertight
    (True, True)
    """
    vertices = np.ascontiguousarray(mesh.vertices, dtype="<f8")
    faces = np.asarray(mesh.faces, dtype=np.int64)
    packed = np.zeros(len(faces), dtype=[("n", "u1"), ("f", "<i4", (3,))])
    packed["n"], packed["f"] = 3, faces
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\n"
              "property double x\nproperty double y\nproperty double z\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\n"
              "end_header\n")
    return header.encode("ascii") + vertices.tobytes() + packed.tobytes()


def write_derived(mesh, folder: Path, link: str) -> Path:
    """Write ``mesh`` as ``<folder>/<link>-<content hash>.ply`` (binary, metres) unless
    that very file is there already; returns its path.

    PLY keeps double-precision vertices and the shared-vertex topology: the union of
    pieces that touch tangentially (a cylinder grazing another's end face) has vertices
    closer than float32 resolves, and an STL of it comes back open."""
    data = _ply_bytes(mesh)
    digest = hashlib.sha256(data).hexdigest()
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", link)
    path = Path(folder).resolve() / f"{stem}-{digest[:16]}.ply"  # links hold absolute paths
    if path.is_file() and file_digest(path) == digest:
        log.info("link %s: reusing %s", link, path)
        return path
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    log.info("link %s: wrote %s", link, path)
    return path
