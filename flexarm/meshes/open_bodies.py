"""A published surface that is not closed, made a solid within a stated tolerance.

Robot makers publish collision meshes as they come out of their tools: several bodies in
one file, a tube left open at one end, T-junctions where two bodies meet.  A flexible
link needs a closed surface, so :func:`close_open_surface` does, in order:

1. :func:`~flexarm.meshes.repair.repair_surface` on the whole file (coincident vertices,
   small holes, winding): when that closes it, nothing else happens.
2. Otherwise body by body (connected components of the merged triangles): a closed body
   stays; an open one has each hole (a loop of boundary edges) closed by a fan to the
   loop's centroid when all patches together stay within :data:`MAX_FILLED_AREA` of the
   file's surface area (the same bound as the repair's); a body with zero volume is
   dropped (a stray sheet).
3. An open body whose holes are larger, or that flat patches do not close (a rim that
   crosses itself), is replaced by its **convex hull**: an explicit fallback, stated in
   the result's one-line :attr:`ClosedSurface.note` that names the user's file.  The hull
   of an open tube is the solid rod it bounds.

The bodies are then united (:func:`~flexarm.meshes.union.union`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from ..fe.errors import MeshError
from .repair import MAX_FILLED_AREA, check_surface, merge_digits, repair_surface
from .union import union

__all__ = ["ClosedSurface", "close_open_surface", "is_closed", "MAX_FILLED_AREA"]


@dataclass(frozen=True, eq=False)
class ClosedSurface:
    """A surface made closed [m] and what was done to it.

    Attributes
    ----------
    mesh : trimesh.Trimesh
        Watertight, outward-wound surface [m] (same frame as the input).
    n_bodies : int
        Connected bodies of the input (after merging coincident vertices).
    n_open : int
        Bodies of the input that were not closed.
    filled_share : float
        Area of the hole patches added, over the input's surface area [-].
    hulled : int
        Open bodies replaced by their convex hull.
    hull_share : float
        Volume of those hulls over the volume of the result [-].
    note : str
        One line on what was done, naming the file ('' when it was closed already).
    """

    mesh: trimesh.Trimesh
    n_bodies: int
    n_open: int
    filled_share: float
    hulled: int
    hull_share: float
    note: str = ""


def is_closed(mesh: trimesh.Trimesh, name: str = "surface") -> bool:
    """Whether :func:`~flexarm.meshes.repair.repair_surface` makes ``mesh`` a closed volume.

    Examples
    --------
    >>> ball = trimesh.creation.icosphere(3, 0.1)        # 1280 triangles
    >>> is_closed(ball), is_closed(trimesh.Trimesh(ball.vertices, ball.faces[1:]))
    (True, True)
    >>> box = trimesh.creation.box((0.1, 0.1, 0.1))      # a whole side missing: 17 %
    >>> is_closed(trimesh.Trimesh(box.vertices, box.faces[2:]))
    False
    """
    try:
        fixed, _ = repair_surface(mesh, name)
    except MeshError:
        return False
    return bool(len(fixed.faces)) and fixed.is_volume


def _boundary_loops(body: trimesh.Trimesh) -> list[np.ndarray]:
    """Directed boundary edges (k, 2) of ``body``, one array per hole."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    directed = np.asarray(body.faces)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    key = np.sort(directed, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    rim = directed[counts[inverse.ravel()] == 1]
    if not len(rim):
        return []
    n = len(body.vertices)
    graph = coo_matrix((np.ones(len(rim)), (rim[:, 0], rim[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    loop = label[rim[:, 0]]
    return [rim[loop == k] for k in np.unique(loop)]


def _fan_patches(body: trimesh.Trimesh, loops: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(new vertices, new faces) closing every loop by a fan to its centroid; the faces
    run each rim edge backwards, so they wind as the body does."""
    pts = np.asarray(body.vertices)
    n = len(pts)
    centres = np.array([pts[np.unique(e)].mean(axis=0) for e in loops])
    faces = np.concatenate([np.column_stack([e[:, 1], e[:, 0], np.full(len(e), n + k)])
                            for k, e in enumerate(loops)])
    return centres, faces


def _patch_area(body: trimesh.Trimesh, loops: list[np.ndarray]) -> float:
    """Area [m^2] of the fan patches of ``loops``."""
    centres, faces = _fan_patches(body, loops)
    pts = np.vstack([body.vertices, centres])
    tri = pts[faces]
    return float(0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]),
                                      axis=1).sum())


def close_open_surface(mesh: trimesh.Trimesh, name: str = "surface") -> ClosedSurface:
    """``mesh`` made a closed solid as the module docstring says; ``name`` (the user's
    file) is what the note and any error name.

    Raises
    ------
    MeshError
        Nothing with a volume is left (every body a flat sheet).

    Examples
    --------
    >>> tube = trimesh.creation.cylinder(0.05, 0.4, sections=32)
    >>> side = np.abs(tube.face_normals[:, 2]) < 0.5        # the open tube: no end caps
    >>> cap = trimesh.creation.box((0.2, 0.2, 0.05))        # a closed housing beside it
    >>> _ = cap.apply_translation((0.0, 0.0, 0.225))
    >>> both = trimesh.util.concatenate([trimesh.Trimesh(tube.vertices, tube.faces[side]),
    ...                                  cap])
    >>> res = close_open_surface(both, "forearm.stl")
    >>> res.mesh.is_volume, res.n_bodies, res.n_open, res.hulled
    (True, 2, 1, 1)
    >>> res.note.split(":")[0]
    'forearm.stl'
    """
    if is_closed(mesh, name):
        fixed, _ = repair_surface(mesh, name)
        return ClosedSurface(fixed, 1, 0, 0.0, 0, 0.0)
    merged = mesh.copy()
    merged.merge_vertices(digits_vertex=merge_digits())
    merged.update_faces(merged.unique_faces())
    merged.update_faces(merged.nondegenerate_faces())
    bodies = merged.split(only_watertight=False)
    total_area = float(merged.area)
    kept, open_bodies, dropped = [], [], 0
    for body in bodies:
        fixed = _repaired(body, name)
        if fixed is not None:
            kept.append(fixed)
        elif _volume_of_hull(body) > 0:
            open_bodies.append(body)
        else:
            dropped += 1
    loops = [_boundary_loops(b) for b in open_bodies]
    share = sum(_patch_area(b, lp) for b, lp in zip(open_bodies, loops, strict=True)) / total_area
    filled, hulls = [], []
    for body, lp in zip(open_bodies, loops, strict=True):
        patched = _filled(body, lp) if share <= MAX_FILLED_AREA else None
        if patched is not None:
            filled.append(patched)
        else:
            hulls.append(body.convex_hull)
    if not kept and not filled and not hulls:
        raise MeshError(f"{name}: no closed body and no open one with a volume in it")
    solid = _united(kept + filled + hulls, name)
    hull_share = sum(float(h.volume) for h in hulls) / float(solid.volume)
    n_open = len(open_bodies) + dropped
    note = _note(name, len(bodies), n_open, sum(len(e) for lp in loops for e in lp), share,
                 len(hulls), hull_share, dropped)
    return ClosedSurface(solid, len(bodies), n_open, share if not hulls else 0.0, len(hulls),
                         hull_share, note)


def _united(pieces: list, name: str) -> trimesh.Trimesh:
    """The union of closed ``pieces`` as the file readers will see it (repaired and
    checked).  manifold3d's plain union first: the simplification of
    :func:`~flexarm.meshes.union.union` can pinch bodies that touch along a face a few
    tenths of a micrometre apart (float32 files) into an edge shared by four faces."""
    from manifold3d import Manifold, Mesh64, OpType

    def solid(m):
        return Manifold(Mesh64(vert_properties=np.ascontiguousarray(m.vertices, dtype=np.float64),
                               tri_verts=np.ascontiguousarray(m.faces, dtype=np.uint64)))

    raw = Manifold.batch_boolean([solid(p) for p in pieces], OpType.Add).to_mesh64()
    plain = trimesh.Trimesh(np.array(raw.vert_properties, dtype=np.float64)[:, :3],
                            np.array(raw.tri_verts, dtype=np.int64), process=False)
    for candidate in (plain, lambda: union(pieces, name)):
        mesh = candidate() if callable(candidate) else candidate
        try:
            fixed, _ = repair_surface(mesh, name)
            check_surface(fixed, name)
        except MeshError:
            continue
        return fixed
    raise MeshError(f"{name}: its bodies could not be united into one closed surface")


def _repaired(body: trimesh.Trimesh, name: str) -> trimesh.Trimesh | None:
    """The body closed by the repair (small holes only), else None."""
    try:
        fixed, _ = repair_surface(body, name)
    except MeshError:
        return None
    if not fixed.is_volume or fixed.volume <= 0:
        return None
    return fixed


def _volume_of_hull(body: trimesh.Trimesh) -> float:
    """Volume [m^3] of the body's convex hull (0 for a flat or degenerate body)."""
    pts = np.asarray(body.vertices)
    if len(pts) < 4:
        return 0.0
    spread = np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)
    if spread[-1] <= 1e-9 * spread[0]:
        return 0.0
    try:
        return float(body.convex_hull.volume)
    except Exception:  # qhull refuses a degenerate set; scipy raises its own error type
        return 0.0


def _filled(body: trimesh.Trimesh, loops: list[np.ndarray]) -> trimesh.Trimesh | None:
    """The body with its holes fanned shut, if that makes it a closed volume."""
    centres, faces = _fan_patches(body, loops)
    out = trimesh.Trimesh(np.vstack([body.vertices, centres]),
                          np.vstack([body.faces, faces]), process=False)
    if not out.is_volume:
        return None
    if out.volume < 0:
        out.invert()
    return out


def _note(name: str, n_bodies: int, n_open: int, n_edges: int, share: float, n_hulls: int,
          hull_share: float, dropped: int) -> str:
    what = (f"{name}: not a closed surface ({n_bodies} bodies, {n_open} open, "
            f"{n_edges} boundary edges)")
    if n_hulls:
        why = (f"closing its holes would add {share:.1%} of its area, more than the "
               f"{MAX_FILLED_AREA:.0%} a repair may" if share > MAX_FILLED_AREA else
               f"flat patches on its holes ({share:.1%} of its area) do not close it")
        return (f"{what}; {why}: the open "
                f"{'body is' if n_hulls == 1 else f'{n_hulls} bodies are'} replaced by "
                f"{'its convex hull' if n_hulls == 1 else 'their convex hulls'} "
                f"({hull_share:.0%} of the solid's volume)")
    extra = f", {dropped} flat sheet{'s' if dropped > 1 else ''} dropped" if dropped else ""
    return f"{what}; its holes closed by flat patches adding {share:.2%} of its area{extra}"
