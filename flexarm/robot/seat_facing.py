"""Seat pairs that face each other: closing the gap between a joint's two seats.

Convex collision hulls of neighbouring links overlap where the real parts nest (a
turret on its base, a forearm tube inside the elbow housing), so the end face that the
seat finder takes on each link can lie far apart along the joint axis: the parent's face
inside the child's hull and the other way round.  The bearing sits where the two parts
meet, so when the two seats of a joint lie more than
:data:`~flexarm.robot.seat_pairs.PAIR_GAP` apart (:func:`face_each_other`):

* one seat is kept, and on the other link its **band** at the kept seat's station is
  taken instead (:func:`band_seat`): the link's surface within a half width ``w`` of the
  kept seat's centroid along the axis, a ring about the axis (``r_min > 0`` unless the
  band holds a face through the axis) -- the other race of the bearing, in the same
  plane.  ``w`` grows from the seat margin until the mesh should put
  ``tol.seat_mesh_nodes_factor`` x the rank-6 minimum of nodes on it over two tet edges,
  with the band's centroid within half of ``PAIR_GAP`` of the station (a face of the
  link on one side is balanced by more of its wall on the other: :func:`band_seat`);
* radially a ring keeps to the surface nearest the axis (out to 1.5 x its inner radius)
  where that still surrounds the axis, so that a long arm's side walls are not coupled
  to the bearing (a band through the axis is a face: all of it);
* of the two ways round (keep the parent's seat, or the child's) the one whose two
  seats should both get enough mesh nodes wins, then the one whose band is rounder about
  the axis (its centroid nearer it), then the one whose weaker side should get more
  nodes; a seat given by hand is always the one kept.

A joint with a seat found on one link only gets the band on the other the same way, and
so does a pair that faces but whose weaker seat is too small for the mesh, when the band
holds more.  A pair with a bore is left as designed (the shaft in the bore reaches the
other seat), and so is a hub held at both ends in a fork; a band centred more than 35 %
of its radius off the axis (a lopsided outline) is no seat.
"""

from __future__ import annotations

import numpy as np

from ..reduction.tolerances import tol as red_tol
from .description import Region, Robot
from .seat_geometry import NODE_AREA, SECTORS, SeatFinder, SeatNotFound
from .seat_pairs import PAIR_GAP, pair_holds, seat_side
from .seat_search import SeatAxis, check_seat, joint_axes
from .tolerances import tol

__all__ = ["BAND_RADIUS", "OFF_AXIS", "band_seat", "face_each_other", "off_axis"]

#: A band keeps to radii up to this times its inner radius where that still closes a ring.
BAND_RADIUS = 1.5
#: The band's half width stops growing at this share of the link's bounding-box diagonal.
_MAX_WIDTH = 0.1
#: Mesh nodes a seat should get (as a face seat is grown for).
_MIN_NODES = tol.seat_mesh_nodes_factor * red_tol.min_region_nodes
#: A band whose surface centroid lies further off the axis than this share of its outer
#: radius is lopsided (an arm's outline, not a ring about the joint); hull outlines about
#: a joint reach 0.3.
OFF_AXIS = 0.35


def _coverage(f: SeatFinder, mask: np.ndarray) -> float:
    """Share [-] of the angular sectors about the axis holding a point of ``mask``."""
    occ = np.zeros(SECTORS, dtype=bool)
    occ[f.p.sector[mask]] = True
    return float(occ.mean())


def _band(f: SeatFinder, near: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """The surface ``near`` with ``lo <= t <= hi`` [m] along the axis, kept to the radii
    nearest the axis where those alone surround it."""
    m = near & (f.p.t >= lo) & (f.p.t <= hi)
    if not m.any():
        return m
    r_lo = float(f.p.r[m].min())
    if r_lo < 4.0 * f.spacing:  # a face through the axis: the disc is the seat
        return m
    inner = m & (f.p.r <= max(BAND_RADIUS * r_lo, r_lo + 6.0 * f.spacing))
    return inner if _coverage(f, inner) >= tol.seat_ring_coverage else m


def _region(f: SeatFinder, ax: SeatAxis, lo: float, hi: float, m: np.ndarray) -> Region:
    """The cylinder about the axis holding the band ``m`` between ``lo`` and ``hi`` [m]."""
    a = np.asarray(ax.axis, dtype=float)
    r_lo, r_hi = float(f.p.r[m].min()), float(f.p.r[m].max())
    r_min = 0.0 if r_lo < 4.0 * f.spacing else max(r_lo - f.margin, 0.0)
    c = np.asarray(ax.origin, dtype=float) + a * 0.5 * (lo + hi)
    return Region(tuple(map(float, c)), tuple(map(float, a)), r_min, r_hi + f.margin,
                  0.5 * (hi - lo))


def band_seat(f: SeatFinder, points: np.ndarray, ax: SeatAxis,
              t_star: float) -> tuple[Region, np.ndarray]:
    """The band of the link's surface at ``t_star`` [m] along ``ax`` (module docstring):
    its region and sample mask; raises ``SeatNotFound`` when there is none.

    The band ``t_star - lo .. t_star + hi`` starts at the seat margin each way and grows
    until the mesh should put enough nodes on it and it is two tet edges wide (a wall
    has nodes only in rows an edge apart); where its centroid drifts more than half of
    :data:`~flexarm.robot.seat_pairs.PAIR_GAP` from ``t_star`` (a face on one side),
    only the other side grows, so that a link's end face can be part of the band.
    """
    near = f.p.r <= f.r_probe
    if f.forbidden is not None:
        near &= ~f.forbidden
    edge = min(f.mesh_size, f.r_probe / 3.2)  # as SeatFinder.n_mesh: h, at most diag / 8
    w_max = max(_MAX_WIDTH * f.r_probe / 0.4, 2.0 * edge)
    lo = hi = max(2.0 * f.spacing, f.margin)
    best = None
    for _ in range(60):
        if max(lo, hi) > w_max:
            break
        m = _band(f, near, t_star - lo, t_star + hi)
        if not m.any() or _coverage(f, m) < tol.seat_ring_coverage:
            break
        reg = _region(f, ax, t_star - lo, t_star + hi, m)
        if f.forbidden is not None and (reg.contains(points) & f.forbidden).any():
            break  # it reached another seat of the link
        drift = float(f.p.t[m].mean()) - t_star
        if abs(drift) <= 0.5 * PAIR_GAP:
            best = (reg, m)
            if f.n_mesh(m) >= _MIN_NODES and lo + hi >= 2.0 * edge:
                break
            lo, hi = 1.25 * lo, 1.25 * hi
        elif drift < 0:  # a face below: more of the link above
            hi *= 1.25
        else:
            lo *= 1.25
    if best is None:
        raise SeatNotFound("the link's surface does not surround the axis where the other "
                           "seat is")
    reg, m = best
    if off_axis(points[m], reg.center, reg.axis) > OFF_AXIS * reg.r_max:
        raise SeatNotFound("the band's surface is lopsided about the axis")
    return reg, m


def off_axis(points: np.ndarray, origin, axis) -> float:
    """Distance [m] of the centroid of ``points`` (k, 3) from the axis through ``origin``
    along unit ``axis``."""
    d = np.asarray(points, dtype=float) - np.asarray(origin, dtype=float)
    a = np.asarray(axis, dtype=float)
    return float(np.linalg.norm((d - np.outer(d @ a, a)).mean(axis=0)))


def _forbidden(regions: dict, name: str, points: np.ndarray) -> np.ndarray:
    """Sample points of the link's regions other than ``name``."""
    others = [r.contains(points) for n, r in regions.items() if n != name]
    return np.logical_or.reduce(others + [np.zeros(len(points), dtype=bool)])


def face_each_other(robot: Robot, samples: dict, regions: dict, mesh_size: float,
                    fixed: set, two_sided: set = frozenset()) -> list[tuple[int, str]]:
    """Replace seats in ``regions`` (link index -> {name: Region}) so that each joint's
    two seats face each other (module docstring); returns the (link, joint) replaced.

    ``samples`` maps link index -> CAD sample, ``fixed`` holds the (link, joint) that must
    stay (given by hand), ``two_sided`` the seats that hold both ends of a hub or both
    cheeks of a fork: a joint with two of those (a hub in a fork) is a pair as it is.  A
    joint whose seats cannot be brought together is left as it is:
    :func:`~flexarm.robot.seat_pairs.seat_pairs` reports its gap.
    """
    axes = joint_axes(robot)
    changed = []
    for j, jt in enumerate(robot.joints):
        ends = (axes[2 * j], axes[2 * j + 1])
        if any(ax.link not in samples for ax in ends) or all(
                (ax.link, jt.name) in two_sided for ax in ends):
            continue
        have = [regions[ax.link].get(jt.name) for ax in ends]
        sides = [None if reg is None else seat_side(samples[ax.link].points,
                                                    samples[ax.link].normals, reg, ax.origin,
                                                    ax.axis)
                 for ax, reg in zip(ends, have, strict=True)]
        holds = None not in sides and pair_holds(*sides)
        if None not in sides and any(s.kind == "bore" for s in sides):
            continue  # a bore joins the other seat through its shaft: a design, kept
        nodes = min((_n_mesh(samples[ax.link], reg.contains(samples[ax.link].points),
                             mesh_size) if reg is not None else 0.0)
                    for ax, reg in zip(ends, have, strict=True))
        if holds and nodes >= _MIN_NODES:
            continue
        best = _best_band(ends, jt.name, sides, have, samples, regions, mesh_size, fixed)
        # a pair that faces already is only given up for one the mesh holds better
        if best is not None and (not holds or best[0][2] > nodes):
            regions[best[1]][jt.name] = best[2]
            changed.append((best[1], jt.name))
    return changed


def _n_mesh(sample, mask: np.ndarray, mesh_size: float) -> float:
    """Tet-mesh surface nodes expected on the sample points ``mask`` (as
    :meth:`~flexarm.robot.seat_geometry.SeatFinder.n_mesh` counts them)."""
    edge = min(mesh_size, sample.diagonal / 8.0)
    return float(mask.sum()) * sample.weight / (NODE_AREA * edge**2)


def _best_band(ends, name: str, sides: list, have: list, samples: dict, regions: dict,
               mesh_size: float, fixed: set):
    """(score, link, band region) of the better way round (module docstring), or None."""
    best = None
    for keep in (0, 1):
        ax, kept = ends[1 - keep], ends[keep]
        if sides[keep] is None or not sides[keep].n or (ax.link, name) in fixed:
            continue
        sample = samples[ax.link]
        f = SeatFinder.of(sample, ax.origin, ax.axis, mesh_size, True,
                          _forbidden(regions[ax.link], name, sample.points))
        try:
            reg, mask = band_seat(f, sample.points, ax, sides[keep].t)
            check_seat(sample, mask)
        except SeatNotFound:
            continue
        k_sample = samples[kept.link]
        nodes = min(f.n_mesh(mask),
                    _n_mesh(k_sample, have[keep].contains(k_sample.points), mesh_size))
        # enough nodes on both first, then the rounder band, then more nodes
        lopsided = off_axis(sample.points[mask], reg.center, reg.axis) / reg.r_max
        score = (nodes >= _MIN_NODES, -round(lopsided / 0.05), nodes)
        if best is None or score > best[0]:
            best = (score, ax.link, reg)
    return best
