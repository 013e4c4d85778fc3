"""Built-in watertight CAD surfaces in SI metres (for tests and the early demo).

All shapes are generated in code (trimesh, manifold3d) and are deterministic:
the same arguments give the same vertex and face arrays.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import trimesh

from ..fe.files import atomic_path
from ..fe.typing import PathType

__all__ = ["bar_surface", "cylinder_surface", "hollow_link_surface", "write_surface"]

logger = logging.getLogger(__name__)


def bar_surface(lx: float, ly: float, lz: float, origin=(0.0, 0.0, 0.0)) -> trimesh.Trimesh:
    """Closed surface of a rectangular bar (12 triangles), minimum corner at ``origin``.

    Parameters
    ----------
    lx, ly, lz : float
        Edge lengths [m].
    origin : (3,) float
        Minimum corner [m] (as in :meth:`TetMesh.box`).

    Examples
    --------
    >>> bar = bar_surface(1.0, 0.05, 0.05)
    >>> bool(bar.is_watertight), round(float(bar.volume), 12), bar.bounds.tolist()
    (True, 0.0025, [[0.0, 0.0, 0.0], [1.0, 0.05, 0.05]])
    """
    sizes = np.array([lx, ly, lz], dtype=np.float64)
    if sizes.shape != (3,) or not (sizes > 0).all():
        raise ValueError(f"bar edge lengths must be three positive numbers, got {sizes}")
    bar = trimesh.creation.box(extents=sizes)
    bar.apply_translation(sizes / 2 + np.asarray(origin, dtype=np.float64))
    return bar


def cylinder_surface(radius: float, length: float, segments: int = 48) -> trimesh.Trimesh:
    """Closed surface of a round bar along z, from z = 0 to ``length``.

    Parameters
    ----------
    radius, length : float
        [m]
    segments : int
        Sides of the polygonal section.

    Examples
    --------
    >>> rod = cylinder_surface(0.05, 0.2, segments=32)
    >>> bool(rod.is_watertight), rod.bounds[:, 2].tolist()
    (True, [0.0, 0.2])
    """
    if radius <= 0 or length <= 0 or segments < 3:
        raise ValueError(
            f"need radius > 0, length > 0, segments >= 3, got {radius}, {length}, {segments}"
        )
    rod = trimesh.creation.cylinder(radius=radius, height=length, sections=int(segments))
    rod.apply_translation((0.0, 0.0, length / 2))
    return rod


def _manifold_to_trimesh(solid) -> trimesh.Trimesh:
    mesh = solid.to_mesh64()
    vertices = np.array(mesh.vert_properties, dtype=np.float64)[:, :3]
    faces = np.array(mesh.tri_verts, dtype=np.int64)
    return trimesh.Trimesh(vertices, faces, process=False)


def _check_link(
    width: float,
    height: float,
    wall: float,
    hub_radius: float,
    bore_radius: float,
    hand_hole_radius: float,
) -> None:
    """Raise ValueError unless the walls, webs and hand hole of a hollow link fit [m]."""
    if not (bore_radius + wall < hub_radius and 2 * wall < min(width, height)):
        raise ValueError(
            "need bore_radius + wall < hub_radius and 2*wall < min(width, height), got "
            f"bore_radius={bore_radius}, wall={wall}, hub_radius={hub_radius}, "
            f"width={width}, height={height}"
        )
    if hand_hole_radius >= width / 2 - wall:
        raise ValueError(
            f"hand_hole_radius={hand_hole_radius} must be < width/2 - wall = {width / 2 - wall}"
        )


def _hub(radius: float, w: float, x: float, segments: int):
    """Manifold cylinder of ``radius`` and y-width ``w`` [m], axis along y through (x, 0, 0)."""
    from manifold3d import Manifold

    # Manifold's cylinders stand on z: centre it, turn its axis onto y, then move it to x.
    return (
        Manifold.cylinder(w, radius, -1.0, int(segments), True)
        .rotate((90.0, 0.0, 0.0))
        .translate((x, 0.0, 0.0))
    )


def _link_solid(
    length: float,
    width: float,
    height: float,
    wall: float,
    hub_radius: float,
    hub_width: float,
    bore_radius: float,
    hand_hole_radius: float,
    segments: int,
):
    """The Manifold solid of :func:`hollow_link_surface` (same parameters, [m])."""
    from manifold3d import Manifold

    arm = Manifold.cube((length, width, height), True).translate((length / 2, 0.0, 0.0))
    outer = (arm + _hub(hub_radius, hub_width, 0.0, segments)
             + _hub(hub_radius, hub_width, length, segments))
    x0, x1 = bore_radius + wall, length - bore_radius - wall
    cavity = Manifold.cube((x1 - x0, width - 2 * wall, height - 2 * wall), True).translate(
        ((x0 + x1) / 2, 0.0, 0.0)
    )
    # the bores are longer than the hubs so the boolean cuts cleanly through both faces
    bores = (_hub(bore_radius, 1.5 * hub_width, 0.0, segments)
             + _hub(bore_radius, 1.5 * hub_width, length, segments))
    solid = outer - cavity - bores
    if hand_hole_radius > 0:
        hole = Manifold.cylinder(height, hand_hole_radius, -1.0, int(segments), False)
        solid = solid - hole.translate((length / 2, 0.0, 0.0))
    return solid


def hollow_link_surface(
    length: float = 0.8,
    width: float = 0.18,
    height: float = 0.16,
    wall: float = 0.015,
    hub_radius: float = 0.11,
    hub_width: float = 0.2,
    bore_radius: float = 0.06,
    hand_hole_radius: float = 0.04,
    segments: int = 64,
) -> trimesh.Trimesh:
    """A cast robot link: a hollow box-section arm between two bearing hubs.

    The hub (bearing bore) axes are parallel to y through (0, 0, 0) and
    (``length``, 0, 0); the arm runs along x.  Its cavity is closed at the ends
    by ``wall``-thick webs around the bores and opens through a round hand hole in
    the top face at mid-length (so the casting is one connected shell of genus 2).

    Parameters
    ----------
    length : float
        Distance between the hub axes [m].
    width, height : float
        Outer section of the arm (y, z) [m].
    wall : float
        Wall thickness of the arm and of the webs next to the bores [m].
    hub_radius, hub_width : float
        Outer radius and y-width of the hubs [m].
    bore_radius : float
        Radius of the bearing bores [m].
    hand_hole_radius : float
        Radius of the access hole in the top wall [m] (0 for none: the cavity is
        then a sealed void).
    segments : int
        Sides of each polygonal circle.

    Returns
    -------
    trimesh.Trimesh
        Watertight, outward-wound surface [m].

    Examples
    --------
    >>> link = hollow_link_surface(segments=24)
    >>> bool(link.is_watertight), bool(link.is_winding_consistent), int(link.euler_number)
    (True, True, -2)
    >>> [round(float(x), 3) for x in link.extents]
    [1.02, 0.2, 0.22]
    """
    _check_link(width, height, wall, hub_radius, bore_radius, hand_hole_radius)
    solid = _link_solid(length, width, height, wall, hub_radius, hub_width, bore_radius,
                        hand_hole_radius, segments)
    surface = _manifold_to_trimesh(solid)
    logger.debug("hollow link: %d faces, %.4g m^3", len(surface.faces), surface.volume)
    return surface


def write_surface(path: PathType, surface: trimesh.Trimesh) -> None:
    """Write a surface atomically; the extension picks the format (``.stl`` is binary STL).

    Parameters
    ----------
    path : path-like
        ``.stl``, ``.obj`` or ``.ply``.
    surface : trimesh.Trimesh
        Coordinates [m] are written as they are (the file is in metres).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "bar.stl"
    >>> write_surface(path, bar_surface(0.5, 0.1, 0.1))
    >>> path.stat().st_size  # 84 + 50 bytes per triangle
    684
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in (".stl", ".obj", ".ply"):
        raise ValueError(f"{path}: cannot write '{ext}' surfaces (supported: .stl, .obj, .ply)")
    with atomic_path(path) as tmp:
        surface.export(tmp, file_type=ext[1:])
