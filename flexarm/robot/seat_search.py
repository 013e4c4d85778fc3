"""The seat of one (link, joint): which end of the link faces the other, and what seats.

The recipe for link ``L`` and a joint (axis ``a`` through the joint origin ``o`` in
``L``'s frame: the parent sees ``joint.origin`` and ``rpy_matrix(joint.rpy) @ joint.axis``;
the child, whose frame is the joint frame at zero angle, sees the origin and
``joint.axis``), with the other link ``O``'s sample moved into ``L``'s frame at zero
joint angle (:func:`other_sample`):

* **Facing side** (:func:`find_seat`).  The axial ranges of the rings
  (:class:`~flexarm.robot.seat_geometry.Rings`) are each link's extent along the axis;
  the seat is at the end of ``L``'s extent beyond which ``O``'s reaches.  ``O`` inside
  ``L``'s extent (a fork around a hub), or reaching past both of ``L``'s ends about
  equally (the hub in the fork), gives a two-sided seat: both ends, one cylinder.
* **Region** (:func:`find_region`).  The cylinder about the axis holding the seat's points
  (a bore, else the end face of :data:`SEAT_FRACTION` of its radius), padded by the
  margin.  A face seat is shrunk while its cylinder would also take more than
  ``tol.seat_foreign_area`` of other surface inside its rim; every seat must hold
  ``tol.seat_min_sample_points`` points that are not collinear (:func:`check_seat`).
  A two-sided seat that takes other surface falls back to the end nearer the joint
  origin; an end face that is no seat (a sliver of hull along the axis) to a bore
  further in.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.typing import FloatArray
from ..reduction.tolerances import tol as red_tol
from .description import Region, Robot
from .kinematics import rpy_matrix
from .seat_geometry import (
    NODE_AREA,
    EndSeat,
    Polar,
    Rings,
    SeatFinder,
    SeatNotFound,
    coupling_rank,
)
from .seat_sample import SurfaceSample
from .tolerances import tol

__all__ = ["SEAT_FRACTION", "SeatAxis", "check_seat", "find_region", "find_seat",
           "first_joint", "joint_axes", "other_sample", "suggested_region", "suggestion",
           "tcp_axis"]

#: Seat disc radius as a share of the end face's radius (a bearing sits inside the rim).
SEAT_FRACTION = 0.7


@dataclass(frozen=True)
class SeatAxis:
    """A seat to find: link index, region name, axis point and direction (link frame),
    and the link on the other side of the joint."""

    link: int
    name: str
    origin: tuple
    axis: tuple
    other: int


def joint_axes(robot: Robot) -> list[SeatAxis]:
    """Every joint seat: (parent, joint) then (child, joint), in joint order."""
    idx = robot.link_index
    out = []
    for jt in robot.joints:
        a = np.asarray(jt.axis, dtype=float)
        out.append(SeatAxis(idx[jt.parent], jt.name, tuple(map(float, jt.origin)),
                         tuple(map(float, rpy_matrix(jt.rpy) @ a)), idx[jt.child]))
        out.append(SeatAxis(idx[jt.child], jt.name, (0.0, 0.0, 0.0), tuple(map(float, a)),
                         idx[jt.parent]))
    return out


def tcp_axis(robot: Robot) -> SeatAxis | None:
    """The TCP link's flange axis: its proximal joint's axis (link frame)."""
    i = robot.chain.tcp_body
    if i == 0:
        return None
    jt = robot.joints[i - 1]
    return SeatAxis(i, "tcp", (0.0, 0.0, 0.0), tuple(map(float, jt.axis)),
                    robot.link_index[jt.parent])


def first_joint(robot: Robot):
    """The joint on the base link (the first one in joint order), or None."""
    return next((jt for jt in robot.joints if robot.link_index[jt.parent] == 0), None)


def other_sample(robot: Robot, ax: SeatAxis, sample: SurfaceSample) -> tuple:
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


def _end_seat(f: SeatFinder, s: int, o_near, fraction: float = SEAT_FRACTION,
              r_from: float = 0.0, r_cap: float = np.inf) -> EndSeat:
    """The seat at the ``s`` end: a bore reaching the other link (which starts at
    ``o_near``; ``"any"``: any bore), else the end face (``o_near=None``: only a face)."""
    if o_near is not None:
        bore = f.bore_end(s, None if o_near == "any" else o_near)
        if bore is not None:
            return f.bore(s, *bore)
        if o_near == "any":
            raise SeatNotFound("no bore about the axis either")
    return f.face(s, fraction, r_from, r_cap)


def _region_of(ax: SeatAxis, s: int, seats: list[EndSeat], margin: float,
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


def find_region(f: SeatFinder, points: FloatArray, ax: SeatAxis, sides: tuple,
                o_near: dict | None, coupling: str = "rbe2", fraction: float = SEAT_FRACTION,
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
        if not clash and (inside & inner & ~mask).sum() <= tol.seat_foreign_area * mask.sum():
            return reg, mask
        # the disc reached a side wall or another seat: a smaller one
        r_cap = 0.8 * max(x.r_max for x in seats if x.kind == "face")
    raise SeatNotFound("every cylinder about the axis that holds the seat also takes "
                       "other surface of the link")


def check_seat(sample: SurfaceSample, mask: np.ndarray) -> None:
    """Raise ``SeatNotFound`` unless the seat's points ``mask`` could carry 6 DOFs."""
    n = int(mask.sum())
    need = tol.seat_min_sample_points
    if n < need:
        raise SeatNotFound(f"only {n} sample points (< {need}) on the seat")
    if coupling_rank(sample.points[mask]) < 6:
        raise SeatNotFound("the seat's points are collinear (a rotation would be free)")


def find_seat(robot: Robot, ax: SeatAxis, samples: dict, mesh_size: float, grow: bool = True,
              forbidden=None):
    """(region, sample mask, sides) of one joint seat; raises ``SeatNotFound``."""
    sample = samples[ax.link]
    f = SeatFinder.of(sample, ax.origin, ax.axis, mesh_size, grow, forbidden)
    other = samples[ax.other]
    q = Polar.of(*other_sample(robot, ax, other), ax.origin, ax.axis)
    e_l = f.rings.extent()
    e_o = Rings.of(q, other.spacing, f.r_probe).extent()
    if e_l is None:
        raise SeatNotFound("the joint axis does not pass through the link's surface")
    if e_o is None:
        raise SeatNotFound(f"the joint axis does not pass through link "
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
            reg, mask = find_region(f, sample.points, ax, sides, where)
            break
        except SeatNotFound as exc:
            why = why or exc
    else:
        raise why
    check_seat(sample, mask)
    return reg, mask, sides


def suggested_region(ax: SeatAxis, sample: SurfaceSample,
                     mesh_size: float | None = None) -> Region:
    """A region to start from about the surface nearest the joint origin (link frame):
    the 200 sample points nearest it, or with ``mesh_size`` [m] as many as a tet mesh
    of that edge needs to put ``tol.seat_mesh_nodes_factor`` x the rank-6 minimum of
    nodes on them."""
    p = Polar.of(sample.points, sample.normals, ax.origin, ax.axis)
    k = 200
    if mesh_size is not None:
        edge = min(mesh_size, sample.diagonal / 8.0)  # as SeatFinder.n_mesh counts
        need = tol.seat_mesh_nodes_factor * red_tol.min_region_nodes * NODE_AREA * edge**2
        k = max(k, int(np.ceil(need / sample.weight)))
    near = np.argsort(p.r + np.abs(p.t))[:k]
    a = np.asarray(ax.axis, dtype=float)
    # the middle of their axial range, so that the slab holds them all
    c = np.asarray(ax.origin, dtype=float) + a * 0.5 * float(p.t[near].min() + p.t[near].max())
    r = max(float(np.percentile(p.r[near], 90)), 0.05 * sample.diagonal)
    hw = max(0.5 * float(np.ptp(p.t[near])), 0.01 * sample.diagonal)
    return Region(tuple(float(v) for v in c), tuple(float(v) for v in a), 0.0, float(r),
                  float(hw))


def suggestion(ax: SeatAxis, sample: SurfaceSample) -> str:
    """``[links.regions.<joint>]`` values of :func:`suggested_region`."""
    reg = suggested_region(ax, sample)

    def vec(v):
        return "[" + ", ".join(f"{x:.4g}" for x in v) + "]"

    return (f"start from [links.regions.{ax.name}] center = {vec(reg.center)}, axis = "
            f"{vec(reg.axis)}, r_min = 0.0, r_max = {reg.r_max:.3g}, half_width = "
            f"{reg.half_width:.3g} (metres, link frame)")
