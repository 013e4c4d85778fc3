"""Hollow a solid CAD hull into a cast shell of uniform wall thickness.

Robot description files (URDF) ship link meshes that are solid hulls -- often exactly
the convex hull -- of what really are hollow castings.  Scaling the density until the
total mass matches the datasheet keeps the hull's full section, so the link stays far
too stiff in bending; cutting the inside away down to a wall of thickness ``t`` gives the
datasheet mass *and* a plausible section.

The shell is the CAD surface plus the reversed surface of a cavity strictly inside it.
The cavity is built in one of two ways:

``"convex"``
    The surface is convex up to CAD faceting noise (:data:`CONVEX_DEPTH_RTOL`,
    :data:`CONVEX_VOLUME_RTOL`): the cavity is the intersection of its hull's face
    half-spaces moved inward by ``t``.  This *is* the inward offset of a convex body,
    exact to rounding, and takes milliseconds (qhull).
``"erosion"``
    Any other closed surface: the morphological erosion ``S - (dS (+) B_t)`` with
    manifold3d.  The swept ball is the union of one prism per face (``t`` either side
    along the face normal: exact walls on every face and at convex edges) and of a
    capsule around every concave edge, the hull of a geodesic polyhedron *inscribed* in
    the ball at both ends.  Only there, where a casting has its fillets, the wall comes
    out slightly thinner than ``t`` (at most 2.2 %, 0.7 % on average with the default
    :data:`BALL_SEGMENTS`), never thicker.  Seconds for a few thousand faces.

Imports only :mod:`flexarm.fe` and :mod:`flexarm.meshes`.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import trimesh
from scipy.optimize import brentq, linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection, QhullError

from ..fe.errors import MeshError
from .repair import check_surface

__all__ = [
    "BALL_SEGMENTS",
    "CONVEX_DEPTH_RTOL",
    "CONVEX_VOLUME_RTOL",
    "HollowShell",
    "bending_ratio",
    "hollow_surface",
    "wall_for_mass",
]

logger = logging.getLogger(__name__)

#: Deepest surface vertex below the convex hull, over the largest extent, for the
#: surface to count as convex (STL exports of convex hulls stay below ~6e-5).
CONVEX_DEPTH_RTOL = 1e-4
#: Hull volume the surface may miss, over the hull volume, to count as convex.
CONVEX_VOLUME_RTOL = 1e-3
#: Segments of the geodesic ball swept along concave edges (erosion only).  Its support
#: falls short of the ball's by at most 2.2 % (mean 0.7 %) at 24, 4.5 % at 16, 1.3 % at 32;
#: the cost grows with its square.
BALL_SEGMENTS = 24
#: A cavity thinner than this times the largest extent counts as none (the part is solid).
_SOLID_RTOL = 1e-6
#: Erosion pieces with |volume| below this times the largest extent cubed are the
#: zero-volume slivers manifold leaves where the swept prisms touch convex edges.
_SLIVER_RTOL = 1e-12
#: Planes of the hull closer than this (normals; offsets over the largest extent) merge.
_PLANE_DIGITS = 12
#: Target size of the temporary (points x planes) arrays [elements].
_CHUNK = 1 << 22


@dataclass(frozen=True, eq=False)
class HollowShell:
    """A CAD solid hollowed to a uniform wall (what :func:`hollow_surface` returns).

    Attributes
    ----------
    mesh : trimesh.Trimesh
        Closed surface of the wall material [m]: the input surface's vertices and faces
        first, unchanged, then the reversed cavity surface.  Watertight, consistently
        wound, positive volume.  If ``is_solid``, the input surface itself.
    thickness : float
        The requested wall thickness [m].
    is_solid : bool
        Nothing is left inside at this thickness (it reaches the largest inscribed
        ball): the part stays solid and ``mesh`` is the input surface.
    cavity : trimesh.Trimesh or None
        Outward-wound surface of the removed inside [m] (several bodies if the inside
        splits up); None if ``is_solid``.
    method : {"convex", "erosion", "solid"}
        How the cavity was built (see the module docstring).
    """

    mesh: trimesh.Trimesh
    thickness: float
    is_solid: bool
    cavity: trimesh.Trimesh | None
    method: str

    @property
    def volume(self) -> float:
        """Volume of the wall material [m^3]."""
        return float(self.mesh.volume)


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


def _unit_ball(segments: int) -> np.ndarray:
    """Vertices (n, 3) of manifold3d's geodesic unit sphere (on the sphere: inscribed)."""
    from manifold3d import Manifold

    mesh = Manifold.sphere(1.0, int(segments)).to_mesh64()
    return np.array(mesh.vert_properties, dtype=np.float64)[:, :3]


def _to_trimesh(solid) -> trimesh.Trimesh:
    mesh = solid.to_mesh64()
    vertices = np.array(mesh.vert_properties, dtype=np.float64)[:, :3]
    return trimesh.Trimesh(vertices, np.array(mesh.tri_verts, dtype=np.int64), process=False)


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
    return mesh


def _winding_number(point: np.ndarray, triangles: np.ndarray) -> float:
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


def _stack(meshes: Sequence[trimesh.Trimesh]) -> trimesh.Trimesh:
    """One mesh of several bodies, each body's vertices and faces as they were."""
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    vertices = np.vstack([m.vertices for m in meshes])
    faces = np.vstack([m.faces + k for m, k in zip(meshes, offsets, strict=True)])
    return trimesh.Trimesh(vertices, faces, process=False)


def _shell_mesh(outer: trimesh.Trimesh, cavity: trimesh.Trimesh) -> trimesh.Trimesh:
    """Outer surface as it is, then the cavity with every face reversed (inward normals)."""
    vertices = np.vstack([outer.vertices, cavity.vertices])
    faces = np.vstack([outer.faces, cavity.faces[:, ::-1] + len(outer.vertices)])
    return trimesh.Trimesh(vertices, faces, process=False)


class _Solid:
    """One closed surface, prepared once to be hollowed at any number of thicknesses."""

    def __init__(self, surface: trimesh.Trimesh, name: str = "surface"):
        check_surface(surface, name)
        self.surface = surface
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
            self.depth <= CONVEX_DEPTH_RTOL * self.size
            and self.hull_volume - self.volume <= CONVEX_VOLUME_RTOL * self.hull_volume
        )
        self._bound = None  # per-face depth bounds, computed when first needed
        self._exact = {}  # face -> exact depth [m], from a linear programme each
        self._capsules = None  # edges that get a swept ball (erosion)
        self._inside = None  # whether the hull's inscribed-ball centre is inside
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
            if self.inradius - thickness < 1e-5 * self.size:
                return None  # a sheet only rounding errors thick: no cavity
            raise
        return points

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
            self._inside = _winding_number(self.center, triangles) > 0.5
        return self._inside

    # --------------------------------------------------------------- general cavity
    def _capsule_edges(self) -> np.ndarray:
        """Vertex pairs (E, 2) of edges that need a swept ball: concave or unsure ones."""
        if self._capsules is None:
            tri = self.vertices[self.faces]
            cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
            twice_area = np.linalg.norm(cross, axis=1)
            longest = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
            # a needle or a point has no trustworthy normal: ball all three of its edges
            degenerate = twice_area <= 1e-8 * longest**2
            normals = cross / np.where(degenerate, 1.0, twice_area)[:, None]
            pairs = self.surface.face_adjacency
            edges = self.surface.face_adjacency_edges
            # height of face 1's far corner above face 0's plane: > 0 concave, 0 flat;
            # flat (coplanar) edges are treated as concave, which only costs a capsule
            far = self.vertices[self.surface.face_adjacency_unshared[:, 1]]
            rise = np.einsum("ij,ij->i", normals[pairs[:, 0]],
                             far - self.vertices[edges[:, 0]])
            concave = (rise > -1e-9 * self.size) | degenerate[pairs].any(axis=1)
            ends = self.faces[degenerate]
            bad_edges = np.concatenate([ends[:, [0, 1]], ends[:, [1, 2]], ends[:, [2, 0]]])
            both = np.sort(np.vstack([edges[concave], bad_edges]), axis=1)
            self._capsules = np.unique(both, axis=0)
        return self._capsules

    def _eroded_cavity(self, thickness: float, segments: int) -> list[trimesh.Trimesh]:
        """Bodies [m] of the points at least ``thickness`` inside (empty list: none)."""
        from manifold3d import Error, Manifold, Mesh64, OpType

        solid = Manifold(Mesh64(vert_properties=np.ascontiguousarray(self.vertices),
                                tri_verts=self.faces.astype(np.uint64)))
        if solid.status() != Error.NoError:
            raise MeshError(f"{self.name}: manifold3d rejects the surface ({solid.status()})")
        tri = self.vertices[self.faces]
        cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        length = np.linalg.norm(cross, axis=1, keepdims=True)
        normals = cross / np.where(length > 0, length, 1.0)
        # one prism per face: every point within `thickness` of the face along its normal
        # (a degenerate face gives a flat, empty hull; its edges carry capsules instead)
        shift = thickness * normals[:, None, :]
        prisms = np.concatenate([tri - shift, tri + shift], axis=1)
        pieces = [Manifold.hull_points(p) for p in prisms]
        ball = thickness * _unit_ball(segments)
        ends = self.vertices[self._capsule_edges()]  # (E, 2, 3)
        capsules = (ends[:, :, None, :] + ball).reshape(len(ends), -1, 3)
        pieces += [Manifold.hull_points(c) for c in capsules]
        cavity = solid - Manifold.batch_boolean(pieces, OpType.Add)
        floor = _SLIVER_RTOL * self.size**3
        return [_to_trimesh(c) for c in cavity.decompose() if c.volume() > floor]

    # ------------------------------------------------------------------------ both
    def _check_thickness(self, thickness: float) -> float:
        thickness = float(thickness)
        if not np.isfinite(thickness) or thickness <= 0:
            raise ValueError(f"wall thickness must be a positive length [m], got {thickness}")
        return thickness

    def _solid_at(self, thickness: float) -> bool:
        return thickness >= self.inradius - _SOLID_RTOL * self.size

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
        return sum(float(c.volume) for c in self._eroded_cavity(thickness, segments))

    def shell(self, thickness: float, segments: int = BALL_SEGMENTS) -> HollowShell:
        thickness = self._check_thickness(thickness)
        cavity, method = None, "solid"
        if not self._solid_at(thickness):
            if self.is_convex:
                points = self._convex_cavity_points(thickness)
                if points is not None and self._convex_ok(thickness):
                    cavity, method = _hull_mesh(points), "convex"
            if method == "solid":
                bodies = self._eroded_cavity(thickness, segments)
                if bodies:
                    cavity, method = _stack(bodies), "erosion"
        if cavity is None:
            logger.info("%s: wall %.4g m leaves nothing inside (inscribed radius <= %.4g m): "
                        "kept solid", self.name, thickness, self.inradius)
            return HollowShell(self.surface, thickness, True, None, "solid")
        mesh = _shell_mesh(self.surface, cavity)
        if not (mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0):
            raise MeshError(f"{self.name}: the hollowed ({method}) surface is not a closed "
                            "shell; mesh it solid or scale the density instead")
        logger.debug("%s: wall %.4g m (%s): %.4g of %.4g m^3 left", self.name, thickness,
                     method, mesh.volume, self.volume)
        return HollowShell(mesh, thickness, False, cavity, method)


def hollow_surface(
    surface: trimesh.Trimesh,
    thickness: float,
    *,
    ball_segments: int = BALL_SEGMENTS,
    name: str = "surface",
) -> HollowShell:
    """Hollow a closed CAD surface to a shell with walls ``thickness`` thick.

    The cavity is the set of points at least ``thickness`` inside the surface: exact, by
    offsetting the hull's planes, for convex surfaces (up to CAD faceting noise); by a
    manifold3d erosion for any other closed surface (see the module docstring).  A
    thickness at or beyond the radius of the largest inscribed ball leaves nothing inside:
    the part is kept solid and the result says so (``is_solid``) instead of raising, so
    that a small link of an arm hollowed at one wall simply stays solid.

    Parameters
    ----------
    surface : trimesh.Trimesh
        Closed, consistently wound surface enclosing a positive volume [m] (e.g. from
        :func:`~flexarm.meshes.load_surface`).  It is not modified.
    thickness : float
        Wall thickness [m], > 0.
    ball_segments : int
        Resolution of the ball swept along concave edges (erosion only).
    name : str
        What to call the part in messages.

    Returns
    -------
    HollowShell
        ``mesh`` (outer surface = the input's vertices and faces, then the reversed
        cavity), ``thickness``, ``is_solid``, ``cavity``, ``method``, ``volume``.

    Raises
    ------
    ValueError
        ``thickness`` is not a positive number.
    MeshError
        The surface is open, non-manifold, inconsistently wound or of no volume, or the
        erosion fails.

    Examples
    --------
    >>> import trimesh
    >>> shell = hollow_surface(trimesh.creation.box((0.4, 0.2, 0.1)), 0.01)
    >>> shell.method, bool(shell.mesh.is_watertight), shell.mesh.body_count
    ('convex', True, 2)
    >>> round(shell.volume * 1e6, 6), round((0.4*0.2*0.1 - 0.38*0.18*0.08) * 1e6, 6)
    (2528.0, 2528.0)
    >>> hollow_surface(trimesh.creation.box((0.4, 0.2, 0.1)), 0.05).is_solid
    True
    """
    return _Solid(surface, name).shell(thickness, ball_segments)


def wall_for_mass(
    surfaces: Sequence[trimesh.Trimesh],
    densities,
    target_mass: float,
    lumped_mass=0.0,
    *,
    ball_segments: int = BALL_SEGMENTS,
    xtol: float = 1e-9,
) -> float:
    """The one wall thickness at which the hollowed parts and the lumped masses weigh
    ``target_mass``.

    Every part gets the same wall; a part whose inscribed ball is thinner than the wall
    stays solid (as in :func:`hollow_surface`).  The total mass grows continuously and
    monotonically with the wall, from the lumped masses (no wall) to the solid parts plus
    the lumped masses; Brent's bracketing method finds the crossing on the exact shell
    volumes (cheap for convex parts: milliseconds per evaluation).

    Parameters
    ----------
    surfaces : sequence of trimesh.Trimesh
        Closed link surfaces [m].
    densities : float or sequence of float
        Density of each part [kg/m^3] (one value for all, or one per surface).
    target_mass : float
        Total mass to match, e.g. the datasheet mass of the arm [kg].
    lumped_mass : float or sequence of float
        Masses not modelled by the surfaces (motors, gearboxes, cables) [kg]; summed.
    ball_segments : int
        See :func:`hollow_surface` (non-convex parts only).
    xtol : float
        Absolute tolerance of the returned thickness [m].

    Returns
    -------
    float
        Wall thickness [m].  If the target is exactly the solid mass, the smallest wall
        that leaves every part solid.

    Raises
    ------
    ValueError
        No surfaces, a non-positive density, the target at or below the lumped masses
        (no wall would be left), or above the solid parts plus the lumped masses (even
        solid hulls are too light: scale the density instead).

    Examples
    --------
    Two boxes hollowed at 12 mm, plus 5 kg of motors, weigh ``target``; recover 12 mm:

    >>> import trimesh
    >>> boxes = [trimesh.creation.box((0.4, 0.2, 0.1)), trimesh.creation.box((0.2, 0.2, 0.2))]
    >>> walls = [0.4 * 0.2 * 0.1 - 0.376 * 0.176 * 0.076, 0.2**3 - 0.176**3]  # [m^3]
    >>> target = 7200.0 * walls[0] + 2700.0 * walls[1] + 5.0
    >>> round(target, 3)
    33.269
    >>> t = wall_for_mass(boxes, [7200.0, 2700.0], target, lumped_mass=5.0)
    >>> round(t * 1e3, 6)  # [mm]
    12.0
    """
    solids = [_Solid(s, f"surface {i}") for i, s in enumerate(surfaces)]
    if not solids:
        raise ValueError("wall_for_mass needs at least one surface")
    try:
        rho = np.broadcast_to(np.asarray(densities, dtype=np.float64), (len(solids),))
    except ValueError:
        raise ValueError(f"need one density or {len(solids)}, got {densities}") from None
    if not (np.isfinite(rho).all() and (rho > 0).all()):
        raise ValueError(f"densities must be positive [kg/m^3], got {rho.tolist()}")
    lumped = float(np.sum(lumped_mass))
    target = float(target_mass)
    solid_mass = float(rho @ [s.volume for s in solids])
    if target <= lumped:
        raise ValueError(
            f"target mass {target:g} kg is not above the lumped masses ({lumped:g} kg): "
            "no wall thickness can give it"
        )
    if target > (lumped + solid_mass) * (1 + 1e-12):
        raise ValueError(
            f"target mass {target:g} kg is above the solid parts plus lumped masses "
            f"({solid_mass:g} + {lumped:g} kg): even solid hulls are too light; "
            "scale the density instead"
        )

    def excess(t: float) -> float:
        shells = [s.volume - s.cavity_volume(t, ball_segments) if t > 0 else 0.0
                  for s in solids]
        return lumped + float(rho @ shells) - target

    # at the largest inscribed radius every part is solid (mass = solid + lumped)
    t_max = max(s.inradius for s in solids)
    if target >= (lumped + solid_mass) * (1 - 1e-12):
        return t_max
    thickness = brentq(excess, 0.0, t_max, xtol=xtol)
    logger.info("wall %.4g m gives %.6g kg", thickness, target)
    return float(thickness)


def _spread(mesh: trimesh.Trimesh) -> np.ndarray:
    """Second moments of volume (3, 3) [m^5], int (x - c)(x - c)^T dV about the centroid c."""
    inertia = trimesh.triangles.mass_properties(mesh.triangles, density=1.0).inertia
    # inertia = tr(C) I - C  =>  tr(inertia) = 2 tr(C)
    return 0.5 * np.trace(inertia) * np.eye(3) - inertia


def bending_ratio(solid: trimesh.Trimesh, shell) -> np.ndarray:
    """Crude bending-stiffness proxy: shell over solid second moments of volume.

    For each principal axis e_k of the solid (largest spread first) the ratio

        r_k = int_shell (e_k . (x - c_shell))^2 dV  /  int_solid (e_k . (x - c_solid))^2 dV,

    i.e. the diagonal of the covariance ("second moment of volume") of each body about
    its own centroid, in the solid's principal frame.  It is *not* the inertia tensor (whose
    diagonal mixes two directions) and not a mass-normalised quantity.

    What it is: for a prismatic member along e_0 with a uniform wall, ``r_1`` and ``r_2``
    are the ratios of the second moments of area of the cross-section, i.e. of the
    bending stiffness EI for deflection along e_1 and e_2 with the same E, up to the end
    walls' O(t / length) share.  ``r_0`` measures spread along the member, not bending.
    What it is not: a finite-element stiffness.  It ignores shear (which matters for
    short, thin-walled links), torsion (the closed thin-walled section's Bredt constant
    differs), local wall bending and ovalisation, hubs, ribs and end conditions; for a
    blocky part (base, wrist) even the beam picture is weak.  The mass changes by
    ``shell.volume / solid.volume``, for thin walls smaller than ``r_1`` and ``r_2``:
    hollowing lowers the stiffness less than the mass.

    Parameters
    ----------
    solid : trimesh.Trimesh
        The closed solid surface [m].
    shell : HollowShell or trimesh.Trimesh
        The hollowed part (its ``mesh``) or any closed surface [m].

    Returns
    -------
    numpy.ndarray
        (3,) ratios, dimensionless, in the order of the solid's principal axes by
        decreasing spread (1 for a solid ``shell``).

    Examples
    --------
    A bar 1 m long and 0.1 m square hollowed to 5 mm walls: a tube whose section keeps
    1 - 0.9^4 of its second moment of area, plus 2 t / length of the inner section's in
    the end walls, 1 - 0.99 * 0.9^4:

    >>> import trimesh
    >>> bar = trimesh.creation.box((1.0, 0.1, 0.1))
    >>> r = bending_ratio(bar, hollow_surface(bar, 0.005))
    >>> [round(float(x), 4) for x in r], round(1 - 0.99 * 0.9**4, 4)
    ([0.2141, 0.3505, 0.3505], 0.3505)
    """
    mesh = shell.mesh if isinstance(shell, HollowShell) else shell
    c_solid = _spread(solid)
    spread, axes = np.linalg.eigh(c_solid)
    order = np.argsort(spread)[::-1]
    spread, axes = spread[order], axes[:, order]
    return np.einsum("ik,ij,jk->k", axes, _spread(mesh), axes) / spread
