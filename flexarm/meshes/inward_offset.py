"""The cavity of a closed solid: every point at least a wall thickness ``t`` inside it.

:func:`~flexarm.meshes.hollow.hollow_surface` turns the cavity into a shell.  It is built
in one of two ways:

``"convex"``
    The surface is convex up to CAD faceting noise (``tol.hollow_convex_depth``,
    ``tol.hollow_convex_volume``): the cavity is the intersection of its hull's face
    half-spaces moved inward by ``t``.  This *is* the inward offset of a convex body,
    exact to rounding, and takes milliseconds (qhull).
``"erosion"``
    Any other closed surface: the morphological erosion ``S - (dS (+) B_t)``
    (:mod:`flexarm.meshes.erosion`: exact walls on every face and at convex edges, at
    most 2.2 % thinner at concave ones; cached per surface and wall).  CAD of several
    bodies that overlap or touch gets instead the points farther than ``t`` from the
    surface of their union, a level set of the sampled distance
    (:mod:`flexarm.meshes.level_set_cavity`: a manifold strictly inside it by
    construction, its convex edges rounded at the grid's scale; cached the same way).

CAD of several closed bodies that overlap, or of one that touches itself, is first
replaced by the surface of the solid it encloses
(:func:`~flexarm.meshes.self_intersections.united_surface`): hollowing each body as it
is would count the overlaps twice and run cavities through the other bodies' skins.

Imports only :mod:`flexarm.fe` and :mod:`flexarm.meshes`.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np
import trimesh
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection, QhullError

from ..fe.errors import MeshError
from .erosion import BALL_SEGMENTS, capsule_edges, eroded_cavity
from .level_set_cavity import level_set_cavity
from .repair import check_surface, winding_number
from .self_intersections import united_surface
from .tolerances import tol

__all__ = ["BALL_SEGMENTS"]  # re-exported from .erosion

logger = logging.getLogger(__name__)

#: Planes of the hull closer than this (normals; offsets over the largest extent) merge.
_PLANE_DIGITS = 12
#: Target size of the temporary (points x planes) arrays [elements].
_CHUNK = 1 << 22


def _planes(equations: np.ndarray, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Unique hull planes as unit normals (J, 3) and offsets (J,): inside is n.x <= d."""
    normals = equations[:, :3]
    offsets = -equations[:, 3]
    # qhull splits coplanar faces into triangles with (nearly) the same plane: merging
    # them avoids needle facets in the offset polytope and shrinks every later array.
    key = np.round(np.column_stack([normals, offsets / size]), _PLANE_DIGITS)
    _, first = np.unique(key, axis=0, return_index=True)
    first.sort()
    return normals[first], offsets[first]


def _chebyshev(normals: np.ndarray, offsets: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre and radius [m] of the largest ball inside {x : normals x <= offsets}.

    Moving every plane inward by t leaves the same centre with radius R - t, so one
    linear programme gives every offset polytope's interior point and the thickness R
    at which nothing is left.
    """
    a_ub = np.column_stack([normals, np.ones(len(normals))])
    res = linprog(
        c=[0.0, 0.0, 0.0, -1.0],
        A_ub=a_ub,
        b_ub=offsets,
        bounds=[(None, None)] * 3 + [(0.0, None)],
        method="highs",
    )
    if res.status != 0:
        raise MeshError(f"no inscribed ball in the convex hull ({res.message})")
    return res.x[:3], float(res.x[3])


def _vertex_depth(points, normals, offsets) -> np.ndarray:
    """Distance [m] of each point below the boundary of the convex polytope (>= 0 inside)."""
    depth = np.empty(len(points))
    step = max(1, _CHUNK // len(normals))
    for i in range(0, len(points), step):
        depth[i:i + step] = (offsets - points[i:i + step] @ normals.T).min(axis=1)
    return depth


def _face_depth_bound(triangles, normals, offsets) -> np.ndarray:
    """Upper bound [m] on how deep each triangle (F, 3, 3) reaches below the hull surface.

    The depth of a point, min_j (d_j - n_j x), is below every single plane's distance,
    whose maximum over a triangle is at a corner: so min_j max_corner is an upper bound.
    It is tight for faces lying on a hull facet and loose only for the few that straddle
    a hull edge; those get the exact linear programme of :meth:`_Solid._face_depth`.
    """
    bound = np.empty(len(triangles))
    step = max(1, _CHUNK // (3 * len(normals)))
    for i in range(0, len(triangles), step):
        depth = offsets - triangles[i:i + step] @ normals.T  # (f, 3, J)
        bound[i:i + step] = depth.max(axis=1).min(axis=1)
    return bound


def _one_per_cluster(points: np.ndarray, radius: float) -> np.ndarray:
    """``points`` (n, 3) with every cluster of points within ``radius`` [m] of each other
    (transitively) replaced by its first point."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(points).query_pairs(radius, output_type="ndarray")
    n = len(points)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    _, first = np.unique(label, return_index=True)
    return points[np.sort(first)]


def _hull_mesh(points: np.ndarray) -> trimesh.Trimesh:
    """Closed, outward-wound surface of the convex hull of ``points`` (n, 3).

    Not :func:`trimesh.convex.convex_hull`: its repair drops qhull's needle triangles
    (offset planes of nearly coplanar CAD facets make some) and leaves the hull open.
    """
    hull = ConvexHull(points)
    used = np.unique(hull.simplices)
    new_id = np.zeros(len(points), dtype=np.int64)
    new_id[used] = np.arange(len(used))
    vertices, faces = points[used], new_id[hull.simplices]
    # qhull's triangles come in either winding: turn each to its facet's outward normal
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", cross, hull.equations[:, :3]) < 0
    faces[flip] = faces[flip][:, ::-1]
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    if not mesh.is_winding_consistent:  # a needle's cross product may have lied
        trimesh.repair.fix_winding(mesh)
        if mesh.volume < 0:
            mesh.invert()
    return _flip_flat_faces(mesh)


def _flip_flat_faces(mesh: trimesh.Trimesh, passes: int = 20) -> trimesh.Trimesh:
    """``mesh`` with every face of near-zero height (a corner on the opposite edge: qhull
    triangulates coplanar facets so) replaced, with its neighbour across that edge, by the
    two faces of the other diagonal.  A file reader's repair would drop such a face and
    open the surface; the flip keeps it closed and the volume unchanged."""
    vertices, faces = mesh.vertices, mesh.faces.copy()
    limit = tol.hollow_flat_face * float(np.ptp(vertices, axis=0).max())
    for _ in range(passes):
        tri = vertices[faces]
        edges = tri[:, [1, 2, 0]] - tri  # edge k runs from corner k to corner k + 1
        length = np.linalg.norm(edges, axis=2)
        k = np.argmax(length, axis=1)  # the long edge; its opposite corner is k + 2
        area2 = np.linalg.norm(np.cross(edges[:, 0], edges[:, 1]), axis=1)
        flat = np.flatnonzero(area2 < limit * length[np.arange(len(faces)), k])
        if flat.size == 0:
            break
        faces = _flip_once(faces, flat, k, vertices)
    return trimesh.Trimesh(vertices, faces, process=False)


def _flip_once(faces: np.ndarray, flat: np.ndarray, k: np.ndarray,
               vertices: np.ndarray) -> np.ndarray:
    """One pass of edge flips over the ``flat`` faces (each flip touches two faces; a face
    already touched in this pass waits for the next)."""
    owner = {}
    for f in range(len(faces)):
        for e in range(3):
            owner[(faces[f, e], faces[f, (e + 1) % 3])] = f
    done = set()
    for f in flat:
        a, b, c = (faces[f, (k[f] + i) % 3] for i in range(3))
        g = owner.get((b, a))
        if g is None or f in done or g in done:
            continue
        d = next(v for v in faces[g] if v not in (a, b))
        normal = np.cross(vertices[faces[g, 1]] - vertices[faces[g, 0]],
                          vertices[faces[g, 2]] - vertices[faces[g, 0]])
        new = [(c, a, d), (c, d, b)]
        for i, (u, v, w) in enumerate(new):
            n = np.cross(vertices[v] - vertices[u], vertices[w] - vertices[u])
            new[i] = (u, v, w) if n @ normal >= 0 else (u, w, v)
        faces[f], faces[g] = new
        done.update((f, g))
    return faces


def _stack(meshes: Sequence[trimesh.Trimesh]) -> trimesh.Trimesh:
    """One mesh of several bodies, each body's vertices and faces as they were."""
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    vertices = np.vstack([m.vertices for m in meshes])
    faces = np.vstack([m.faces + k for m, k in zip(meshes, offsets, strict=True)])
    return trimesh.Trimesh(vertices, faces, process=False)


def _one_solid(surface: trimesh.Trimesh, name: str) -> tuple[trimesh.Trimesh, bool]:
    """``surface`` as one solid, and whether it is clean enough to erode: several bodies
    that overlap are replaced by the surface of their union; one body whose sheets touch
    is kept (the mesher unites it) unless that union cannot be formed."""
    united = united_surface(surface, name)
    if united is None:
        logger.info("%s: its sheets touch and cannot be united: hollowed as they are", name)
        return surface, False
    if surface.body_count == 1:
        return surface, True
    if united is not surface:
        logger.info("%s: %d bodies united (%.4g of %.4g m^3)", name, surface.body_count,
                    united.volume, surface.volume)
    return united, False


class _Solid:
    """One closed surface, prepared once to be hollowed at any number of thicknesses."""

    def __init__(self, surface: trimesh.Trimesh, name: str = "surface"):
        check_surface(surface, name)
        self.surface, self.clean = _one_solid(surface, name)
        surface = self.surface
        self.name = name
        self.vertices = np.array(surface.vertices, dtype=np.float64)
        self.faces = np.array(surface.faces, dtype=np.int64)
        self.volume = float(surface.volume)
        self.size = float(np.ptp(self.vertices, axis=0).max())
        hull = ConvexHull(self.vertices)
        self.hull_volume = float(hull.volume)
        self.normals, self.offsets = _planes(hull.equations, self.size)
        # The hull's inscribed ball bounds every cavity: beyond its radius nothing is
        # left inside the hull, so certainly nothing inside the surface either.
        self.center, self.inradius = _chebyshev(self.normals, self.offsets)
        self.depth = float(_vertex_depth(self.vertices, self.normals, self.offsets).max())
        self.is_convex = bool(
            self.depth <= tol.hollow_convex_depth * self.size
            and self.hull_volume - self.volume <= tol.hollow_convex_volume * self.hull_volume
        )
        self._bound = None  # per-face depth bounds, computed when first needed
        self._exact = {}  # face -> exact depth [m], from a linear programme each
        self._inside = None  # whether the hull's inscribed-ball centre is inside
        self._capsules = None  # edges that get a swept ball (erosion)
        self._eroded = {}  # (thickness, segments, clean) -> cavity bodies
        logger.debug(
            "%s: %d faces, convex=%s (vertex depth %.3g m, hull volume +%.3g %%), "
            "inradius %.4g m", name, len(self.faces), self.is_convex, self.depth,
            100 * (self.hull_volume / self.volume - 1), self.inradius,
        )

    # ---------------------------------------------------------------- convex cavity
    def _face_depth(self, face: int) -> float:
        """Deepest point [m] of one face below the hull surface (a small LP, cached)."""
        if face not in self._exact:
            tri = self.vertices[self.faces[face]]
            # max s  s.t.  n_j . (tri^T lam) + s <= d_j,  sum(lam) = 1,  lam >= 0
            res = linprog(
                c=[0.0, 0.0, 0.0, -1.0],
                A_ub=np.column_stack([self.normals @ tri.T, np.ones(len(self.normals))]),
                b_ub=self.offsets,
                A_eq=[[1.0, 1.0, 1.0, 0.0]],
                b_eq=[1.0],
                bounds=[(0.0, None)] * 3 + [(None, None)],
                method="highs",
            )
            self._exact[face] = float(res.x[3]) if res.status == 0 else np.inf
        return self._exact[face]

    def _surface_clear_of(self, thickness: float) -> bool:
        """Whether no face reaches ``thickness`` deep below the hull surface.

        The offset polytope is the set of points at least ``thickness`` deep: if no face
        reaches it, the surface and the cavity cannot touch and their union is a valid
        shell (wall between ``thickness - depth`` and ``thickness``).
        """
        if self._bound is None:
            self._bound = _face_depth_bound(self.vertices[self.faces], self.normals,
                                            self.offsets)
        suspects = np.flatnonzero(self._bound >= thickness)
        return all(self._face_depth(int(f)) < thickness for f in suspects)

    def _convex_cavity_points(self, thickness: float) -> np.ndarray | None:
        """Corners (n, 3) [m] of the hull moved inward by ``thickness``; None if flat."""
        halfspaces = np.column_stack([self.normals, thickness - self.offsets])
        try:
            points = HalfspaceIntersection(halfspaces, self.center).intersections
            ConvexHull(points)  # a cavity only a rounding error thick fails here
        except QhullError:
            if self.inradius - thickness < tol.hollow_flat_cavity * self.size:
                return None  # a sheet only rounding errors thick: no cavity
            raise
        # Offset planes of nearly coplanar facets meet in clusters of corners nanometres
        # apart; kept, they become needle faces that a file's float32 rounding collapses
        # into holes.  One corner per cluster keeps the cavity closed through any file.
        return _one_per_cluster(points, tol.hollow_point_merge * self.size)

    def _convex_ok(self, thickness: float) -> bool:
        """Whether the offset hull is a valid cavity: clear of the surface and inside it."""
        if not self._surface_clear_of(thickness):
            logger.info("%s: the surface dips %.4g m or more below its hull: eroding instead",
                        self.name, thickness)
            return False
        if self._inside is None:
            # Clear of the surface, the (convex, connected) cavity is either all inside
            # or all in a pocket between surface and hull: its centre tells which.
            triangles = self.vertices[self.faces]
            self._inside = winding_number(self.center, triangles) > 0.5
        return self._inside

    # --------------------------------------------------------------- general cavity
    def _capsule_edges(self) -> np.ndarray:
        """Vertex pairs (E, 2) of edges that need a swept ball: concave or unsure ones."""
        if self._capsules is None:
            self._capsules = capsule_edges(self.surface, self.size)
        return self._capsules

    def _eroded_cavity(self, thickness: float, segments: int,
                       clean: bool = True) -> list[trimesh.Trimesh]:
        """Bodies [m] of the points at least ``thickness`` inside (empty list: none).

        Clean CAD is eroded (:func:`~flexarm.meshes.erosion.eroded_cavity`: exact walls
        on faces and convex edges; ``clean``: fit to be written).  CAD whose bodies
        overlap or touch gets the level set of its distance
        (:func:`~flexarm.meshes.level_set_cavity.level_set_cavity`), a manifold strictly
        inside it where the erosion's prisms and capsules cross the other bodies' skins.
        """
        key = (float(thickness), int(segments), clean)
        if key not in self._eroded:
            if self.clean:
                found = eroded_cavity(self.surface, thickness, segments, self.name,
                                      self._capsule_edges(), clean)
            else:
                found = level_set_cavity(self.surface, thickness, self.name)
            self._eroded[key] = found
        return self._eroded[key]

    def eroded_area(self, thickness: float, segments: int = BALL_SEGMENTS) -> float:
        """Surface area [m^2] of the eroded cavity at ``thickness`` [m]: the rate at which
        its volume shrinks as the wall grows (0 when nothing is left)."""
        if thickness <= 0:
            return float(self.surface.area)
        if self._solid_at(thickness):
            return 0.0
        return sum(float(c.area) for c in self._eroded_cavity(thickness, segments, False))

    # ------------------------------------------------------------------------ both
    def _solid_at(self, thickness: float) -> bool:
        return thickness >= self.inradius - tol.hollow_solid * self.size

    def cavity_volume(self, thickness: float, segments: int = BALL_SEGMENTS) -> float:
        """Volume [m^3] removed at this wall thickness (0 when nothing is left inside)."""
        if thickness <= 0 or self._solid_at(thickness):
            return 0.0
        if self.is_convex:
            points = self._convex_cavity_points(thickness)
            if points is None:
                return 0.0
            if self._convex_ok(thickness):
                return float(ConvexHull(points).volume)
        return sum(float(c.volume) for c in self._eroded_cavity(thickness, segments, False))

    def cavity(self, thickness: float,
               segments: int = BALL_SEGMENTS) -> tuple[trimesh.Trimesh | None, str]:
        """Outward-wound cavity surface [m] at this wall thickness and how it was built:
        ``"convex"``, ``"erosion"`` (several bodies if the inside splits up), ``"level
        set"`` (CAD whose bodies overlap or touch), or None and
        ``"solid"`` when nothing is left inside."""
        cavity, method = None, "solid"
        if not self._solid_at(thickness):
            if self.is_convex:
                points = self._convex_cavity_points(thickness)
                if points is not None and self._convex_ok(thickness):
                    cavity, method = _hull_mesh(points), "convex"
            if method == "solid":
                bodies = self._eroded_cavity(thickness, segments)
                if bodies:
                    cavity = _stack(bodies)
                    method = "erosion" if self.clean else "level set"
        return cavity, method
