"""Repair and check closed triangle surfaces (the input of tetrahedralisation).

:func:`repair_surface` fixes what can be fixed without guessing the designer's
intent (coincident vertices, degenerate and duplicate faces, small holes, winding,
inverted normals); :func:`check_surface` refuses what is left with one clear line.
"""

from __future__ import annotations

import logging

import numpy as np
import trimesh

from ..fe.errors import MeshError
from ..fe.tolerances import tol as fe_tol
from .tolerances import tol

__all__ = ["repair_surface", "check_surface", "merge_digits", "MAX_FILLED_AREA",
           "MAX_FILLED_VOLUME", "winding_number"]

logger = logging.getLogger(__name__)

#: Hole filling guesses the missing surface: it is refused when the new faces cover more
#: than this share of the closed surface's area ...
MAX_FILLED_AREA = 0.01
#: ... or enclose more than this share of its volume, counted as the volume between the
#: new faces and each hole's centroid (zero for a flat patch on a flat hole).  A box
#: missing two triangles of neighbouring sides is "closed" by a diagonal patch that cuts
#: off a sixth of it; these bounds refuse that, and pass the few-triangle gaps of CAD
#: exports.
MAX_FILLED_VOLUME = 0.01


def merge_digits() -> int:
    """Decimal digits [m] that trimesh rounds vertices to when merging (``point_merge`` of fe).

    Examples
    --------
    >>> merge_digits()
    9
    """
    return int(round(-np.log10(fe_tol.point_merge)))


def repair_surface(surface: trimesh.Trimesh,
                   name: str = "surface") -> tuple[trimesh.Trimesh, tuple[str, ...]]:
    """Repaired copy of a triangle surface and a note for each repair made.

    In order: merge coincident vertices (within ``fe_tol.point_merge`` [m]), drop
    degenerate and duplicate faces and unused vertices, fill small holes, make the
    winding consistent and turn inward-pointing normals outward.  The input is not
    modified.  Holes are filled only when the patch is small: more than
    :data:`MAX_FILLED_AREA` of the area or :data:`MAX_FILLED_VOLUME` of the volume
    raises :class:`MeshError` naming ``name`` (the part would become another solid).

    Parameters
    ----------
    surface : trimesh.Trimesh
        Triangle surface, coordinates [m].
    name : str
        What to call it in messages (usually the file path).

    Returns
    -------
    repaired : trimesh.Trimesh
    notes : tuple of str
        One human-readable line per repair (empty if nothing was changed).

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box((1.0, 1.0, 1.0))
    >>> _ = box.invert()
    >>> fixed, notes = repair_surface(box)
    >>> round(float(fixed.volume), 12), notes
    (1.0, ('inverted the normals (they pointed inward)',))
    """
    mesh = surface.copy()
    notes: list[str] = []

    n_vertices = len(mesh.vertices)
    mesh.merge_vertices(merge_tex=True, merge_norm=True, digits_vertex=merge_digits())
    if len(mesh.vertices) < n_vertices:
        notes.append(f"merged {_count(n_vertices - len(mesh.vertices), 'coincident vertex')}")

    keep = mesh.nondegenerate_faces(height=fe_tol.point_merge)
    if not keep.all():
        mesh.update_faces(keep)
        notes.append(f"removed {_count(int((~keep).sum()), 'degenerate face')}")
    keep = mesh.unique_faces()
    if not keep.all():
        mesh.update_faces(keep)
        notes.append(f"removed {_count(int((~keep).sum()), 'duplicate face')}")
    n_vertices = len(mesh.vertices)
    mesh.remove_unreferenced_vertices()
    if len(mesh.vertices) < n_vertices:
        notes.append(f"removed {_count(n_vertices - len(mesh.vertices), 'unused vertex')}")

    if len(mesh.faces) and not mesh.is_watertight:
        n_faces = len(mesh.faces)
        trimesh.repair.fill_holes(mesh)
        if len(mesh.faces) > n_faces:
            area, volume = _filled_shares(mesh, n_faces)
            what = (f"{_count(len(mesh.faces) - n_faces, 'face')} covering {area:.2%} of the "
                    f"area and {volume:.2%} of the volume")
            if area > MAX_FILLED_AREA or volume > MAX_FILLED_VOLUME:
                raise MeshError(
                    f"{name}: the surface is open, and closing it takes {what} (at most "
                    f"{MAX_FILLED_AREA:.0%} and {MAX_FILLED_VOLUME:.0%}): that would be a "
                    "different solid; close the surface in the CAD export")
            notes.append(f"filled holes with {what}")

    if len(mesh.faces) and not mesh.is_winding_consistent:
        trimesh.repair.fix_winding(mesh)
        if mesh.is_winding_consistent:
            notes.append("made the face winding consistent")

    # One sign for the whole part: inner shells of voids legitimately enclose
    # negative volume, so bodies are never flipped one by one.
    if len(mesh.faces) and mesh.is_watertight and mesh.is_winding_consistent:
        if mesh.volume < 0:
            mesh.invert()
            notes.append("inverted the normals (they pointed inward)")
    return mesh, tuple(notes)


def _filled_shares(mesh: trimesh.Trimesh, n_old: int) -> tuple[float, float]:
    """Shares [-] of the area and of the volume of ``mesh`` in its faces from ``n_old``
    on (the hole patches).  The patch volume is that of the tetrahedra from each patch
    face to the centroid of its hole's boundary vertices, taken unsigned."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    new = np.asarray(mesh.faces[n_old:])
    pts = np.asarray(mesh.vertices)
    edges = np.sort(np.asarray(mesh.faces[:n_old])[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    keys, counts = np.unique(edges, axis=0, return_counts=True)
    rim = keys[counts == 1]  # each hole is one loop of these edges
    n = len(pts)
    graph = coo_matrix((np.ones(len(rim)), (rim[:, 0], rim[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    on_rim = np.zeros(n, dtype=bool)
    on_rim[rim.ravel()] = True
    sums = np.zeros((label.max() + 1, 3))
    np.add.at(sums, label[on_rim], pts[on_rim])
    centre = sums / np.maximum(np.bincount(label[on_rim], minlength=len(sums)), 1)[:, None]
    apex = centre[label[new[:, 0]]]
    a, b, c = (pts[new[:, k]] - apex for k in range(3))
    patch = float(np.abs(np.einsum("ij,ij->i", a, np.cross(b, c))).sum()) / 6.0
    area = float(mesh.area_faces[n_old:].sum()) / float(mesh.area)
    return area, patch / max(abs(float(mesh.volume)), np.finfo(float).tiny)


def _count(n: int, noun: str) -> str:
    if n == 1:
        return f"1 {noun}"
    return f"{n} {noun[:-2] + 'ices' if noun.endswith('ex') else noun + 's'}"


def _edge_counts(surface: trimesh.Trimesh) -> np.ndarray:
    """(k,) int: how many faces use each distinct (undirected) edge."""
    _, counts = np.unique(surface.edges_sorted, axis=0, return_counts=True)
    return counts


def check_surface(surface: trimesh.Trimesh, name: str = "surface", repaired: bool = True) -> None:
    """Raise :class:`MeshError` unless the surface bounds a positive volume.

    Parameters
    ----------
    surface : trimesh.Trimesh
        Triangle surface, coordinates [m].
    name : str
        What to call it in messages (usually the file path).
    repaired : bool
        Whether :func:`repair_surface` has already been tried (changes the hint).

    Examples
    --------
    >>> import trimesh
    >>> check_surface(trimesh.creation.box((0.1, 0.1, 0.1)))  # fine: no error
    >>> open_box = trimesh.creation.box((0.1, 0.1, 0.1))
    >>> open_box.update_faces([True] * 10 + [False] * 2)
    >>> check_surface(open_box, "box.stl", repaired=False)
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.MeshError: box.stl: the surface is open (4 boundary edges); try repair=True
    """
    if len(surface.faces) == 0:
        raise MeshError(f"{name}: the surface has no faces")
    counts = _edge_counts(surface)
    n_open = int((counts == 1).sum())
    if n_open:
        hint = " and repair could not close it" if repaired else "; try repair=True"
        raise MeshError(f"{name}: the surface is open ({_count(n_open, 'boundary edge')}){hint}")
    n_multi = int((counts > 2).sum())
    if n_multi:
        raise MeshError(
            f"{name}: the surface is not manifold "
            f"({_count(n_multi, 'edge')} shared by more than two faces)"
        )
    if not surface.is_winding_consistent:
        raise MeshError(
            f"{name}: inconsistent face winding (neighbouring faces disagree on which side is out)"
        )
    volume = float(surface.volume)
    extent = float(np.ptp(surface.vertices, axis=0).max())
    if volume <= tol.surface_min_volume * extent**3:
        hint = "; the normals point inward" if volume < 0 else ""
        raise MeshError(
            f"{name}: the surface encloses zero or negative volume ({volume:.3g} m^3){hint}"
        )
    logger.debug("%s: closed surface, %d faces, %.4g m^3", name, len(surface.faces), volume)


def winding_number(point: np.ndarray, triangles: np.ndarray) -> float:
    """How often the closed surface of ``triangles`` (F, 3, 3) winds around ``point``.

    1 inside an outward-wound surface, 0 outside: the solid angles of all faces seen from
    the point (Van Oosterom & Strackee), summed.  Exact for any closed surface, however
    non-convex, and robust for points not on it.
    """
    a, b, c = np.moveaxis(triangles - point, 1, 0)
    la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    dot = lambda u, v: np.einsum("ij,ij->i", u, v)  # noqa: E731
    den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb
    return float(np.arctan2(det, den).sum() / (2 * np.pi))
