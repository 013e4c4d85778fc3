"""Interface regions: which FE nodes of a link carry a joint.

A region is a cylinder in the link frame (a bearing seat: centre, axis, radius range,
half-width) or a named node set of the mesh.  :func:`interfaces` selects the nodes of
every region and checks them all *before* anything is factorised, so a bad region
fails in milliseconds with a message that names it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.errors import InterfaceError
from ..fe.mesh import TetMesh
from ..fe.tolerances import tol as fe_tol
from ..fe.typing import ArrayLike, FloatArray, IntArray
from .tolerances import tol

__all__ = [
    "CylinderRegion",
    "NodeSetRegion",
    "Interface",
    "select_region",
    "interfaces",
    "parse_cylinder",
    "axis_frame",
]


def axis_frame(axis: ArrayLike) -> FloatArray:
    """(3, 3) right-handed frame whose third column is the unit ``axis``.

    Columns are the frame's x, y, z axes in link coordinates.  The x axis is the
    link axis least aligned with ``axis`` projected off it, so the frame is
    deterministic.

    >>> axis_frame([0, 0, 2.0]).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    z = np.asarray(axis, dtype=float)
    norm = np.linalg.norm(z)
    if not norm > 0:
        raise ValueError(f"axis must be a non-zero (3,) vector, got {axis}")
    z = z / norm
    e = np.eye(3)[int(np.argmin(np.abs(z)))]
    x = e - (e @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


@dataclass(frozen=True)
class CylinderRegion:
    """Nodes inside a hollow cylinder (link frame, metres).

    Parameters
    ----------
    name : str
    center : (3,) float
        Centre of the cylinder [m]; also the interface node's position.
    axis : (3,) float
        Cylinder axis (any length).
    r_min, r_max : float
        Radial range [m] measured from the axis (``r_min = 0``: a full disc).
    half_width : float
        Half the axial extent [m].

    Examples
    --------
    >>> CylinderRegion("hub", (0, 0, 0), (1, 0, 0), 0.0, 0.1, 0.01).frame[:, 2].tolist()
    [1.0, 0.0, 0.0]
    """

    name: str
    center: tuple
    axis: tuple
    r_min: float
    r_max: float
    half_width: float

    def __post_init__(self) -> None:
        c = np.asarray(self.center, dtype=float)
        a = np.asarray(self.axis, dtype=float)
        if c.shape != (3,) or a.shape != (3,):
            raise ValueError(f"region '{self.name}': center and axis must be (3,), "
                             f"got {c.shape} and {a.shape}")
        if not np.linalg.norm(a) > 0:
            raise InterfaceError(f"region '{self.name}': the axis is the zero vector")
        if not (0.0 <= self.r_min < self.r_max) or not self.half_width > 0:
            raise InterfaceError(
                f"region '{self.name}': need 0 <= r_min < r_max and half_width > 0 [m], got "
                f"r_min={self.r_min}, r_max={self.r_max}, half_width={self.half_width}"
            )
        object.__setattr__(self, "center", tuple(float(v) for v in c))
        object.__setattr__(self, "axis", tuple(float(v) for v in a / np.linalg.norm(a)))

    @property
    def reference_point(self) -> FloatArray:
        """(3,) interface node position [m]: the cylinder centre."""
        return np.array(self.center)

    @property
    def frame(self) -> FloatArray:
        """(3, 3) interface frame, z along the axis (columns in link coordinates)."""
        return axis_frame(self.axis)

    def contains(self, points: FloatArray) -> np.ndarray:
        """(n,) bool: which of ``points`` (n, 3) [m] lie inside (boundary included)."""
        d = np.asarray(points, dtype=float) - self.reference_point
        a = np.asarray(self.axis)
        h = d @ a
        r = np.linalg.norm(d - h[:, None] * a, axis=1)
        eps = fe_tol.point_merge
        return (np.abs(h) <= self.half_width + eps) & (r >= self.r_min - eps) & (
            r <= self.r_max + eps
        )


@dataclass(frozen=True)
class NodeSetRegion:
    """The nodes of a named node set of the mesh.

    Parameters
    ----------
    name : str
        Interface name.
    node_set : str
        Key in ``mesh.node_sets`` (defaults to ``name``).
    reference_point : (3,) float, optional
        Interface node position [m]; default: centroid of the set's nodes.
    """

    name: str
    node_set: str = ""
    reference_point: tuple | None = None

    def __post_init__(self) -> None:
        if not self.node_set:
            object.__setattr__(self, "node_set", self.name)

    @property
    def frame(self) -> FloatArray:
        return np.eye(3)


Region = CylinderRegion | NodeSetRegion


@dataclass(frozen=True, eq=False)
class Interface:
    """A checked interface: region nodes plus the interface node's position and frame.

    Attributes
    ----------
    name : str
    nodes : (k,) int
        Sorted FE node indices of the region.
    position : (3,) float
        Interface node position [m], link frame.
    frame : (3, 3) float
        Interface frame (columns = axes in link coordinates).
    """

    name: str
    nodes: IntArray
    position: FloatArray
    frame: FloatArray


def parse_cylinder(text: str) -> CylinderRegion:
    """Parse ``NAME:cx,cy,cz,ax,ay,az,r,w`` or ``NAME:cx,cy,cz,ax,ay,az,r_min,r_max,w``.

    ``r`` is the outer radius (``r_min = 0``), ``w`` the half-width, all in metres.

    >>> parse_cylinder("hub:0,0,0,0,0,1,0.05,0.01").r_max
    0.05
    """
    name, sep, rest = text.partition(":")
    try:
        vals = [float(v) for v in rest.split(",")] if sep else []
    except ValueError:
        vals = []
    if not name.strip() or len(vals) not in (8, 9):
        raise ValueError(
            f"interface must be NAME:cx,cy,cz,ax,ay,az,r,w or "
            f"NAME:cx,cy,cz,ax,ay,az,r_min,r_max,w [m], got '{text}'"
        )
    r_min, r_max = (0.0, vals[6]) if len(vals) == 8 else (vals[6], vals[7])
    return CylinderRegion(name.strip(), vals[0:3], vals[3:6], r_min, r_max, vals[-1])


def select_region(mesh: TetMesh, region: Region, surface_only: bool = True) -> IntArray:
    """(k,) sorted node indices of ``region`` (possibly empty for a cylinder).

    Parameters
    ----------
    mesh : TetMesh
    region : CylinderRegion or NodeSetRegion
    surface_only : bool
        Cylinders keep only nodes of the outer skin (a seat on a hollow link takes none
        from the wall of its cavity); a node set with interior nodes raises
        :class:`InterfaceError`.

    Examples
    --------
    >>> m = TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1))
    >>> select_region(m, CylinderRegion("a", (0, .05, .05), (1, 0, 0), 0, 1, 1e-3)).size
    4
    """
    if isinstance(region, CylinderRegion):
        cand = mesh.boundary_nodes(outer=True) if surface_only else np.arange(mesh.n_nodes)
        return cand[region.contains(mesh.points[cand])]
    if region.node_set not in mesh.node_sets:
        known = ", ".join(sorted(mesh.node_sets)) or "none"
        raise InterfaceError(
            f"region '{region.name}': the mesh has no node set '{region.node_set}' "
            f"(known: {known})"
        )
    nodes = np.unique(mesh.node_sets[region.node_set])
    if surface_only and nodes.size:
        inner = np.setdiff1d(nodes, mesh.boundary_nodes())
        if inner.size:
            raise InterfaceError(
                f"region '{region.name}': {inner.size} of {nodes.size} nodes are not on the "
                f"surface (first: node {int(inner[0])}); pass surface_only=False to allow them"
            )
    return nodes


def check_spread(name: str, points: FloatArray, what: str = "nodes") -> None:
    """Raise :class:`InterfaceError` unless ``points`` (k, 3) can carry 6 rigid DOFs."""
    k = len(points)
    if k < tol.min_region_nodes:
        raise InterfaceError(
            f"region '{name}': {k} {what}, need at least {tol.min_region_nodes} "
            "non-collinear ones to carry 6 DOFs"
        )
    d = points - points.mean(axis=0)
    ev = np.linalg.eigvalsh(d.T @ d)
    # Two vanishing principal moments = all points on one line (rotation about it is free).
    if ev[1] <= tol.region_collinear * max(ev[2], np.finfo(float).tiny):
        raise InterfaceError(
            f"region '{name}': its {k} {what} are collinear; a rotation about their line "
            "would be unconstrained (widen the region)"
        )


def interfaces(mesh: TetMesh, regions, surface_only: bool = True) -> tuple[Interface, ...]:
    """Select and check every region; raise :class:`InterfaceError` naming the bad one.

    Checks, in order: duplicate names, empty regions, too few or collinear nodes,
    nodes shared by two regions (and, for node sets, interior nodes).

    Examples
    --------
    >>> m = TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1))
    >>> a = CylinderRegion("a", (0, .05, .05), (1, 0, 0), 0, 1, 1e-3)
    >>> b = CylinderRegion("b", (1, .05, .05), (1, 0, 0), 0, 1, 1e-3)
    >>> [i.nodes.size for i in interfaces(m, [a, b])]
    [4, 4]
    """
    regions = list(regions)
    if not regions:
        raise InterfaceError("at least one interface region is needed")
    names = [r.name for r in regions]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise InterfaceError(f"interface names must be unique, '{dup[0]}' is repeated")
    out = []
    owner = np.full(mesh.n_nodes, -1, dtype=np.int64)
    for i, region in enumerate(regions):
        nodes = select_region(mesh, region, surface_only)
        if nodes.size == 0:
            where = "surface nodes" if surface_only else "nodes"
            raise InterfaceError(f"region '{region.name}' is empty: no {where} inside it")
        check_spread(region.name, mesh.points[nodes])
        shared = nodes[owner[nodes] >= 0]
        if shared.size:
            other = regions[int(owner[shared[0]])].name
            raise InterfaceError(
                f"region '{region.name}' overlaps region '{other}': {shared.size} shared "
                f"nodes (first: node {int(shared[0])})"
            )
        owner[nodes] = i
        if isinstance(region, CylinderRegion):
            pos = region.reference_point
        elif region.reference_point is not None:
            pos = np.asarray(region.reference_point, dtype=float)
        else:
            pos = mesh.points[nodes].mean(axis=0)
        nodes.setflags(write=False)
        out.append(Interface(region.name, nodes, pos, region.frame))
    return tuple(out)
