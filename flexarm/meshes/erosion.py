"""The cavity of any closed solid by erosion: the points at least a wall thickness inside.

:func:`eroded_cavity` subtracts from the solid the union of everything within ``t`` of
its surface: one prism per face (``t`` either side along the face normal: exact walls
on every face and at convex edges) and a capsule around every concave edge, the hull of
a geodesic polyhedron *inscribed* in the ball at both ends (there, where a casting has
its fillets, the wall comes out slightly thinner than ``t``: at most 2.2 %, 0.7 % on
average with :data:`BALL_SEGMENTS`).  The union is manifold3d's.

What makes it usable on published link hulls (the UR10's, measured 2026-11-27):

* manifold3d's result is simplified below
  :attr:`~flexarm.meshes.tolerances.Tolerances.union_merge` of the part's size; where
  the face prisms only touch around a surface corner (a saddle) the cavity keeps a
  sliver up to it, cut off by an octahedron inscribed in the wall's ball; a body that
  ``decompose`` hands back twice is kept once (it would count its volume twice);
* for writing, the cavity is made to survive a file reader's repair
  (:func:`_without_caps`): needle edges collapsed, flat caps split away, and what is
  left degenerate moved tens of nanometres apart, so that the reader's vertex merge
  and degenerate-face removal find nothing to do;
* each erosion is kept in the package cache (``eroded-cavities``), keyed by the surface,
  the wall and the ball: a wall search evaluates a few walls once, and hollowing at the
  wall found (or a second import of the same robot) reads them back.

Imports only :mod:`flexarm.fe` and :mod:`flexarm.meshes`.
"""

from __future__ import annotations

import io
import logging

import numpy as np
import trimesh

from ..fe.errors import MeshError
from .tolerances import tol

__all__ = ["BALL_SEGMENTS", "capsule_edges", "eroded_cavity"]

logger = logging.getLogger(__name__)

#: Segments of the geodesic ball swept along concave edges.  Its support falls short of
#: the ball's by at most 2.2 % (mean 0.7 %) at 24, 4.5 % at 16, 1.3 % at 32; the cost
#: grows with its square.
BALL_SEGMENTS = 24
#: Format of the cached cavities (bump when the construction changes).
_VERSION = 13


def _unit_ball(segments: int) -> np.ndarray:
    """Vertices (n, 3) of manifold3d's geodesic unit sphere (on the sphere: inscribed)."""
    from manifold3d import Manifold

    mesh = Manifold.sphere(1.0, int(segments)).to_mesh64()
    return np.array(mesh.vert_properties, dtype=np.float64)[:, :3]


def _to_trimesh(solid) -> trimesh.Trimesh:
    mesh = solid.to_mesh64()
    vertices = np.array(mesh.vert_properties, dtype=np.float64)[:, :3]
    return trimesh.Trimesh(vertices, np.array(mesh.tri_verts, dtype=np.int64), process=False)


def capsule_edges(surface: trimesh.Trimesh, size: float) -> np.ndarray:
    """Vertex pairs (E, 2) of the edges of a closed ``surface`` that need a swept ball:
    concave ones, flat ones (treated as concave: it only costs a capsule) and the edges
    of needle faces, whose normal cannot be trusted.  ``size`` [m] is the part's largest
    extent.

    Examples
    --------
    >>> box = trimesh.creation.box((1.0, 1.0, 1.0))
    >>> capsule_edges(box, 1.0).shape  # the six face diagonals are flat
    (6, 2)
    """
    vertices, faces = np.asarray(surface.vertices), np.asarray(surface.faces)
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    twice_area = np.linalg.norm(cross, axis=1)
    longest = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
    degenerate = twice_area <= tol.hollow_needle_face * longest**2
    normals = cross / np.where(degenerate, 1.0, twice_area)[:, None]
    pairs = surface.face_adjacency
    edges = surface.face_adjacency_edges
    # height of face 1's far corner above face 0's plane: > 0 concave, 0 flat
    far = vertices[surface.face_adjacency_unshared[:, 1]]
    rise = np.einsum("ij,ij->i", normals[pairs[:, 0]], far - vertices[edges[:, 0]])
    concave = (rise > -tol.hollow_flat_edge * size) | degenerate[pairs].any(axis=1)
    ends = faces[degenerate]
    bad_edges = np.concatenate([ends[:, [0, 1]], ends[:, [1, 2]], ends[:, [2, 0]]])
    both = np.sort(np.vstack([edges[concave], bad_edges]), axis=1)
    return np.unique(both, axis=0)


def _erode(vertices: np.ndarray, faces: np.ndarray, edges: np.ndarray, thickness: float,
           segments: int, size: float, name: str) -> list[trimesh.Trimesh]:
    """The bodies of the erosion, computed (see the module docstring)."""
    from manifold3d import Error, Manifold, Mesh64, OpType

    solid = Manifold(Mesh64(vert_properties=np.ascontiguousarray(vertices),
                            tri_verts=faces.astype(np.uint64)))
    if solid.status() != Error.NoError:
        raise MeshError(f"{name}: manifold3d rejects the surface ({solid.status()})")
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(cross, axis=1, keepdims=True)
    normals = cross / np.where(length > 0, length, 1.0)
    # one prism per face: every point within `thickness` of the face along its normal
    # (a degenerate face gives a flat, empty hull; its edges carry capsules instead)
    shift = thickness * normals[:, None, :]
    prisms = np.concatenate([tri - shift, tri + shift], axis=1)
    pieces = [Manifold.hull_points(p) for p in prisms]
    ball = thickness * _unit_ball(segments)
    ends = vertices[edges]  # (E, 2, 3)
    capsules = (ends[:, :, None, :] + ball).reshape(len(ends), -1, 3)
    pieces += [Manifold.hull_points(c) for c in capsules]
    # every piece is an original mesh of its own, and simplify keeps the edges between
    # originals: one original, then collapse what is below the merge length
    cavity = (solid - Manifold.batch_boolean(pieces, OpType.Add)).as_original().simplify(
        tol.union_merge * size)
    cavity = _off_the_surface(cavity, vertices, thickness, tol.union_merge * size)
    floor = tol.hollow_sliver_volume * size**3
    bodies, seen = [], set()
    for c in cavity.decompose():
        body = _to_trimesh(c)
        # decompose can hand the same body back twice: keep one
        key = (len(body.vertices), *np.round(np.sort(body.vertices, axis=0)[[0, -1]].ravel()
                                             / (tol.union_merge * size)).astype(int))
        if c.volume() > floor and key not in seen:
            seen.add(key)
            bodies.append(body)
    return bodies


def _without_caps(mesh: trimesh.Trimesh, merge: float, passes: int = 20) -> trimesh.Trimesh:
    """``mesh`` as a file reader's repair will leave it, but still closed.

    Edges shorter than ``merge`` [m] (the short edges of needle faces) collapse where
    that keeps the surface a manifold, so the reader's vertex merge finds nothing to
    merge; then every *cap* the reader would drop as degenerate (a face whose third
    corner lies on its longest edge) is removed by splitting the face across that edge
    at the corner.  Volume (to the merge length) and closedness are kept.

    Examples
    --------
    >>> v = np.array([[0, 0, 0], [2, 0, 0], [1, 1e-12, 0], [1, 1, 0], [1, -0.5, 1.0]])
    >>> f = np.array([[0, 1, 2], [1, 0, 3], [0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4]])
    >>> m = trimesh.Trimesh(v, f, process=False)  # a closed solid with one flat cap
    >>> clean = _without_caps(m, 1e-8)
    >>> bool(clean.is_volume), len(clean.faces), round(float(clean.volume), 9) == round(
    ...     float(m.volume), 9)
    (True, 6, True)
    """
    from ..fe.tolerances import tol as fe_tol

    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = _collapsed(vertices, np.array(mesh.faces, dtype=np.int64),
                       max(float(merge), 10 * fe_tol.point_merge), passes)
    for _ in range(passes):
        caps = np.flatnonzero(~trimesh.triangles.nondegenerate(
            vertices[faces], height=fe_tol.point_merge))
        if caps.size == 0:
            break
        tri = vertices[faces[caps]]
        longest = np.argmax(np.linalg.norm(tri[:, [1, 2, 0]] - tri, axis=2), axis=1)
        split = _split_once(faces, caps, longest)
        if len(split) == len(faces) and np.array_equal(split, faces):
            break  # none can be split: the caller's check says so
        faces = split
    out = trimesh.Trimesh(_nudged(vertices, faces, fe_tol.point_merge), faces, process=False)
    out.remove_unreferenced_vertices()
    return out


def _nudged(vertices: np.ndarray, faces: np.ndarray, merge: float) -> np.ndarray:
    """``vertices`` with the corners of what is left degenerate (an edge the manifold
    condition kept from collapsing, a cap whose split would duplicate an edge) moved
    2.5 times trimesh's merge length off (it calls a face with a shorter edge
    degenerate): far enough that the reader neither merges nor drops them, tens of
    nanometres from where they were."""
    vertices = vertices.copy()
    step = 2.5 * max(merge, trimesh.tol.merge)
    for _ in range(3):
        tri = vertices[faces]
        shortest = np.linalg.norm(tri[:, [1, 2, 0]] - tri, axis=2).min(axis=1)
        bad = np.flatnonzero(~trimesh.triangles.nondegenerate(tri, height=merge)
                             | (shortest < step / 2))
        if bad.size == 0:
            break
        for f in bad:
            tri = vertices[faces[f]]
            length = np.linalg.norm(tri[[1, 2, 0]] - tri, axis=1)
            k = int(np.argmax(length))
            a, b, c = (int(faces[f, (k + i) % 3]) for i in range(3))
            ab = vertices[b] - vertices[a]
            foot = vertices[a] + ab * ((vertices[c] - vertices[a]) @ ab) / (ab @ ab)
            off = vertices[c] - foot
            if np.linalg.norm(off) < 1e-3 * merge:  # on the line: any perpendicular
                off = np.cross(ab, np.eye(3)[int(np.argmin(np.abs(ab)))])
            vertices[c] = foot + step * off / np.linalg.norm(off)
            short = int(np.argmin(length))
            u, v = int(faces[f, short]), int(faces[f, (short + 1) % 3])
            gap = vertices[v] - vertices[u]
            if np.linalg.norm(gap) < step:
                vertices[v] = vertices[u] + step * gap / max(np.linalg.norm(gap), 1e-300)
    # two sheets of one body that touch at a corner (a pinch): each corner steps back
    # into its body along its normal
    from scipy.spatial import cKDTree

    pairs = cKDTree(vertices).query_pairs(step, output_type="ndarray")
    if len(pairs):
        mesh = trimesh.Trimesh(vertices, faces, process=False)
        joined = {tuple(e) for e in np.sort(mesh.edges_unique, axis=1).tolist()}
        apart = [p for p in np.sort(pairs, axis=1).tolist() if tuple(p) not in joined]
        if apart:
            ends = np.unique(np.array(apart))
            vertices[ends] -= step * mesh.vertex_normals[ends]
    return vertices


def _collapsed(vertices: np.ndarray, faces: np.ndarray, merge: float,
               passes: int) -> np.ndarray:
    """``faces`` with every edge shorter than ``merge`` [m] collapsed onto its first
    vertex where that keeps the surface a manifold (the two vertices share no neighbour
    but the corners opposite the edge), its two faces dropped."""
    for _ in range(passes):
        edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]],
                                        faces[:, [2, 0]]]), axis=1)
        edges = np.unique(edges, axis=0)
        length = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
        short = edges[np.argsort(length)][: int((length < merge).sum())]
        if not len(short):
            break
        ring: dict = {}
        for i, f in enumerate(faces):
            for v in f:
                ring.setdefault(int(v), set()).add(i)
        moved, gone = {}, set()
        for u, v in short:
            u, v = int(u), int(v)
            if u in moved or v in moved or ring[u] & gone or ring[v] & gone:
                continue  # touched in this pass: next pass
            shared = ring[u] & ring[v]
            opposite = {int(w) for f in shared for w in faces[f]} - {u, v}
            around = ({int(w) for f in ring[u] for w in faces[f]}
                      & {int(w) for f in ring[v] for w in faces[f]}) - {u, v}
            if len(shared) != 2 or around != opposite:
                continue
            moved[v] = u
            moved[u] = u
            gone |= shared | ring[u] | ring[v]  # its fan changes: no second collapse here
            for f in shared:
                faces[f] = -1
        if not moved:
            break
        faces = faces[faces[:, 0] >= 0]
        for v, u in moved.items():
            faces[faces == v] = u
    return faces


def _split_once(faces: np.ndarray, caps: np.ndarray, k: np.ndarray) -> np.ndarray:
    """One pass of cap removals: cap (a, b, c) with c on its longest edge a-b (edge
    ``k`` of the cap, from corner k to k + 1) and its neighbour (b, a, d) across it
    become (b, c, d) and (c, a, d); a face already touched in this pass waits, a split
    whose edge c-d exists stays."""
    owner = {(int(f[e]), int(f[(e + 1) % 3])): i for i, f in enumerate(faces)
             for e in range(3)}
    gone, new, touched = [], [], set()
    for f, kf in zip(caps, k, strict=True):
        a, b, c = (int(faces[f, (kf + i) % 3]) for i in range(3))
        g = owner.get((b, a))
        if g is None or g == f or f in touched or g in touched:
            continue
        d = next((int(v) for v in faces[g] if v not in (a, b)), c)
        if d == c or (c, d) in owner or (d, c) in owner:
            continue
        gone += [f, g]
        new += [(b, c, d), (c, a, d)]
        touched.update((f, g))
    if not gone:
        return faces
    keep = np.ones(len(faces), dtype=bool)
    keep[gone] = False
    return np.vstack([faces[keep], np.array(new, dtype=faces.dtype)])


def _off_the_surface(cavity, vertices: np.ndarray, thickness: float, merge: float):
    """``cavity`` (a manifold3d solid) without the spikes that reach a surface corner:
    where the face prisms only touch around a corner (a saddle), the difference keeps a
    sliver of no volume up to it.  An octahedron inscribed in the wall's ball about each
    such corner cuts it off (every point of it is within the wall of the surface)."""
    from manifold3d import Manifold, OpType
    from scipy.spatial import cKDTree

    mesh = cavity.to_mesh64()
    inner = np.array(mesh.vert_properties, dtype=np.float64)[:, :3]
    if not len(inner):
        return cavity
    near = cKDTree(inner).query_ball_point(vertices, merge)
    corners = vertices[[i for i, hits in enumerate(near) if hits]]
    if not len(corners):
        return cavity
    logger.info("cutting the cavity off %d surface corners", len(corners))
    octahedron = thickness * np.vstack([np.eye(3), -np.eye(3)])
    cuts = [Manifold.hull_points(c + octahedron) for c in corners]
    return cavity - Manifold.batch_boolean(cuts, OpType.Add)


def _pack(bodies: list[trimesh.Trimesh]) -> bytes:
    buffer = io.BytesIO()
    arrays = {f"v{i}": b.vertices for i, b in enumerate(bodies)}
    arrays.update({f"f{i}": b.faces for i, b in enumerate(bodies)})
    np.savez(buffer, n=len(bodies), **arrays)
    return buffer.getvalue()


def _unpack(data: bytes) -> list[trimesh.Trimesh]:
    with np.load(io.BytesIO(data)) as z:
        return [trimesh.Trimesh(z[f"v{i}"], z[f"f{i}"], process=False)
                for i in range(int(z["n"]))]


def eroded_cavity(surface: trimesh.Trimesh, thickness: float,
                  segments: int = BALL_SEGMENTS, name: str = "surface",
                  edges: np.ndarray | None = None,
                  clean: bool = True) -> list[trimesh.Trimesh]:
    """Bodies [m] of the points at least ``thickness`` [m] inside the closed ``surface``
    (empty list: none), each outward-wound; read from the package cache when this very
    erosion was computed before.  ``clean``: the bodies as one mesh that survives a file
    reader's repair (:func:`_without_caps`; MeshError naming ``name`` where it cannot);
    without, each as manifold3d gives it (volumes and areas the same to rounding).

    Parameters
    ----------
    surface : trimesh.Trimesh
        Closed, consistently wound surface [m].
    thickness : float
        Wall thickness [m], > 0.
    segments : int
        Resolution of the ball swept along concave edges.
    name : str
        What to call the part in messages.
    edges : (E, 2) int, optional
        :func:`capsule_edges` of ``surface`` when the caller has them already.
    clean : bool
        See above.

    Examples
    --------
    >>> box = trimesh.creation.box((0.4, 0.2, 0.1))
    >>> (cavity,) = eroded_cavity(box, 0.01)
    >>> round(float(cavity.volume) * 1e6, 6), round(0.38 * 0.18 * 0.08 * 1e6, 6)
    (5472.0, 5472.0)
    """
    from ..fe.cache import BYTES, cache_key, cached

    vertices = np.ascontiguousarray(surface.vertices, dtype=np.float64)
    faces = np.ascontiguousarray(surface.faces, dtype=np.int64)
    size = float(np.ptp(vertices, axis=0).max())
    key = cache_key("eroded-cavity", _VERSION, vertices, faces, float(thickness),
                    int(segments), libraries=("manifold3d",))

    def compute() -> bytes:
        found = capsule_edges(surface, size) if edges is None else edges
        logger.info("%s: eroding %d faces and %d capsules by %.4g m", name, len(faces),
                    len(found), thickness)
        return _pack(_erode(vertices, faces, found, float(thickness), int(segments), size,
                            name))

    bodies = _unpack(cached("eroded-cavities", key, compute, codec=BYTES).value)
    if not clean:
        return bodies
    if not bodies:
        return bodies
    # cleaned together: two bodies may touch each other as a body may touch itself
    bodies = [_without_caps(trimesh.util.concatenate(bodies), tol.union_merge * size)]
    if not bodies[0].is_volume:
        raise MeshError(f"{name}: the cavity at {thickness * 1e3:.2f} mm walls does not stay "
                        "a closed surface once cleaned of its sub-micrometre faces (a "
                        "file reader would open it); try another wall")
    return bodies
