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
   its points cover ``tol.seat_ring_coverage`` of 12 angular sectors.  A face pierced by
   the axis or a bore closes a ring; a plane that merely contains the axis covers two
   sectors.  The axial range of the rings is a link's *extent* along the axis.
2. **Facing side.**  The end of ``L``'s extent beyond which ``O``'s extent reaches.  ``O``
   inside ``L``'s extent (a fork around a hub), or reaching past both of ``L``'s ends about
   equally (the hub in the fork), gives a two-sided seat: both ends, one cylinder.
3. **At that end** (surface normals from the CAD's outward winding decide what is what):

   * a **bore** -- a ring of surface facing the axis -- whose end reaches ``O``'s extent:
     the seat is the bore wall, followed from that end inwards while the ring stays closed
     and across empty stretches of up to 3 radii (the two walls of a hollow cast hub);
   * otherwise the **end face** -- the front-most ring of surface facing ``O`` (within 60
     degrees of the axis, ``tol.seat_facing``): per (radius, sector) cell the front-most
     such point, kept while the front stays within a slope ``tol.seat_face_slope`` of the
     face's point on the axis (hull faces are faceted); the seat is the disc of
     :data:`SEAT_FRACTION` of that face radius, grown until a tet mesh at the mesh size
     ``h`` should put ``tol.seat_mesh_nodes_factor`` x the rank-6 minimum of nodes on it
     (``area / (0.87 h^2)``).

4. **Region.**  The cylinder about the joint axis holding those points, padded by the
   margin ``max(3 x pytetwild envelope x link diagonal, h / 10)``: the tet mesh's surface
   nodes lie within the envelope of the CAD surface, so the ones on the seat are inside.
   A face seat is shrunk while its cylinder would also take more than
   ``tol.seat_foreign_area`` of other surface inside its rim (the side walls of a thin
   link).  It must hold >= ``tol.seat_min_sample_points`` sample points that are not
   collinear (a rank-6 coupling: the second-moment test of
   :mod:`flexarm.reduction.interfaces`).  Every seat is found at its own size first, then
   grown for the mesh only as far as it stays clear of the link's other regions.  A
   two-sided seat that takes other surface falls back to the end nearer the joint origin;
   an end face that is no seat (a sliver of hull along the axis) to a bore further in.

5. **Pairs.**  The two seats of a joint must face each other: where their surfaces'
   centroids lie more than 5 mm apart along the axis (convex hulls that overlap), one is
   kept and the other link's band of surface at the same station replaces the other
   (:mod:`~flexarm.robot.seat_facing`); a seat found on one link only gets its partner
   the same way.  :mod:`~flexarm.robot.seat_pairs` measures every pair.

Optionally the TCP link gets a ``"tcp"`` region -- its flange face: the end opposite its
proximal seat along that joint's axis, outside any seat that reaches it; coupling
``rbe3`` as in the demo arm, so the tool load spreads without stiffening the flange -- and
the base a ``"base"`` region: its foundation, the flat face at the end of the base
opposite the first joint's seat.  These two are skipped with a warning when not found; a
joint seat that cannot be found raises ``ValueError`` with a region to start from
(:func:`detect_regions`), or gets that region written for review while every other seat
is still found (:func:`find_seats`, :mod:`~flexarm.robot.seat_review`).

The tolerances are in :mod:`flexarm.robot.tolerances`.  The parts live in their own
modules and are re-exported here: the CAD sample in :mod:`~flexarm.robot.seat_sample`,
steps 1 and 3 in :mod:`~flexarm.robot.seat_geometry`, steps 2 and 4 in
:mod:`~flexarm.robot.seat_search`, the report in :mod:`~flexarm.robot.seat_report`.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass

import numpy as np

from ..reduction.tolerances import tol as red_tol
from .description import Link, Region, Robot
from .kinematics import rpy_matrix
from .seat_facing import face_each_other
from .seat_geometry import Polar, Rings, SeatFinder, SeatNotFound, seat_margin
from .seat_report import (
    SeatReport,
    SeatRow,
    region_order,
    region_references,
    seat_report,
    seat_row,
)
from .seat_review import MissingSeat, ReviewRegion
from .seat_sample import SAMPLE_DIVISIONS, SurfaceSample, link_sample, surface_sample
from .seat_search import (
    SEAT_FRACTION,
    check_seat,
    find_region,
    find_seat,
    first_joint,
    joint_axes,
    suggested_region,
    suggestion,
    tcp_axis,
)
from .tolerances import tol

__all__ = ["SurfaceSample", "surface_sample", "link_sample", "SeatRow", "SeatReport",
           "SeatSearch", "detect_regions", "find_seats", "seat_report", "seat_row",
           "region_references", "region_order",
           "SAMPLE_DIVISIONS", "RING_COVERAGE", "FACE_SLOPE", "SEAT_FRACTION",
           "MIN_MESH_NODES", "MIN_SAMPLE_POINTS", "FOREIGN_AREA"]

# The seat tolerances under their former names (read from ``tol``; kept for importers).
RING_COVERAGE = tol.seat_ring_coverage
FACE_SLOPE = tol.seat_face_slope
MIN_MESH_NODES = tol.seat_mesh_nodes_factor * red_tol.min_region_nodes
MIN_SAMPLE_POINTS = tol.seat_min_sample_points
FOREIGN_AREA = tol.seat_foreign_area


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
        :func:`find_seats` writes a suggestion for review instead.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> found = detect_regions(load_robot(), overwrite=True)
    >>> reg = found.links[1].regions["joint_2"]        # the frame's bore for joint 2
    >>> [round(v, 3) for v in reg.center], reg.axis, round(reg.r_min, 3)
    ([0.175, -0.18, 0.0], (0.0, 1.0, 0.0), 0.072)
    """
    return _detect(robot, overwrite, mesh_size, tcp, base, review=False).robot


@dataclass(frozen=True, eq=False)
class SeatSearch:
    """What :func:`find_seats` found: the ``robot`` with its regions, the seats it could
    not find (``missing``: :class:`~flexarm.robot.seat_review.MissingSeat`, each with the
    suggestion written for review) and the (link, joint) seats it moved so that the two
    seats of a joint face each other (``paired``)."""

    robot: Robot
    missing: tuple = ()
    paired: tuple = ()


def find_seats(robot: Robot, overwrite: bool = False, mesh_size: float | None = None, *,
               tcp: bool = True, base: bool = True) -> SeatSearch:
    """As :func:`detect_regions`, but a joint seat not found never drops the others: it
    gets a :class:`~flexarm.robot.seat_review.ReviewRegion` (the surface nearest the
    joint origin) and a :class:`~flexarm.robot.seat_review.MissingSeat` entry.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> res = find_seats(load_robot(), overwrite=True)
    >>> res.missing, sum(len(lk.regions) for lk in res.robot.links)
    ((), 14)
    """
    return _detect(robot, overwrite, mesh_size, tcp, base, review=True)


def _detect(robot: Robot, overwrite: bool, mesh_size, tcp: bool, base: bool,
            review: bool) -> SeatSearch:
    h = robot.options.mesh_size if mesh_size is None else float(mesh_size)
    if not h > 0:
        raise ValueError(f"mesh_size must be > 0 m, got {mesh_size}")
    samples = {i: link_sample(lk) for i, lk in enumerate(robot.links) if lk.mesh is not None}
    regions = {i: ({} if overwrite else dict(lk.regions)) for i, lk in enumerate(robot.links)}
    fixed = {(i, n) for i, regs in regions.items() for n in regs}
    todo = [ax for ax in joint_axes(robot) if ax.link in samples and ax.other in samples
            and ax.name not in regions[ax.link]]
    sides_of, why = _seats_at_own_size(robot, todo, samples, regions, h)
    _grow_for_the_mesh(robot, [ax for ax in todo if (ax.link, ax.name) not in why], samples,
                       regions, h)
    if tcp:  # before the pairs: a band that moves must keep clear of the flange face
        _add_tcp(robot, samples, regions, sides_of, h)
    if base:
        _add_base(robot, samples, regions, sides_of, h)
    two_sided = {key for key, sides in sides_of.items() if len(sides) == 2}
    paired = face_each_other(robot, samples, regions, h, fixed, two_sided)
    missing = []
    for ax in todo:
        if (ax.link, ax.name) not in why or ax.name in regions[ax.link]:
            continue  # found, or found as the band facing the other link's seat
        lk = robot.links[ax.link]
        if not review:
            raise ValueError(f"links.{lk.name}: no bearing seat for {ax.name} found on the CAD "
                             f"({why[(ax.link, ax.name)]}); {suggestion(ax, samples[ax.link])}")
        reg = ReviewRegion(*dataclasses.astuple(suggested_region(ax, samples[ax.link], h)))
        regions[ax.link][ax.name] = reg
        missing.append(MissingSeat(lk.name, ax.name, why[(ax.link, ax.name)], reg))
    for i, sample in samples.items():
        _check_overlaps(robot.links[i], regions[i], sample)
    links = tuple(dataclasses.replace(lk, regions=regions[i]) for i, lk in enumerate(robot.links))
    done = dataclasses.replace(robot, links=links)
    return SeatSearch(done, tuple(missing),
                      tuple((robot.links[i].name, n) for i, n in paired))


def _seats_at_own_size(robot: Robot, todo: list, samples: dict, regions: dict,
                       h: float) -> tuple[dict, dict]:
    """Every seat of ``todo`` at its own size into ``regions``: (link, joint) -> its
    sides, and (link, joint) -> why it was not found."""
    sides_of: dict[tuple, tuple] = {}
    why: dict[tuple, str] = {}
    for ax in todo:
        try:  # one seat not found must not stop the others
            reg, _, sides = find_seat(robot, ax, samples, h, grow=False)
        except SeatNotFound as exc:
            why[(ax.link, ax.name)] = str(exc)
            continue
        regions[ax.link][ax.name] = reg
        sides_of[(ax.link, ax.name)] = sides
    return sides_of, why


def _grow_for_the_mesh(robot: Robot, todo: list, samples: dict, regions: dict,
                       h: float) -> None:
    """The seats of ``todo`` grown for the mesh where that keeps clear of the others."""
    for ax in todo:
        pts = samples[ax.link].points
        others = [r for n, r in regions[ax.link].items() if n != ax.name]
        forbidden = np.logical_or.reduce([r.contains(pts) for r in others] +
                                         [np.zeros(len(pts), dtype=bool)])
        try:
            regions[ax.link][ax.name] = find_seat(robot, ax, samples, h, True, forbidden)[0]
        except SeatNotFound:
            pass  # keep the seat at its own size


def _check_overlaps(link: Link, regions: dict, sample: SurfaceSample) -> None:
    """Raise ``ValueError`` if two of the link's regions share CAD sample points."""
    names = sorted(regions)
    inside = {n: regions[n].contains(sample.points) for n in names}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            shared = int((inside[a] & inside[b]).sum())
            if shared:
                raise ValueError(f"links.{link.name}: regions '{a}' and '{b}' overlap "
                                 f"({shared} shared CAD sample points); set one of them by "
                                 f"hand in [links.regions.{a}]")


def _add_tcp(robot: Robot, samples: dict, regions: dict, sides_of: dict, h: float) -> None:
    """The ``"tcp"`` region (the flange face) into ``regions``, or a warning."""
    ax = tcp_axis(robot)
    if ax is None or ax.link not in samples or "tcp" in regions[ax.link]:
        return
    sample = samples[ax.link]
    f = SeatFinder.of(sample, ax.origin, ax.axis, h)
    prox = sides_of.get((ax.link, robot.joints[ax.link - 1].name))
    if prox is not None and len(prox) == 1:
        s = -prox[0]  # the flange faces away from the proximal seat
    else:
        s = 1 if np.asarray(robot.tool.xyz, dtype=float) @ np.asarray(ax.axis) >= 0 else -1
    try:
        facing = s * f.p.na >= tol.seat_facing
        rings = Rings.of(f.p, f.spacing, f.r_probe, facing)
        end = rings.end_cell(s)
        if end is None:
            raise SeatNotFound("no flange face closes a ring about the axis")
        u_end = rings.front(f.p, s, end[0], end[1], facing)[1]
        # start outside the seats that reach the flange face (a bore through the flange)
        at_face = facing & (np.abs(s * f.p.t - u_end) <= 3 * f.spacing + f.margin)
        r_from = 0.0
        for other in regions[ax.link].values():
            if (other.contains(sample.points) & at_face).any():
                r_from = max(r_from, other.r_max + f.margin)
        reg, mask = find_region(f, sample.points, ax, (s,), None, "rbe3", 1.0, r_from)
        check_seat(sample, mask)
        _clear_of(reg, regions[ax.link], sample)
    except SeatNotFound as exc:
        warnings.warn(f"links.{robot.links[ax.link].name}: no flange face for a 'tcp' region "
                      f"({exc}); the TCP is carried rigidly by the flange seat", stacklevel=4)
        return
    regions[ax.link]["tcp"] = reg


def _add_base(robot: Robot, samples: dict, regions: dict, sides_of: dict, h: float) -> None:
    """The ``"base"`` region (the foundation face) into ``regions``, or a warning."""
    first = first_joint(robot)
    if first is None or 0 not in samples or "base" in regions[0]:
        return
    sample = samples[0]
    a = rpy_matrix(first.rpy) @ np.asarray(first.axis, dtype=float)
    o = np.asarray(first.origin, dtype=float)
    prox = sides_of.get((0, first.name))
    s = -prox[0] if prox is not None and len(prox) == 1 else -1
    p = Polar.of(sample.points, sample.normals, o, a)
    u = s * p.t
    margin = seat_margin(sample, h)
    facing = s * p.na >= tol.seat_facing
    try:
        if not facing.any():
            raise SeatNotFound("no surface faces away from the first joint")
        face = facing & (u >= u[facing].max() - margin - sample.spacing)  # the flat bottom
        check_seat(sample, face)
        r_lo = float(p.r[face].min())
        r_min = 0.0 if r_lo < 4 * sample.spacing else max(r_lo - margin, 0.0)
        c = o + a * s * 0.5 * (float(u[face].min()) + float(u[face].max()))
        reg = Region(tuple(map(float, c)), tuple(map(float, a)), r_min,
                     float(p.r[face].max()) + margin,
                     0.5 * float(np.ptp(u[face])) + margin, "rbe2")
        _clear_of(reg, regions[0], sample)
    except SeatNotFound as exc:
        warnings.warn(f"links.{robot.links[0].name}: no foundation face for a 'base' region "
                      f"({exc}); the base stays rigid", stacklevel=4)
        return
    regions[0]["base"] = reg


def _clear_of(reg: Region, regions: dict, sample: SurfaceSample) -> None:
    """Raise :class:`SeatNotFound` if ``reg`` shares CAD sample points with a joint seat
    (a base plate thinner than the seats' margins): that seat wins."""
    inside = reg.contains(sample.points)
    for name, other in regions.items():
        shared = int((inside & other.contains(sample.points)).sum())
        if shared:
            raise SeatNotFound(f"it would overlap the seat of {name} ({shared} shared CAD "
                               f"sample points)")
