"""How well a robot's interface regions sit on its CAD: one :class:`SeatRow` per region.

:func:`seat_report` measures every region of every link with a mesh on the link's CAD
sample (:func:`~flexarm.robot.seat_sample.link_sample`): the surface it holds, its radius
range and axial extent, how far its points' centroid lies from the joint axis and origin
it serves (:func:`region_references`), and the rigid-body rank a coupling on them
carries.  It works for hand-made regions as for detected ones
(:func:`~flexarm.robot.seats.detect_regions`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..fe.typing import FloatArray
from .description import Link, Region, Robot
from .kinematics import rpy_matrix
from .seat_geometry import Polar, coupling_rank
from .seat_sample import link_sample
from .seat_search import first_joint, joint_axes, tcp_axis

__all__ = ["SeatReport", "SeatRow", "region_order", "region_references", "seat_report",
           "seat_row"]


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
    for ax in joint_axes(robot):
        out[(robot.links[ax.link].name, ax.name)] = (np.array(ax.origin), np.array(ax.axis))
    tax = tcp_axis(robot)
    if tax is not None:
        out[(robot.links[tax.link].name, "tcp")] = (np.asarray(robot.tool.xyz, dtype=float),
                                                    np.array(tax.axis))
    first = first_joint(robot)
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
    p = Polar.of(inside, np.zeros_like(inside), region.center, region.axis)
    c = inside.mean(axis=0)
    o, a = (np.asarray(v, dtype=float) for v in reference)
    d = c - o
    off_axis = float(np.linalg.norm(d - (d @ a) * a))
    return SeatRow(link_name, name, n, n * weight, float(p.r.min()), float(p.r.max()),
                   float(np.ptp(p.t)), off_axis, float(np.linalg.norm(d)), coupling_rank(inside))


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
