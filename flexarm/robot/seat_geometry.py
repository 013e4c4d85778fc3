"""Rings, end faces and bores of a link's surface about one axis (the seat geometry).

A link's CAD sample (:mod:`flexarm.robot.seat_sample`) is seen about a joint axis as
:class:`Polar` coordinates: axial ``t``, radius ``r``, one of :data:`SECTORS` angular
sectors, and the normal's axial and radial components.  :class:`Rings` bins it along the
axis and by radius: a cell is a *ring* when its points cover ``tol.seat_ring_coverage``
of the sectors (a face pierced by the axis or a bore closes one; a plane that merely
contains the axis covers two sectors).  :class:`SeatFinder` finds the seat at one end of
the link: a **bore** (a ring of surface facing the axis, followed inwards) or the **end
face** (the front-most ring of surface facing along the axis, followed outwards within
the slope ``tol.seat_face_slope``, grown until the tet mesh should put enough nodes on
it).  Which end, and which of the two, :mod:`flexarm.robot.seat_search` decides.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..fe.typing import FloatArray
from ..reduction.interfaces import axis_frame
from ..reduction.tolerances import tol as red_tol
from .seat_sample import SurfaceSample
from .tolerances import tol

__all__ = ["ENVELOPE_MARGIN", "MESH_MARGIN", "NODE_AREA", "R_PROBE", "SECTORS", "EndSeat",
           "Polar", "Rings", "SeatFinder", "SeatNotFound", "coupling_rank", "seat_margin"]

#: Angular sectors about an axis (a ring covers ``tol.seat_ring_coverage`` of them).
SECTORS = 12
#: Rings are looked for within this share of the link's bounding-box diagonal [-].
R_PROBE = 0.4
#: Margin = max(ENVELOPE_MARGIN x fTetWild's envelope (:func:`~flexarm.meshes.tetwild.envelope`)
#: x diagonal, MESH_MARGIN x mesh size).
ENVELOPE_MARGIN = 3.0
MESH_MARGIN = 0.1
#: Surface area of a tet mesh per surface node, in units of h^2 (equilateral triangles).
NODE_AREA = math.sqrt(3.0) / 2.0


class SeatNotFound(Exception):
    """Why no seat was found (becomes the ValueError's reason)."""


@dataclass(frozen=True, eq=False)
class Polar:
    """Sample points about an axis: axial ``t``, radius ``r``, sector, and the normal's
    axial component ``na`` and radial component ``nr`` (< 0: facing the axis)."""

    t: FloatArray
    r: FloatArray
    sector: np.ndarray
    na: FloatArray
    nr: FloatArray

    @staticmethod
    def of(points: FloatArray, normals: FloatArray, origin, axis) -> Polar:
        F = axis_frame(axis)
        d = (np.asarray(points) - np.asarray(origin, dtype=float)) @ F
        n = np.asarray(normals) @ F
        r = np.hypot(d[:, 0], d[:, 1])
        phi = np.arctan2(d[:, 1], d[:, 0])
        sector = np.floor((phi + np.pi) / (2 * np.pi) * SECTORS).astype(np.int64) % SECTORS
        with np.errstate(invalid="ignore", divide="ignore"):
            nr = np.where(r > 0, (n[:, 0] * d[:, 0] + n[:, 1] * d[:, 1]) / r, 0.0)
        return Polar(d[:, 2], r, sector, n[:, 2], nr)


def _sector_share(bins: np.ndarray, sector: np.ndarray, n_bins: int) -> FloatArray:
    """(n_bins,) share of the angular sectors holding a point, per bin."""
    occ = np.zeros((n_bins, SECTORS), dtype=bool)
    occ[bins, sector] = True
    return occ.sum(axis=1) / SECTORS


@dataclass(frozen=True, eq=False)
class Rings:
    """Where (a subset of) a surface closes rings about an axis.

    Axial bins of 2 spacings; radial bins: a disc of 4 spacings, then rings of 3.  A cell
    is a ring when a window of axial bins (3 for the disc, where a face pierced by the axis
    may slope by up to ``tol.seat_face_slope``; 2 elsewhere) covers
    ``tol.seat_ring_coverage`` of the sectors.
    """

    t0: float  # axial position of bin 0 [m]
    b: float  # axial bin [m]
    r_edges: FloatArray  # radial bin edges [m]
    ring: np.ndarray  # (n_axial, n_radial) bool

    @staticmethod
    def of(p: Polar, spacing: float, r_probe: float, mask=None) -> Rings:
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
        start = win.sum(axis=2) >= tol.seat_ring_coverage * SECTORS
        ring = start | np.roll(start, 1, axis=0)  # every bin of a ring window
        ring[:, 0] |= np.roll(start[:, 0], 2, axis=0)
        return Rings(t0, b, r_edges, ring)

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

    def front(self, p: Polar, s: int, near: np.ndarray, rb: int, mask,
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
        j = int(np.argmax(cum.sum(axis=1) >= tol.seat_ring_coverage * SECTORS))
        new = occ[j] & ~cum[j - 1] if j > 0 else occ[j]
        sel = idx[(step == j) & new[p.sector[idx]]]
        front = np.full(SECTORS, -np.inf)
        np.maximum.at(front, p.sector[sel], s * p.t[sel])
        inner = np.full(SECTORS, np.inf)
        np.minimum.at(inner, p.sector[sel], p.r[sel])
        ok = np.isfinite(front)
        return float(np.median(inner[ok])), float(np.median(front[ok]))


@dataclass(frozen=True)
class EndSeat:
    """A seat at one end: its points (a mask on the sample) and its radial range."""

    kind: str  # "face" | "bore"
    mask: np.ndarray
    u_lo: float  # axial range of its points along the facing direction u = s t [m]
    u_hi: float
    r_min: float
    r_max: float


@dataclass(frozen=True, eq=False)
class SeatFinder:
    """The seat search on one link's sample about one axis (its frame)."""

    p: Polar
    rings: Rings
    spacing: float
    margin: float
    mesh_size: float
    weight: float
    r_probe: float
    grow: bool = True  # grow face seats until the mesh should put enough nodes on them
    forbidden: np.ndarray | None = None  # sample points of the link's other regions

    @staticmethod
    def of(sample: SurfaceSample, origin, axis, mesh_size: float, grow: bool = True,
           forbidden=None) -> SeatFinder:
        p = Polar.of(sample.points, sample.normals, origin, axis)
        r_probe = R_PROBE * sample.diagonal
        return SeatFinder(p, Rings.of(p, sample.spacing, r_probe), sample.spacing,
                       seat_margin(sample, mesh_size), mesh_size, sample.weight, r_probe, grow,
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
        inward = self.p.nr <= -tol.seat_facing
        rings = Rings.of(self.p, self.spacing, self.r_probe, inward)
        cells = rings.ring.copy()
        cells[:, 0] = False  # a bore leaves the axis free
        if o_near is not None:
            slack = 2 * rings.b + self.margin
            edge = rings.t0 + rings.b * (np.arange(len(cells)) + (1 if s > 0 else 0))
            cells[s * edge < s * o_near - slack] = False  # ends short of the other link
        end = rings.end_cell(s, cells=cells)
        if end is None:
            return None
        return rings.front(self.p, s, end[0], end[1], inward)

    def bore(self, s: int, r_bore: float, u_end: float) -> EndSeat:
        """The bore wall at ``r_bore`` [m] from its end ``u_end`` inwards."""
        u = s * self.p.t
        band = ((self.p.r >= r_bore - self.margin) & (self.p.r <= r_bore + 2 * self.margin)
                & (self.p.nr <= -tol.seat_facing))
        b = max(2.0 * self.spacing, self.margin)
        m = band & (u <= u_end + b)
        k = np.maximum(np.floor((u_end - u[m]) / b), 0).astype(np.int64)  # end -> inwards
        n = int(k.max()) + 1
        share = _sector_share(k, self.p.sector[m], n)
        good = share >= tol.seat_ring_coverage
        if not good[:2].any():
            raise SeatNotFound(f"the bore of radius {r_bore:.4g} m does not close a ring")
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
        return EndSeat("bore", sel, float(u[sel].min()), float(u[sel].max()),
                     max(r_bore - self.margin, 0.0), r_bore + 2 * self.margin)

    def face(self, s: int, fraction: float, r_from: float, r_cap: float) -> EndSeat:
        """The end face on the ``s`` side from radius ``r_from`` [m]: the disc (annulus)
        of ``fraction`` of its radius, grown until the mesh puts enough nodes on it."""
        facing = s * self.p.na >= tol.seat_facing
        rings = Rings.of(self.p, self.spacing, self.r_probe, facing)
        end = rings.end_cell(s, r_from)
        if end is None:
            raise SeatNotFound("no surface facing the other link closes a ring about "
                               "the axis")
        r_in, u_end = rings.front(self.p, s, end[0], end[1], facing, r_from)
        r0 = r_from if r_from > 0 else (0.0 if end[1] == 0 else r_in)
        u = s * self.p.t
        dr = 3.0 * self.spacing
        band = 3.0 * self.spacing  # CAD only: the same face at every mesh size
        m = facing & (self.p.r >= r0) & (self.p.r <= r_cap) & (
            u >= u_end - band - tol.seat_face_slope * (r_cap - r0))
        if not m.any():
            raise SeatNotFound("no end face outside the other seats")
        rb = np.floor((self.p.r[m] - r0) / dr).astype(np.int64)
        cell = rb * SECTORS + self.p.sector[m]
        n_rb = int(rb.max()) + 1
        front = np.full(n_rb * SECTORS, -np.inf)
        np.maximum.at(front, cell, u[m])
        r_out = r0 + dr * (np.arange(n_rb) + 1)
        slope = tol.seat_face_slope
        flat = front.reshape(n_rb, SECTORS) >= (u_end - band - slope * (r_out - r0))[:, None]
        need = np.full(n_rb, tol.seat_ring_coverage)
        need[0] = 0.5  # the innermost cells hold few points
        bad = np.flatnonzero(flat.mean(axis=1) < need)
        n_ok = int(bad[0]) if bad.size else n_rb
        if n_ok == 0:
            raise SeatNotFound("the end face about the axis is not flat enough to seat on")
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
        min_nodes = tol.seat_mesh_nodes_factor * red_tol.min_region_nodes
        while self.grow and self.n_mesh(sel) < min_nodes and radius < r_grow:
            radius = min(1.25 * radius, r_grow)
            sel = on & (self.p.r <= radius)
        if not sel.any():
            raise SeatNotFound("the end face holds no sample points")
        # a hole's rim is padded like the rest; a limit set by another seat is kept exactly
        r_min = r_from if r_from > 0 else max(r0 - self.margin, 0.0) if r0 > 0 else 0.0
        return EndSeat("face", sel, float(u[sel].min()), float(u[sel].max()), r_min, radius)


def seat_margin(sample: SurfaceSample, mesh_size: float) -> float:
    """Padding [m] of a region around its CAD points (see the module docstring)."""
    from ..meshes.tetwild import envelope

    return max(ENVELOPE_MARGIN * envelope(sample.diagonal, mesh_size) * sample.diagonal,
               MESH_MARGIN * mesh_size)


def coupling_rank(points: FloatArray) -> int:
    """Rigid-body DOFs a coupling on ``points`` carries: 6, 5 (collinear), 3 (one point), 0."""
    if len(points) == 0:
        return 0
    d = points - points.mean(axis=0)
    ev = np.linalg.eigvalsh(d.T @ d)
    if ev[2] <= 0.0:
        return 3
    return 5 if ev[1] <= red_tol.region_collinear * ev[2] else 6
