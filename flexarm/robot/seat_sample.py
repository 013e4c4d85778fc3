"""A dense, deterministic sample of a link's CAD surface with outward normals.

The bearing-seat finder (:mod:`flexarm.robot.seats`) and its report work on this sample
rather than on a tet mesh, so what they find does not depend on the tetrahedraliser:
:func:`surface_sample` spreads points evenly over any triangulated surface (the R2
low-discrepancy sequence, no random numbers), :func:`link_sample` samples a link's CAD
once per process.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..fe.typing import FloatArray
from .description import Link

__all__ = ["SAMPLE_DIVISIONS", "SurfaceSample", "link_sample", "surface_sample"]

#: Sample spacing = link bounding-box diagonal / this (~30-80k points on a robot link).
SAMPLE_DIVISIONS = 200
_R2 = 1.32471795724474602596  # plastic number: the R2 low-discrepancy sequence


@dataclass(frozen=True, eq=False)
class SurfaceSample:
    """Points spread evenly over a closed surface.

    Attributes
    ----------
    points : (n, 3) float
        Sample points [m] in the link frame.
    normals : (n, 3) float
        Outward unit normal of the triangle each point lies on.
    weight : float
        Surface area per point [m^2].
    spacing : float
        Nominal distance between neighbouring points [m].
    diagonal : float
        Bounding-box diagonal of the surface [m].
    """

    points: FloatArray
    normals: FloatArray
    weight: float
    spacing: float
    diagonal: float


def surface_sample(vertices, faces, spacing: float | None = None) -> SurfaceSample:
    """Deterministic, even sample of a triangulated surface (no random numbers).

    Every triangle gets its share of ``area / spacing^2`` points (systematic allocation,
    so the total is exact), placed by the R2 low-discrepancy sequence folded into the
    triangle: long thin CAD triangles get a few points spread along them.

    Parameters
    ----------
    vertices : (v, 3) float
        Surface vertices [m].
    faces : (f, 3) int
        Triangles, wound counter-clockwise seen from outside (outward normals).
    spacing : float, optional
        Point spacing [m]; default ``diagonal / SAMPLE_DIVISIONS``.

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box((0.2, 0.1, 0.1))
    >>> s = surface_sample(box.vertices, box.faces, spacing=0.005)
    >>> len(s.points), round(s.weight * len(s.points), 6), s.normals[0].tolist()
    (4000, 0.1, [-1.0, 0.0, 0.0])
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    diag = float(np.linalg.norm(np.ptp(v, axis=0)))
    h = diag / SAMPLE_DIVISIONS if spacing is None else float(spacing)
    tri = v[f]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    cross = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    total = float(area.sum())
    if not total > 0 or not h > 0:
        raise ValueError(f"surface_sample: need a surface with area > 0 and spacing > 0, got "
                         f"area {total} m^2, spacing {h} m")
    cum = np.floor(np.cumsum(area) / h**2).astype(np.int64)
    count = np.diff(cum, prepend=0)
    owner = np.repeat(np.arange(len(f)), count)
    # Each triangle takes the next stretch of one R2 sequence: a contiguous stretch is as
    # even as the whole, and congruent triangles (a fan of cap triangles) do not all leave
    # the same spot empty, as restarting the sequence in each would.
    j = np.arange(len(owner))
    s = (0.5 + j / _R2) % 1.0
    t = (0.5 + j / _R2**2) % 1.0
    fold = s + t > 1.0  # the unit square's far half maps onto the triangle by a reflection
    s[fold], t[fold] = 1.0 - s[fold], 1.0 - t[fold]
    pts = tri[owner, 0] + s[:, None] * e1[owner] + t[:, None] * e2[owner]
    normals = cross[owner] / np.maximum(2.0 * area[owner], np.finfo(float).tiny)[:, None]
    return SurfaceSample(pts, normals, total / max(len(pts), 1), h, diag)


@lru_cache(maxsize=32)
def _cached_sample(path: str, units: str, mtime: float) -> SurfaceSample:
    from ..fe.topology import outer_faces
    from ..meshes import load_surface

    surf = load_surface(path, units=units)
    # a seat is on the outside: a hollow link's cavity wall would read as bores and faces
    faces = np.asarray(surf.faces)
    return surface_sample(surf.vertices, faces[outer_faces(surf.vertices, faces)])


def link_sample(link: Link) -> SurfaceSample:
    """:func:`surface_sample` of the link's CAD [m, link frame] (kept for the process).

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> s = link_sample(load_robot().links[-1])
    >>> round(s.spacing * 1e3, 2), len(s.points) > 10_000
    (1.14, True)
    """
    if link.mesh is None:
        raise ValueError(f"links.{link.name}: no CAD mesh to find bearing seats on")
    path = Path(link.mesh)
    return _cached_sample(str(path), link.units, path.stat().st_mtime)
