"""Bearing seats found on the link CAD itself: interface regions for a robot that has none.

A joint couples two links through a bearing; each link's *seat* is the part of its surface
where the other link sits: a bore around the joint axis (a cast hub), an end face pierced
by the axis (a solid hull, as URDF collision meshes are), or both ends of a hub held in a
fork.  :func:`detect_regions` finds one :class:`~flexarm.robot.description.Region` per
(link, joint) on a dense deterministic sample of the CAD surface (:func:`surface_sample`),
so the result does not depend on the tetrahedraliser; :func:`seat_report` measures any
robot's regions on the same sample.

The recipe, per link ``L`` and joint (axis ``a`` through the joint origin ``o`` in ``L``'s
frame: the parent sees ``joint.origin`` and ``rpy_matrix(joint.rpy) @ joint.axis``; the
child, whose frame is the joint frame at zero angle, sees the origin and ``joint.axis``),
with the other link ``O``'s sample moved into ``L``'s frame at zero joint angle:

1. **Rings.**  The sample is binned along the axis and by radius; a cell is a *ring* when
   its points cover :data:`RING_COVERAGE` of 12 angular sectors.  A face pierced by the
   axis or a bore closes a ring; a plane that merely contains the axis covers two sectors.
   The axial range of the rings is a link's *extent* along the axis.
2. **Facing side.**  The end of ``L``'s extent beyond which ``O``'s extent reaches.  ``O``
   inside ``L``'s extent (a fork around a hub), or reaching past both of ``L``'s ends about
   equally (the hub in the fork), gives a two-sided seat: both ends, one cylinder.
3. **At that end** (surface normals from the CAD's outward winding decide what is what):

   * a **bore** -- a ring of surface facing the axis -- whose end reaches ``O``'s extent:
     the seat is the bore wall, followed from that end inwards while the ring stays closed
     and across empty stretches of up to 3 radii (the two walls of a hollow cast hub);
   * otherwise the **end face** -- the front-most ring of surface facing ``O`` (within 60
     degrees of the axis): per (radius, sector) cell the front-most such point, kept while
     the front stays within a slope :data:`FACE_SLOPE` of the face's point on the axis
     (hull faces are faceted); the seat is the disc of :data:`SEAT_FRACTION` of that face
     radius, grown until a tet mesh at the mesh size ``h`` should put
     :data:`MIN_MESH_NODES` nodes on it (``area / (0.87 h^2)``).

4. **Region.**  The cylinder about the joint axis holding those points, padded by the
   margin ``max(3 x pytetwild envelope x link diagonal, h / 10)``: the tet mesh's surface
   nodes lie within the envelope of the CAD surface, so the ones on the seat are inside.
   A face seat is shrunk while its cylinder would also take more than
   :data:`FOREIGN_AREA` of other surface inside its rim (the side walls of a thin link).
   It must hold >= :data:`MIN_SAMPLE_POINTS` sample points that are not collinear (a
   rank-6 coupling: the second-moment test of :mod:`flexarm.reduction.interfaces`).
   Every seat is found at its own size first, then grown for the mesh only as far as it
   stays clear of the link's other regions.  A two-sided seat that takes other surface
   falls back to the end nearer the joint origin; an end face that is no seat (a sliver
   of hull along the axis) to a bore further in.

Optionally the TCP link gets a ``"tcp"`` region -- its flange face: the end opposite its
proximal seat along that joint's axis, outside any seat that reaches it; coupling
``rbe3`` as in the demo arm, so the tool load spreads without stiffening the flange -- and
the base a ``"base"`` region: its foundation, the flat face at the end of the base
opposite the first joint's seat.  These two are skipped with a warning when not found; a
joint seat that cannot be found raises ``ValueError`` with a region to start from.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..fe.typing import FloatArray
from ..meshes.tolerances import tol as mesh_tol
from ..reduction.interfaces import axis_frame
from ..reduction.tolerances import tol as red_tol
from .description import Link, Region, Robot
from .kinematics import rpy_matrix

__all__ = ["SurfaceSample", "surface_sample", "link_sample", "SeatRow", "SeatReport",
           "detect_regions", "seat_report", "seat_row", "region_references", "region_order",
           "SAMPLE_DIVISIONS", "RING_COVERAGE", "FACE_SLOPE", "SEAT_FRACTION",
           "MIN_MESH_NODES", "MIN_SAMPLE_POINTS", "FOREIGN_AREA"]

#: Sample spacing = link bounding-box diagonal / this (~30-80k points on a robot link).
SAMPLE_DIVISIONS = 200
#: Angular sectors about an axis, and the share of them a surface must cover to be a ring.
SECTORS = 12
RING_COVERAGE = 0.75
#: Rings are looked for within this share of the link's bounding-box diagonal [-].
R_PROBE = 0.4
#: A surface point faces a direction when its normal is within 60 degrees of it.
FACING = 0.5
#: An end face is followed outwards while its front stays within this slope (axial drop
#: per radius) of its point on the axis: convex-hull faces are faceted, not flat.
FACE_SLOPE = 0.5
#: Seat disc radius as a share of the end face's radius (a bearing sits inside the rim).
SEAT_FRACTION = 0.7
#: Tet-mesh surface nodes a seat should catch at the mesh size (4 x the rank-6 minimum).
MIN_MESH_NODES = 4 * red_tol.min_region_nodes
#: Sample points a seat must hold (far more than the rank-6 minimum: it is a sample).
MIN_SAMPLE_POINTS = 20
#: Margin = max(ENVELOPE_MARGIN x pytetwild envelope x diagonal, MESH_MARGIN x mesh size).
ENVELOPE_MARGIN = 3.0
MESH_MARGIN = 0.1
#: Surface area of a tet mesh per surface node, in units of h^2 (equilateral triangles).
NODE_AREA = math.sqrt(3.0) / 2.0
#: Other surface a face seat's cylinder may take inside its rim, as a share of its area.
FOREIGN_AREA = 0.15
_R2 = 1.32471795724474602596  # plastic number: the R2 low-discrepancy sequence


class _SeatNotFound(Exception):
    """Why no seat was found (becomes the ValueError's reason)."""


# ------------------------------------------------------------------------------ sample
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
    from ..meshes import load_surface

    surf = load_surface(path, units=units)
    return surface_sample(surf.vertices, surf.faces)


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


# ------------------------------------------------------------------------------ geometry
@dataclass(frozen=True, eq=False)
class _Polar:
    """Sample points about an axis: axial ``t``, radius ``r``, sector, and the normal's
    axial component ``na`` and radial component ``nr`` (< 0: facing the axis)."""

    t: FloatArray
    r: FloatArray
    sector: np.ndarray
    na: FloatArray
    nr: FloatArray

    @staticmethod
    def of(points: FloatArray, normals: FloatArray, origin, axis) -> _Polar:
        F = axis_frame(axis)
        d = (np.asarray(points) - np.asarray(origin, dtype=float)) @ F
        n = np.asarray(normals) @ F
        r = np.hypot(d[:, 0], d[:, 1])
        phi = np.arctan2(d[:, 1], d[:, 0])
        sector = np.floor((phi + np.pi) / (2 * np.pi) * SECTORS).astype(np.int64) % SECTORS
        with np.errstate(invalid="ignore", divide="ignore"):
            nr = np.where(r > 0, (n[:, 0] * d[:, 0] + n[:, 1] * d[:, 1]) / r, 0.0)
        return _Polar(d[:, 2], r, sector, n[:, 2], nr)


def _sector_share(bins: np.ndarray, sector: np.ndarray, n_bins: int) -> FloatArray:
    """(n_bins,) share of the angular sectors holding a point, per bin."""
    occ = np.zeros((n_bins, SECTORS), dtype=bool)
    occ[bins, sector] = True
    return occ.sum(axis=1) / SECTORS


@dataclass(frozen=True, eq=False)
class _Rings:
    """Where (a subset of) a surface closes rings about an axis.

    Axial bins of 2 spacings; radial bins: a disc of 4 spacings, then rings of 3.  A cell
    is a ring when a window of axial bins (3 for the disc, where a face pierced by the axis
    may slope by up to :data:`FACE_SLOPE`; 2 elsewhere) covers :data:`RING_COVERAGE` of
    the sectors.
    """

    t0: float  # axial position of bin 0 [m]
    b: float  # axial bin [m]
    r_edges: FloatArray  # radial bin edges [m]
    ring: np.ndarray  # (n_axial, n_radial) bool

    @staticmethod
    def of(p: _Polar, spacing: float, r_probe: float, mask=None) -> _Rings:
        b = 2.0 * spacing
        r_edges = np.concatenate([[0.0], np.arange(4.0 * spacing, r_probe + 3.0 * spacing,
                                                   3.0 * spacing)])
        m = p.r < r_edges[-1]
        if mask is not None:
            m &= mask
        t0 = float(p.t[m].min()) if m.any() else 0.0
        ub = np.floor((p.t[m] - t0) / b).astype(np.int64)
        rb = np.searchsorted(r_edges, p.r[m], side="right") - 1
        n_u = (int(ub.max()) if m.any() else 0) + 3  # two empty bins at the top: no wrap
        occ = np.zeros((n_u, len(r_edges) - 1, SECTORS), dtype=bool)
        occ[ub, rb, p.sector[m]] = True
        win = occ | np.roll(occ, -1, axis=0)  # the window starting at each bin
        win[:, 0] |= np.roll(occ[:, 0], -2, axis=0)
        start = win.sum(axis=2) >= RING_COVERAGE * SECTORS
        ring = start | np.roll(start, 1, axis=0)  # every bin of a ring window
        ring[:, 0] |= np.roll(start[:, 0], 2, axis=0)
        return _Rings(t0, b, r_edges, ring)

    def extent(self) -> tuple[float, float] | None:
        """Axial range (t_lo, t_hi) [m] of the rings (to a bin), None without rings."""
        ub = np.flatnonzero(self.ring.any(axis=1))
        if not ub.size:
            return None
        return self.t0 + self.b * ub[0], self.t0 + self.b * (ub[-1] + 1)

    def rb_from(self, r_from: float) -> int:
        """First radial bin wholly outside ``r_from`` [m]."""
        return int(np.searchsorted(self.r_edges, r_from - 1e-12))

    def end_cell(self, s: int, r_from: float = 0.0, cells=None):
        """(axial bins, radial bin) of the innermost ring within 2 bins of the ``s`` end
        (``s = +1``: high t) among ``cells`` (default all rings) from ``r_from``; None."""
        k0 = self.rb_from(r_from)
        ring = self.ring if cells is None else cells
        ring = ring[:, k0:]
        ub = np.flatnonzero(ring.any(axis=1))
        if not ub.size:
            return None
        near = ub[ub >= ub[-1] - 2] if s > 0 else ub[ub <= ub[0] + 2]
        return near, k0 + int(np.flatnonzero(ring[near].any(axis=0))[0])

    def front(self, p: _Polar, s: int, near: np.ndarray, rb: int, mask,
              r_from: float = 0.0) -> tuple[float, float]:
        """(radius, front ``u = s t``) [m] of the ring in cell (``near``, ``rb``).

        Its axial bins are scanned from 2 bins outside the end inwards until their sectors
        close the ring; radius and front are medians over the sectors that the last bin
        closed (other surface just outside the end fills the others first).
        """
        m = mask & (p.r >= max(self.r_edges[rb], r_from)) & (p.r < self.r_edges[rb + 1])
        k = np.floor((p.t[m] - self.t0) / self.b).astype(np.int64)
        first = int(near.max()) + 2 if s > 0 else int(near.min()) - 2
        keep = s * k <= s * first
        idx = np.flatnonzero(m)[keep]
        step = s * (first - k[keep])  # 0 = the outermost bin scanned
        occ = np.zeros((int(step.max()) + 1, SECTORS), dtype=bool)
        occ[step, p.sector[idx]] = True
        cum = np.logical_or.accumulate(occ, axis=0)
        j = int(np.argmax(cum.sum(axis=1) >= RING_COVERAGE * SECTORS))
        new = occ[j] & ~cum[j - 1] if j > 0 else occ[j]
        sel = idx[(step == j) & new[p.sector[idx]]]
        front = np.full(SECTORS, -np.inf)
        np.maximum.at(front, p.sector[sel], s * p.t[sel])
        inner = np.full(SECTORS, np.inf)
        np.minimum.at(inner, p.sector[sel], p.r[sel])
        ok = np.isfinite(front)
        return float(np.median(inner[ok])), float(np.median(front[ok]))


@dataclass(frozen=True)
class _Seat:
    """A seat at one end: its points (a mask on the sample) and its radial range."""

    kind: str  # "face" | "bore"
    mask: np.ndarray
    u_lo: float  # axial range of its points along the facing direction u = s t [m]
    u_hi: float
    r_min: float
    r_max: float


@dataclass(frozen=True, eq=False)
class _Finder:
    """The seat search on one link's sample about one axis (its frame)."""

    p: _Polar
    rings: _Rings
    spacing: float
    margin: float
    mesh_size: float
    weight: float
    r_probe: float
    grow: bool = True  # grow face seats until the mesh should put enough nodes on them
    forbidden: np.ndarray | None = None  # sample points of the link's other regions

    @staticmethod
    def of(sample: SurfaceSample, origin, axis, mesh_size: float, grow: bool = True,
           forbidden=None) -> _Finder:
        p = _Polar.of(sample.points, sample.normals, origin, axis)
        r_probe = R_PROBE * sample.diagonal
        return _Finder(p, _Rings.of(p, sample.spacing, r_probe), sample.spacing,
                       _margin(sample, mesh_size), mesh_size, sample.weight, r_probe, grow,
                       forbidden)

    def n_mesh(self, mask) -> float:
        """Expected tet-mesh surface nodes on the sample points ``mask``.

        The edge is ``h`` but at most 1/8 of the link's diagonal: pytetwild keeps the
        surface within 1e-3 of the diagonal, so a small link gets much shorter edges (the
        IRB 4600's 16 cm flange link has 600 nodes at h = 60 mm).
        """
        edge = min(self.mesh_size, self.r_probe / (8 * R_PROBE))
        return float(mask.sum()) * self.weight / (NODE_AREA * edge**2)

    def bore_end(self, s: int, o_near: float | None):
        """(radius, front u) [m] of the bore nearest the ``s`` end whose end reaches the
        other link's extent (which starts at ``t = o_near``; None: any bore), or None."""
        inward = self.p.nr <= -FACING
        rings = _Rings.of(self.p, self.spacing, self.r_probe, inward)
        cells = rings.ring.copy()
        cells[:, 0] = False  # a bore leaves the axis free
        if o_near is not None:
            tol = 2 * rings.b + self.margin
            edge = rings.t0 + rings.b * (np.arange(len(cells)) + (1 if s > 0 else 0))
            cells[s * edge < s * o_near - tol] = False  # ends short of the other link
        end = rings.end_cell(s, cells=cells)
        if end is None:
            return None
        return rings.front(self.p, s, end[0], end[1], inward)

    def bore(self, s: int, r_bore: float, u_end: float) -> _Seat:
        """The bore wall at ``r_bore`` [m] from its end ``u_end`` inwards."""
        u = s * self.p.t
        band = ((self.p.r >= r_bore - self.margin) & (self.p.r <= r_bore + 2 * self.margin)
                & (self.p.nr <= -FACING))
        b = max(2.0 * self.spacing, self.margin)
        m = band & (u <= u_end + b)
        k = np.maximum(np.floor((u_end - u[m]) / b), 0).astype(np.int64)  # end -> inwards
        n = int(k.max()) + 1
        share = _sector_share(k, self.p.sector[m], n)
        good = share >= RING_COVERAGE
        if not good[:2].any():
            raise _SeatNotFound(f"the bore of radius {r_bore:.4g} m does not close a ring")
        # Follow it inwards through empty bins (a cavity it passes, as the two walls of a
        # hollow hub: one bearing seat) for up to 3 radii; stop where other surface
        # crosses its radius without closing the ring.
        edge = np.convolve(good, [1, 1, 1])[1:-1] > 0  # the end of a wall splits a bin
        stop = np.flatnonzero((share > 0) & ~edge)
        end = int(stop[0]) if stop.size else n
        idx = np.flatnonzero(good[:end])
        breaks = np.flatnonzero(np.diff(idx) * b > 3.0 * r_bore)
        last = int(idx[breaks[0]] if breaks.size else idx[-1])
        sel = m.copy()
        sel[m] = (k <= last) & good[k]
        return _Seat("bore", sel, float(u[sel].min()), float(u[sel].max()),
                     max(r_bore - self.margin, 0.0), r_bore + 2 * self.margin)

    def face(self, s: int, fraction: float, r_from: float, r_cap: float) -> _Seat:
        """The end face on the ``s`` side from radius ``r_from`` [m]: the disc (annulus)
        of ``fraction`` of its radius, grown until the mesh puts enough nodes on it."""
        facing = s * self.p.na >= FACING
        rings = _Rings.of(self.p, self.spacing, self.r_probe, facing)
        end = rings.end_cell(s, r_from)
        if end is None:
            raise _SeatNotFound("no surface facing the other link closes a ring about "
                                "the axis")
        r_in, u_end = rings.front(self.p, s, end[0], end[1], facing, r_from)
        r0 = r_from if r_from > 0 else (0.0 if end[1] == 0 else r_in)
        u = s * self.p.t
        dr = 3.0 * self.spacing
        band = 3.0 * self.spacing  # CAD only: the same face at every mesh size
        m = facing & (self.p.r >= r0) & (self.p.r <= r_cap) & (
            u >= u_end - band - FACE_SLOPE * (r_cap - r0))
        if not m.any():
            raise _SeatNotFound("no end face outside the other seats")
        rb = np.floor((self.p.r[m] - r0) / dr).astype(np.int64)
        cell = rb * SECTORS + self.p.sector[m]
        n_rb = int(rb.max()) + 1
        front = np.full(n_rb * SECTORS, -np.inf)
        np.maximum.at(front, cell, u[m])
        r_out = r0 + dr * (np.arange(n_rb) + 1)
        flat = front.reshape(n_rb, SECTORS) >= (u_end - band - FACE_SLOPE * (r_out - r0))[:, None]
        need = np.full(n_rb, RING_COVERAGE)
        need[0] = 0.5  # the innermost cells hold few points
        bad = np.flatnonzero(flat.mean(axis=1) < need)
        n_ok = int(bad[0]) if bad.size else n_rb
        if n_ok == 0:
            raise _SeatNotFound("the end face about the axis is not flat enough to seat on")
        r_face = float(r_out[n_ok - 1])
        on = np.zeros_like(m)
        on[m] = flat.ravel()[cell] & (u[m] >= front[cell] - band) & (rb < n_ok)
        radius = min(max(r0 + fraction * (r_face - r0), r0 + 2 * dr), r_face)
        # grown for the mesh only while the face is whole all round (a disc centred on
        # the axis, not one that follows the face out on one side)
        whole = flat.all(axis=1)
        whole[0] = True
        n_whole = int(np.argmin(whole)) if not whole.all() else n_rb
        r_grow = max(radius, float(r_out[min(n_whole, n_ok) - 1]))
        sel = on & (self.p.r <= radius)
        while self.grow and self.n_mesh(sel) < MIN_MESH_NODES and radius < r_grow:
            radius = min(1.25 * radius, r_grow)
            sel = on & (self.p.r <= radius)
        if not sel.any():
            raise _SeatNotFound("the end face holds no sample points")
        # a hole's rim is padded like the rest; a limit set by another seat is kept exactly
        r_min = r_from if r_from > 0 else max(r0 - self.margin, 0.0) if r0 > 0 else 0.0
        return _Seat("face", sel, float(u[sel].min()), float(u[sel].max()), r_min, radius)


def _margin(sample: SurfaceSample, mesh_size: float) -> float:
    """Padding [m] of a region around its CAD points (see the module docstring)."""
    return max(ENVELOPE_MARGIN * mesh_tol.tet_envelope * sample.diagonal,
               MESH_MARGIN * mesh_size)


def _rank(points: FloatArray) -> int:
    """Rigid-body DOFs a coupling on ``points`` carries: 6, 5 (collinear), 3 (one point), 0."""
    if len(points) == 0:
        return 0
    d = points - points.mean(axis=0)
    ev = np.linalg.eigvalsh(d.T @ d)
    if ev[2] <= 0.0:
        return 3
    return 5 if ev[1] <= red_tol.region_collinear * ev[2] else 6


# ------------------------------------------------------------------------------ the search
@dataclass(frozen=True)
class _Axis:
    """A seat to find: link index, region name, axis point and direction (link frame),
    and the link on the other side of the joint."""

    link: int
    name: str
    origin: tuple
    axis: tuple
    other: int


def _joint_axes(robot: Robot) -> list[_Axis]:
    """Every joint seat: (parent, joint) then (child, joint), in joint order."""
    idx = robot.link_index
    out = []
    for jt in robot.joints:
        a = np.asarray(jt.axis, dtype=float)
        out.append(_Axis(idx[jt.parent], jt.name, tuple(map(float, jt.origin)),
                         tuple(map(float, rpy_matrix(jt.rpy) @ a)), idx[jt.child]))
        out.append(_Axis(idx[jt.child], jt.name, (0.0, 0.0, 0.0), tuple(map(float, a)),
                         idx[jt.parent]))
    return out


def _other_sample(robot: Robot, ax: _Axis, sample: SurfaceSample) -> tuple:
    """The other link's sample points and normals in ``ax.link``'s frame at zero angle."""
    jt = next(j for j in robot.joints if j.name == ax.name)
    R = rpy_matrix(jt.rpy)
    o = np.asarray(jt.origin, dtype=float)
    if robot.link_index[jt.parent] == ax.link:  # child -> parent: p = R q + o
        return sample.points @ R.T + o, sample.normals @ R.T
    return (sample.points - o) @ R, sample.normals @ R  # parent -> child: R^T (p - o)


def _facing(e_l: tuple, e_o: tuple) -> tuple[int, ...]:
    """Sides (+1 / -1 along the axis) of ``L``'s seat from the extents of L and O."""
    plus = max(0.0, e_o[1] - e_l[1])
    minus = max(0.0, e_l[0] - e_o[0])
    tau = 0.1 * max(min(e_l[1] - e_l[0], e_o[1] - e_o[0]), 0.0)
    if plus <= tau and minus <= tau:  # O inside L's extent: a fork around O's hub
        return (1, -1)
    if min(plus, minus) >= 0.5 * max(plus, minus):  # O past both ends: L is the hub
        return (1, -1)
    return (1,) if plus > minus else (-1,)


def _end_seat(f: _Finder, s: int, o_near, fraction: float = SEAT_FRACTION,
              r_from: float = 0.0, r_cap: float = np.inf) -> _Seat:
    """The seat at the ``s`` end: a bore reaching the other link (which starts at
    ``o_near``; ``"any"``: any bore), else the end face (``o_near=None``: only a face)."""
    if o_near is not None:
        bore = f.bore_end(s, None if o_near == "any" else o_near)
        if bore is not None:
            return f.bore(s, *bore)
        if o_near == "any":
            raise _SeatNotFound("no bore about the axis either")
    return f.face(s, fraction, r_from, r_cap)


def _region_of(ax: _Axis, s: int, seats: list[_Seat], margin: float,
               coupling: str) -> tuple[Region, np.ndarray]:
    """The cylinder about the axis holding the seats' points, padded by ``margin``."""
    a = np.asarray(ax.axis, dtype=float)
    # two-sided seats come as (+1, -1): back to t = s u for both
    t = [(x.u_lo, x.u_hi) if k == 0 else (-x.u_hi, -x.u_lo) for k, x in enumerate(seats)]
    t_lo = min(v[0] for v in t) - margin
    t_hi = max(v[1] for v in t) + margin
    c = np.asarray(ax.origin, dtype=float) + a * s * 0.5 * (t_lo + t_hi)
    r_min = min(x.r_min for x in seats)
    r_max = max(max(x.r_max for x in seats), r_min + margin)
    reg = Region(tuple(map(float, c)), tuple(map(float, a)), float(r_min), float(r_max),
                 float(0.5 * (t_hi - t_lo)), coupling)
    mask = np.logical_or.reduce([x.mask for x in seats])
    return reg, mask


def _find(f: _Finder, points: FloatArray, ax: _Axis, sides: tuple, o_near: dict | None,
          coupling: str = "rbe2", fraction: float = SEAT_FRACTION,
          r_from: float = 0.0) -> tuple[Region, np.ndarray]:
    """The region at the ``sides`` ends; a face seat shrinks while it takes other surface."""
    r_cap = f.r_probe
    for _ in range(12):
        seats = [_end_seat(f, s, None if o_near is None else o_near[s], fraction, r_from, r_cap)
                 for s in sides]
        reg, mask = _region_of(ax, sides[0], seats, f.margin, coupling)
        if all(x.kind == "bore" for x in seats):  # a bore ring also takes the rims of its
            if f.forbidden is not None and (reg.contains(points) & f.forbidden).any():
                break                             # end faces, as a bearing seat does
            return reg, mask
        inside = reg.contains(points)
        clash = f.forbidden is not None and (inside & f.forbidden).any()
        # other surface well inside the disc: a side wall (the face's own rim, within the
        # margin of the cylinder's radii, is part of the seat)
        inner = (f.p.r > reg.r_min + f.margin) & (f.p.r < reg.r_max - f.margin)
        if not clash and (inside & inner & ~mask).sum() <= FOREIGN_AREA * mask.sum():
            return reg, mask
        # the disc reached a side wall or another seat: a smaller one
        r_cap = 0.8 * max(x.r_max for x in seats if x.kind == "face")
    raise _SeatNotFound("every cylinder about the axis that holds the seat also takes "
                        "other surface of the link")


def _check_seat(sample: SurfaceSample, mask: np.ndarray) -> None:
    n = int(mask.sum())
    if n < MIN_SAMPLE_POINTS:
        raise _SeatNotFound(f"only {n} sample points (< {MIN_SAMPLE_POINTS}) on the seat")
    if _rank(sample.points[mask]) < 6:
        raise _SeatNotFound("the seat's points are collinear (a rotation would be free)")


def _seat(robot: Robot, ax: _Axis, samples: dict, mesh_size: float, grow: bool = True,
          forbidden=None):
    """(region, sample mask, sides) of one joint seat; raises ``_SeatNotFound``."""
    sample = samples[ax.link]
    f = _Finder.of(sample, ax.origin, ax.axis, mesh_size, grow, forbidden)
    other = samples[ax.other]
    q = _Polar.of(*_other_sample(robot, ax, other), ax.origin, ax.axis)
    e_l = f.rings.extent()
    e_o = _Rings.of(q, other.spacing, f.r_probe).extent()
    if e_l is None:
        raise _SeatNotFound("the joint axis does not pass through the link's surface")
    if e_o is None:
        raise _SeatNotFound(f"the joint axis does not pass through link "
                            f"'{robot.links[ax.other].name}'")
    sides = _facing(e_l, e_o)
    o_near = {1: e_o[0], -1: e_o[1]}  # where the other link starts, seen from either end
    near = (1,) if abs(e_l[1]) <= abs(e_l[0]) else (-1,)  # the end nearer the joint origin
    tries = [(sides, o_near)]
    if len(sides) == 2:  # a two-sided seat that takes other surface: one end alone
        tries.append((near, o_near))
    # an end face that is no seat (a sliver of hull along the axis): a bore further in
    tries.append((sides, {1: "any", -1: "any"}))
    why = None
    for sides, where in tries:
        try:
            reg, mask = _find(f, sample.points, ax, sides, where)
            break
        except _SeatNotFound as exc:
            why = why or exc
    else:
        raise why
    _check_seat(sample, mask)
    return reg, mask, sides


def _suggestion(ax: _Axis, sample: SurfaceSample) -> str:
    """``[links.regions.<joint>]`` values about the surface nearest the joint origin."""
    p = _Polar.of(sample.points, sample.normals, ax.origin, ax.axis)
    near = np.argsort(p.r + np.abs(p.t))[:200]
    a = np.asarray(ax.axis)
    c = np.asarray(ax.origin) + a * float(np.median(p.t[near]))
    r = max(float(np.percentile(p.r[near], 90)), 0.05 * sample.diagonal)
    hw = max(0.5 * float(np.ptp(p.t[near])), 0.01 * sample.diagonal)

    def vec(v):
        return "[" + ", ".join(f"{x:.4g}" for x in v) + "]"

    return (f"start from [links.regions.{ax.name}] center = {vec(c)}, axis = {vec(a)}, "
            f"r_min = 0.0, r_max = {r:.3g}, half_width = {hw:.3g} (metres, link frame)")


def detect_regions(robot: Robot, overwrite: bool = False, mesh_size: float | None = None, *,
                   tcp: bool = True, base: bool = True) -> Robot:
    """The robot with a seat region for every joint on both links it joins, from the CAD.

    See the module docstring for the recipe.  Links without a mesh are skipped.

    Parameters
    ----------
    robot : Robot
    overwrite : bool
        Replace every region (joint seats, ``"tcp"``, ``"base"``); by default only what
        is missing is added and the given regions are kept.
    mesh_size : float, optional
        Tet edge length [m] the regions must work at (default: the robot's
        ``model.mesh_size``): it sets the margin around the CAD surface and how far a
        face seat grows so that the mesh puts enough nodes on it.
    tcp : bool
        Also a ``"tcp"`` region on the TCP link (its flange face, ``rbe3``).
    base : bool
        Also a ``"base"`` region on the base link (its foundation face): the base then
        becomes a flexible body clamped there instead of a rigid one.

    Returns
    -------
    Robot
        A new robot; regions in the link frames [m].

    Raises
    ------
    ValueError
        A joint seat cannot be found (the message names the link and the joint and gives
        ``[links.regions.<joint>]`` values to start from), or two regions of a link overlap.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> found = detect_regions(load_robot(), overwrite=True)
    >>> reg = found.links[1].regions["joint_2"]        # the frame's bore for joint 2
    >>> [round(v, 3) for v in reg.center], reg.axis, round(reg.r_min, 3)
    ([0.175, -0.18, 0.0], (0.0, 1.0, 0.0), 0.072)
    """
    h = robot.options.mesh_size if mesh_size is None else float(mesh_size)
    if not h > 0:
        raise ValueError(f"mesh_size must be > 0 m, got {mesh_size}")
    samples = {i: link_sample(lk) for i, lk in enumerate(robot.links) if lk.mesh is not None}
    regions = {i: ({} if overwrite else dict(lk.regions)) for i, lk in enumerate(robot.links)}
    sides_of: dict[tuple, tuple] = {}
    todo = [ax for ax in _joint_axes(robot) if ax.link in samples and ax.other in samples
            and ax.name not in regions[ax.link]]
    for ax in todo:  # every seat at its own size first, ...
        try:
            reg, _, sides = _seat(robot, ax, samples, h, grow=False)
        except _SeatNotFound as exc:
            lk = robot.links[ax.link]
            raise ValueError(f"links.{lk.name}: no bearing seat for {ax.name} found on the CAD "
                             f"({exc}); {_suggestion(ax, samples[ax.link])}") from None
        regions[ax.link][ax.name] = reg
        sides_of[(ax.link, ax.name)] = sides
    for ax in todo:  # ... then grown for the mesh where that keeps clear of the others
        pts = samples[ax.link].points
        others = [r for n, r in regions[ax.link].items() if n != ax.name]
        forbidden = np.logical_or.reduce([r.contains(pts) for r in others] +
                                         [np.zeros(len(pts), dtype=bool)])
        try:
            regions[ax.link][ax.name] = _seat(robot, ax, samples, h, True, forbidden)[0]
        except _SeatNotFound:
            pass  # keep the seat at its own size
    if tcp:
        _add_tcp(robot, samples, regions, sides_of, h)
    if base:
        _add_base(robot, samples, regions, sides_of, h)
    for i, sample in samples.items():
        _check_overlaps(robot.links[i], regions[i], sample)
    links = tuple(dataclasses.replace(lk, regions=regions[i]) for i, lk in enumerate(robot.links))
    return dataclasses.replace(robot, links=links)


def _check_overlaps(link: Link, regions: dict, sample: SurfaceSample) -> None:
    names = sorted(regions)
    inside = {n: regions[n].contains(sample.points) for n in names}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            shared = int((inside[a] & inside[b]).sum())
            if shared:
                raise ValueError(f"links.{link.name}: regions '{a}' and '{b}' overlap "
                                 f"({shared} shared CAD sample points); set one of them by "
                                 f"hand in [links.regions.{a}]")


def _tcp_axis(robot: Robot) -> _Axis | None:
    """The TCP link's flange axis: its proximal joint's axis (link frame)."""
    i = robot.chain.tcp_body
    if i == 0:
        return None
    jt = robot.joints[i - 1]
    return _Axis(i, "tcp", (0.0, 0.0, 0.0), tuple(map(float, jt.axis)), robot.link_index[jt.parent])


def _add_tcp(robot: Robot, samples: dict, regions: dict, sides_of: dict, h: float) -> None:
    ax = _tcp_axis(robot)
    if ax is None or ax.link not in samples or "tcp" in regions[ax.link]:
        return
    sample = samples[ax.link]
    f = _Finder.of(sample, ax.origin, ax.axis, h)
    prox = sides_of.get((ax.link, robot.joints[ax.link - 1].name))
    if prox is not None and len(prox) == 1:
        s = -prox[0]  # the flange faces away from the proximal seat
    else:
        s = 1 if np.asarray(robot.tool.xyz, dtype=float) @ np.asarray(ax.axis) >= 0 else -1
    try:
        facing = s * f.p.na >= FACING
        rings = _Rings.of(f.p, f.spacing, f.r_probe, facing)
        end = rings.end_cell(s)
        if end is None:
            raise _SeatNotFound("no flange face closes a ring about the axis")
        u_end = rings.front(f.p, s, end[0], end[1], facing)[1]
        # start outside the seats that reach the flange face (a bore through the flange)
        at_face = facing & (np.abs(s * f.p.t - u_end) <= 3 * f.spacing + f.margin)
        r_from = 0.0
        for other in regions[ax.link].values():
            if (other.contains(sample.points) & at_face).any():
                r_from = max(r_from, other.r_max + f.margin)
        reg, mask = _find(f, sample.points, ax, (s,), None, "rbe3", 1.0, r_from)
        _check_seat(sample, mask)
    except _SeatNotFound as exc:
        warnings.warn(f"links.{robot.links[ax.link].name}: no flange face for a 'tcp' region "
                      f"({exc}); the TCP is carried rigidly by the flange seat", stacklevel=3)
        return
    regions[ax.link]["tcp"] = reg


def _add_base(robot: Robot, samples: dict, regions: dict, sides_of: dict, h: float) -> None:
    first = next((jt for jt in robot.joints if robot.link_index[jt.parent] == 0), None)
    if first is None or 0 not in samples or "base" in regions[0]:
        return
    sample = samples[0]
    a = rpy_matrix(first.rpy) @ np.asarray(first.axis, dtype=float)
    o = np.asarray(first.origin, dtype=float)
    prox = sides_of.get((0, first.name))
    s = -prox[0] if prox is not None and len(prox) == 1 else -1
    p = _Polar.of(sample.points, sample.normals, o, a)
    u = s * p.t
    margin = _margin(sample, h)
    facing = s * p.na >= FACING
    try:
        if not facing.any():
            raise _SeatNotFound("no surface faces away from the first joint")
        face = facing & (u >= u[facing].max() - margin - sample.spacing)  # the flat bottom
        _check_seat(sample, face)
        r_lo = float(p.r[face].min())
        r_min = 0.0 if r_lo < 4 * sample.spacing else max(r_lo - margin, 0.0)
        c = o + a * s * 0.5 * (float(u[face].min()) + float(u[face].max()))
        reg = Region(tuple(map(float, c)), tuple(map(float, a)), r_min,
                     float(p.r[face].max()) + margin,
                     0.5 * float(np.ptp(u[face])) + margin, "rbe2")
    except _SeatNotFound as exc:
        warnings.warn(f"links.{robot.links[0].name}: no foundation face for a 'base' region "
                      f"({exc}); the base stays rigid", stacklevel=3)
        return
    regions[0]["base"] = reg


# ------------------------------------------------------------------------------ report
@dataclass(frozen=True)
class SeatRow:
    """One region of one link measured on the CAD sample.

    Attributes
    ----------
    link, region : str
    n_points : int
        Sample points of the CAD surface inside the region.
    area : float
        CAD surface area inside the region [m^2].
    r_lo, r_hi : float
        Radius range of those points about the region's axis [m].
    axial : float
        Their extent along the region's axis [m].
    axis_offset : float
        Distance of their centroid from the reference axis [m] (the joint axis; for
        ``"tcp"`` the flange axis, for ``"base"`` the first joint's axis).
    origin_offset : float
        Distance of their centroid from the reference point [m] (the joint origin; the
        TCP; the base frame origin).
    rank : int
        Rigid-body DOFs a coupling on them carries (6 unless collinear or empty).
    """

    link: str
    region: str
    n_points: int
    area: float
    r_lo: float
    r_hi: float
    axial: float
    axis_offset: float
    origin_offset: float
    rank: int


@dataclass(frozen=True)
class SeatReport:
    """:class:`SeatRow` s of a robot, link by link."""

    robot: str
    rows: tuple

    def text(self) -> str:
        """Table: link, region, sample points, area [cm^2], radius range, axial extent and
        centroid offsets [mm], rank."""
        lines = [f"bearing seats of {self.robot} (on the CAD surface sample)",
                 f"{'link':<14} {'region':<9} {'points':>7} {'area_cm2':>9} "
                 f"{'r_mm':>11} {'axial_mm':>8} {'off_axis_mm':>11} {'off_origin_mm':>13} "
                 f"{'rank':>4}"]
        for r in self.rows:
            lines.append(f"{r.link:<14} {r.region:<9} {r.n_points:>7} {1e4 * r.area:>9.1f} "
                         f"{1e3 * r.r_lo:>5.0f}-{1e3 * r.r_hi:<5.0f} {1e3 * r.axial:>8.1f} "
                         f"{1e3 * r.axis_offset:>11.1f} {1e3 * r.origin_offset:>13.1f} "
                         f"{r.rank:>4}")
        return "\n".join(lines)


def region_references(robot: Robot) -> dict[tuple[str, str], tuple[FloatArray, FloatArray]]:
    """(link, region) -> (reference point [m], unit axis) in the link frame.

    Joint seats: the joint origin and axis as that link sees them; ``"tcp"``: the tool
    point and the TCP link's proximal joint axis; ``"base"``: the base frame origin and the
    first joint's axis.  Other names: the region's own centre and axis.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> ref = region_references(load_robot())
    >>> [float(v) for v in ref[("frame", "joint_2")][0]]
    [0.175, 0.0, 0.0]
    """
    out = {}
    for ax in _joint_axes(robot):
        out[(robot.links[ax.link].name, ax.name)] = (np.array(ax.origin), np.array(ax.axis))
    tax = _tcp_axis(robot)
    if tax is not None:
        out[(robot.links[tax.link].name, "tcp")] = (np.asarray(robot.tool.xyz, dtype=float),
                                                    np.array(tax.axis))
    first = next((jt for jt in robot.joints if robot.link_index[jt.parent] == 0), None)
    if first is not None:
        a = rpy_matrix(first.rpy) @ np.asarray(first.axis, dtype=float)
        out[(robot.links[0].name, "base")] = (np.zeros(3), a)
    for lk in robot.links:
        for name, reg in lk.regions.items():
            out.setdefault((lk.name, name), (np.asarray(reg.center, dtype=float),
                                             np.asarray(reg.axis, dtype=float)))
    return out


def seat_row(link_name: str, name: str, region: Region, points: FloatArray, weight: float,
             reference: tuple) -> SeatRow:
    """:class:`SeatRow` of ``region`` on ``points`` (n, 3) [m], each carrying ``weight``
    [m^2] of surface, against ``reference`` = (point [m], unit axis).

    Examples
    --------
    >>> ring = np.array([[np.cos(a), np.sin(a), 0.0] for a in np.arange(8) * np.pi / 4])
    >>> reg = Region((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.5, 1.5, 0.1)
    >>> row = seat_row("link", "joint_1", reg, ring, 1e-4, ((0, 0, 0), (0, 0, 1)))
    >>> row.n_points, round(row.area, 6), row.r_lo, row.axis_offset < 1e-12, row.rank
    (8, 0.0008, 1.0, True, 6)
    """
    inside = np.asarray(points, dtype=float)[region.contains(points)]
    n = len(inside)
    if n == 0:
        return SeatRow(link_name, name, 0, 0.0, 0.0, 0.0, 0.0, math.nan, math.nan, 0)
    p = _Polar.of(inside, np.zeros_like(inside), region.center, region.axis)
    c = inside.mean(axis=0)
    o, a = (np.asarray(v, dtype=float) for v in reference)
    d = c - o
    off_axis = float(np.linalg.norm(d - (d @ a) * a))
    return SeatRow(link_name, name, n, n * weight, float(p.r.min()), float(p.r.max()),
                   float(np.ptp(p.t)), off_axis, float(np.linalg.norm(d)), _rank(inside))


def seat_report(robot: Robot) -> SeatReport:
    """Every region of every link with a mesh, measured on the CAD sample.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> rep = seat_report(load_robot())
    >>> row = next(r for r in rep.rows if (r.link, r.region) == ("lower_arm", "joint_2"))
    >>> row.rank, round(row.r_lo, 3), round(1e3 * row.axis_offset) < 5   # a 75 mm bore
    (6, 0.075, True)
    """
    refs = region_references(robot)
    rows = []
    for lk in robot.links:
        if lk.mesh is None:
            continue
        sample = link_sample(lk)
        for name in region_order(robot, lk):
            rows.append(seat_row(lk.name, name, lk.regions[name], sample.points, sample.weight,
                                 refs[(lk.name, name)]))
    return SeatReport(robot.name, tuple(rows))


def region_order(robot: Robot, link: Link) -> list[str]:
    """The link's region names: joints in joint order, then ``tcp``, ``base``, others.

    >>> from flexarm.robot import load_robot
    >>> robot = load_robot()
    >>> region_order(robot, robot.links[0])
    ['joint_1', 'base']
    """
    order = {n: k for k, n in enumerate(robot.joint_names + ("tcp", "base"))}
    return sorted(link.regions, key=lambda n: (order.get(n, len(order)), n))
