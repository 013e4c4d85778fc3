"""Where a closed surface passes through itself, and the surface of the solid it encloses.

Published collision hulls are closed and consistently wound, yet some touch themselves:
a vertex a few nanometres through a face of another part of the hull, two sheets of a
thin flange crossing over a few micrometres.  A conforming mesher (Gmsh's boundary
recovery) refuses such a surface ("a segment and a facet intersect"), while fTetWild
absorbs it in its envelope but never meshes twice alike.  The union of the surface with
itself (manifold3d, deterministic), with features far below any mesh size simplified
away, is the same solid as a clean surface that the deterministic mesher fills.

Only edge-through-face crossings are found (two coplanar overlapping faces are not).
"""

from __future__ import annotations

import logging

import numpy as np
import trimesh

from .tolerances import tol

__all__ = ["crossings", "united_surface"]

logger = logging.getLogger(__name__)

#: Edges per block of the sweep (memory: block x candidate faces booleans).
_BLOCK = 256


def _diagonal(vertices: np.ndarray) -> float:
    return float(np.linalg.norm(np.ptp(vertices, axis=0)))


def _candidates(lo_e, hi_e, lo_f, hi_f) -> tuple[np.ndarray, np.ndarray]:
    """(edge, face) index pairs whose bounding boxes overlap (sweep along the longest axis)."""
    axis = int(np.argmax(np.ptp(np.concatenate([lo_f, hi_f]), axis=0)))
    by_lo = np.argsort(lo_f[:, axis], kind="stable")
    lo_sorted = lo_f[by_lo, axis]
    edge_order = np.argsort(lo_e[:, axis], kind="stable")
    pairs_e, pairs_f = [], []
    for start in range(0, len(edge_order), _BLOCK):
        block = edge_order[start:start + _BLOCK]
        upper = np.searchsorted(lo_sorted, hi_e[block, axis].max(), side="right")
        faces = by_lo[:upper]
        faces = faces[hi_f[faces, axis] >= lo_e[block, axis].min()]
        if not len(faces):
            continue
        overlap = np.all((lo_e[block, None, :] <= hi_f[None, faces, :])
                         & (hi_e[block, None, :] >= lo_f[None, faces, :]), axis=2)
        i, j = np.nonzero(overlap)
        pairs_e.append(block[i])
        pairs_f.append(faces[j])
    if not pairs_e:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(pairs_e), np.concatenate(pairs_f)


def crossings(vertices, faces, gap: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Edges that pass through (or within ``gap`` of) a face they do not share a corner with.

    Parameters
    ----------
    vertices : (n, 3) float
        Surface vertices [m].
    faces : (m, 3) int
        Triangles.
    gap : float, optional
        Distance [m] below which an edge end counts as touching a face's plane; default
        ``tol.self_intersection_gap`` times the bounding-box diagonal.

    Returns
    -------
    edges : (k, 2) int
        Vertex pairs of the crossing edges.
    faces : (k,) int
        The face each one crosses.

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box((1.0, 1.0, 1.0))
    >>> len(crossings(box.vertices, box.faces)[1])
    0
    >>> two = trimesh.util.concatenate([box, box.copy().apply_translation([0.5, 0.2, 0.1])])
    >>> len(crossings(two.vertices, two.faces)[1]) > 0
    True
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    gap = tol.self_intersection_gap * _diagonal(v) if gap is None else float(gap)
    edges = np.unique(np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]),
                              axis=1), axis=0)
    p, q = v[edges[:, 0]], v[edges[:, 1]]
    tri = v[f]
    k, j = _candidates(np.minimum(p, q) - gap, np.maximum(p, q) + gap,
                       tri.min(axis=1) - gap, tri.max(axis=1) + gap)
    shares = (f[j] == edges[k, 0, None]).any(axis=1) | (f[j] == edges[k, 1, None]).any(axis=1)
    k, j = k[~shares], j[~shares]
    a, b, c = tri[j, 0], tri[j, 1], tri[j, 2]
    n = np.cross(b - a, c - a)
    norm = np.linalg.norm(n, axis=1)
    ok = norm > 0
    k, j, a, b, c, n, norm = k[ok], j[ok], a[ok], b[ok], c[ok], n[ok], norm[ok]
    sp = np.einsum("ij,ij->i", p[k] - a, n) / norm
    sq = np.einsum("ij,ij->i", q[k] - a, n) / norm
    # reaches the plane from both sides (within gap), and is not lying in it
    reach = (np.minimum(sp, sq) < gap) & (np.maximum(sp, sq) > -gap)
    reach &= np.maximum(np.abs(sp), np.abs(sq)) >= gap
    t = np.clip(sp / np.where(sp == sq, 1.0, sp - sq), 0.0, 1.0)
    x = p[k] + t[:, None] * (q[k] - p[k])

    def side(u, w):
        return np.einsum("ij,ij->i", np.cross(w - u, x - u), n)

    # on a face's edge counts (the pierced point of a box's split face lies on its diagonal)
    inside = (side(a, b) >= 0) & (side(b, c) >= 0) & (side(c, a) >= 0)
    hit = reach & inside
    return edges[k[hit]], j[hit]


def _manifold(mesh: trimesh.Trimesh):
    from manifold3d import Manifold, Mesh64

    return Manifold(Mesh64(vert_properties=np.ascontiguousarray(mesh.vertices, dtype=np.float64),
                           tri_verts=np.ascontiguousarray(mesh.faces, dtype=np.uint64)))


def _self_united(mesh: trimesh.Trimesh):
    """``mesh`` united with itself (manifold3d), or None.  manifold3d counts a region the
    surface encloses twice once *out*, so this is only right where sheets overlap thinly:
    the volume must stay the surface's."""
    solid = _manifold(mesh)
    if solid.status().name != "NoError":
        return None
    united = solid + solid
    if abs(united.volume() - mesh.volume) > tol.self_intersection_volume * abs(mesh.volume):
        return None
    return united


def _united_bodies(surface: trimesh.Trimesh):
    """The union of the surface's separate bodies, each clean or thinly self-touching (a
    body enclosing space inside out, such as a cavity, cannot be one of them)."""
    solids = [_self_united(body) for body in surface.split(only_watertight=False)]
    if not solids or any(s is None for s in solids):
        return None
    solid = solids[0]
    for other in solids[1:]:
        solid = solid + other
    return solid


def united_surface(surface: trimesh.Trimesh, name: str = "surface") -> trimesh.Trimesh | None:
    """``surface`` if no sheet of it touches or crosses another (:func:`crossings`), else
    the surface of the solid it encloses: the surface united with itself where its sheets
    only touch, else its separate bodies united (manifold3d), features below
    ``tol.self_intersection_merge`` times the diagonal simplified away (ten and a hundred
    times less where that makes sheets touch).  None when it crosses itself otherwise,
    manifold3d refuses it, or the result still touches itself (two sheets through one
    point).

    The same surface always gives the same result (manifold3d is deterministic).

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box((1.0, 1.0, 1.0))
    >>> united_surface(box) is box
    True
    >>> two = trimesh.util.concatenate([box, box.copy().apply_translation([0.5, 0.3, 0.2])])
    >>> round(float(united_surface(two).volume), 9)  # 2 m^3 less the overlap
    1.72
    """
    v = np.asarray(surface.vertices, dtype=np.float64)
    f = np.asarray(surface.faces, dtype=np.int64)
    found = len(crossings(v, f)[1])
    if not found:
        return surface
    # thin touches of one surface (a shell's cavity included), else overlapping bodies
    solid = _self_united(surface) or _united_bodies(surface)
    if solid is None:
        logger.info("%s: the surface crosses itself", name)
        return None
    # the coarsest simplification whose result does not touch itself (a fixed ladder)
    for merge in tol.self_intersection_merge * 10.0 ** -np.arange(3):
        out = solid.simplify(merge * _diagonal(v)).to_mesh64()
        united = trimesh.Trimesh(np.array(out.vert_properties, dtype=np.float64)[:, :3],
                                 np.array(out.tri_verts, dtype=np.int64), process=False)
        if united.is_volume and not len(crossings(united.vertices, united.faces)[1]):
            logger.info("%s: %d edges through faces: meshing the union of the surface (%+.2g "
                        "of its volume)", name, found, united.volume / surface.volume - 1)
            return united
    logger.info("%s: the surface still touches itself after its union", name)
    return None
