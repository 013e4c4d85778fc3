"""The two seats of each joint measured against each other: do they face each other?

A joint's bearing joins the seat on its parent link to the seat on its child link, so
the two must lie at the same place along the joint axis.  :func:`seat_pairs` measures,
on each link's CAD sample (:func:`~flexarm.robot.seat_sample.link_sample`), the centroid
of the surface each seat holds, in the joint frame at zero angle:

* **gap** -- child centroid minus parent centroid along the joint axis [m]; a pair is
  accepted within :data:`PAIR_GAP`;
* **overlap** -- how far the two seats' radius ranges about the axis overlap [m]
  (negative: one ring lies inside the other with that radial clearance, as the inner
  and outer race of a bearing);
* the CAD sample points each seat holds.

Two kinds of seat span an axial range: a **bore** (a fifth of its surface or more faces
the axis), whose shaft joins the other seat wherever that is along the bore, and a seat
held at **both ends** (the two end faces of a hub, the two cheeks of a fork), with the
other seat in between.  A pair with one of them holds when the two seats' axial ranges
meet within ``PAIR_GAP`` (``reach``), whatever their centroids.

Node counts on the tet mesh are the build's business
(:func:`flexarm.studies.show_regions.show_regions` adds them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..fe.typing import FloatArray
from .description import Region, Robot
from .seat_geometry import Polar
from .seat_review import is_review
from .seat_sample import link_sample
from .seat_search import joint_axes
from .tolerances import tol

__all__ = ["BORE_SHARE", "ENDS_SHARE", "PAIR_GAP", "SeatPair", "SeatSide", "pair_holds",
           "seat_pairs", "seat_side"]

#: Largest distance [m] along the joint axis between the two seats of a joint.
PAIR_GAP = 5e-3
#: What a distance may exceed ``PAIR_GAP`` by and still be within it [m]: STL vertices are
#: float32, so a 5 mm design gap on a 1 m part reads as 5.00001 mm (the demo arm's base
#: bore and frame seat).
_SLACK = 1e-6


def _within(distance: float) -> bool:
    return distance <= PAIR_GAP + _SLACK
#: A seat is a bore when at least this share of its surface faces the axis (the rest:
#: the rims of its end faces, which a bearing seat takes too).
BORE_SHARE = 0.2
#: A seat is held at both ends when its surface lies in two groups along the axis, each
#: with at least this share of it, apart by more than half its axial extent.
ENDS_SHARE = 0.1


@dataclass(frozen=True)
class SeatSide:
    """The CAD surface one seat holds, about its joint axis: ``n`` sample points, their
    centroid ``t`` along the axis from the joint origin, axial range ``t_lo``..``t_hi``
    and radius range ``r_lo``..``r_hi`` [m]; ``kind``: ``"bore"``, ``"ends"`` (held at
    both ends) or ``"face"`` (module docstring)."""

    n: int
    t: float
    r_lo: float
    r_hi: float
    t_lo: float = math.nan
    t_hi: float = math.nan
    kind: str = "face"


def pair_holds(parent: SeatSide, child: SeatSide) -> bool:
    """Whether two seats face each other: centroids within :data:`PAIR_GAP` along the
    axis, or, with a bore or a seat held at both ends, axial ranges that meet within it."""
    if not (parent.n and child.n):
        return False
    if _within(abs(child.t - parent.t)):
        return True
    return _held(parent, child) != "" and _within(_reach(parent, child))


def _held(a: SeatSide, b: SeatSide) -> str:
    """The spanning kind of a pair: ``"bore"``, ``"ends"`` or ``""`` (faces)."""
    kinds = {a.kind, b.kind}
    return "bore" if "bore" in kinds else "ends" if "ends" in kinds else ""


def _reach(a: SeatSide, b: SeatSide) -> float:
    """Axial distance [m] between the ranges of two seats (0 where they overlap)."""
    return max(a.t_lo - b.t_hi, b.t_lo - a.t_hi, 0.0)


@dataclass(frozen=True)
class SeatPair:
    """The two seats of one joint (see the module docstring; lengths in metres).

    ``parent`` and ``child`` are link names; ``review`` says whether either seat is a
    suggestion awaiting review; ``missing`` names the links without a seat for it."""

    joint: str
    parent: str
    child: str
    gap: float
    overlap: float
    parent_points: int
    child_points: int
    review: bool = False
    missing: tuple = ()
    held: str = ""
    reach: float = math.nan

    @property
    def ok(self) -> bool:
        """Both seats hold surface and face each other (:func:`pair_holds`)."""
        if self.missing or not (self.parent_points and self.child_points):
            return False
        return _within(abs(self.gap)) or (self.held != "" and _within(self.reach))

    @property
    def status(self) -> str:
        """``ok``, ``ok (bore)``, ``ok (both ends)``, ``review``, or what is wrong with the
        pair (one phrase)."""
        if self.missing:
            return f"missing on {', '.join(self.missing)}"
        if not (self.parent_points and self.child_points):
            return "a seat holds no CAD surface"
        if not self.ok and self.held:
            return (f"gap {1e3 * abs(self.gap):.1f} mm > {1e3 * PAIR_GAP:g} mm along the axis "
                    f"(the {'bore' if self.held == 'bore' else 'two-ended'} seat's range "
                    f"{1e3 * self.reach:.1f} mm from the other's)")
        if not self.ok:
            return f"gap {1e3 * abs(self.gap):.1f} mm > {1e3 * PAIR_GAP:g} mm along the axis"
        if self.review:
            return "review"
        if _within(abs(self.gap)):
            return "ok"
        return "ok (bore)" if self.held == "bore" else "ok (both ends)"


def seat_side(points: FloatArray, normals: FloatArray, region: Region, origin,
              axis) -> SeatSide:
    """:class:`SeatSide` of ``region`` on the sample ``points`` (n, 3) [m] with outward
    unit ``normals`` (n, 3), about the joint axis through ``origin`` along unit ``axis``
    (the link's frame).

    Examples
    --------
    >>> ring = np.array([[np.cos(a), np.sin(a), 0.2] for a in np.arange(8) * np.pi / 4])
    >>> s = seat_side(ring, -ring * [1, 1, 0], Region((0, 0, 0.2), (0, 0, 1), 0.5, 1.5,
    ...               0.01), (0, 0, 0), (0, 0, 1))
    >>> s.n, round(s.t, 12), round(s.r_lo, 12), round(s.r_hi, 12), s.kind
    (8, 0.2, 1.0, 1.0, 'bore')
    """
    inside = region.contains(points)
    if not inside.any():
        return SeatSide(0, math.nan, math.nan, math.nan)
    p = Polar.of(np.asarray(points)[inside], np.asarray(normals)[inside], origin, axis)
    return SeatSide(int(inside.sum()), float(p.t.mean()), float(p.r.min()), float(p.r.max()),
                    float(p.t.min()), float(p.t.max()), _kind(p))


def _kind(p: Polar) -> str:
    """``"bore"``, ``"ends"`` or ``"face"`` of a seat's surface about its axis."""
    if np.mean(p.nr <= -tol.seat_facing) >= BORE_SHARE:
        return "bore"
    t = np.sort(p.t)
    if len(t) < 2:
        return "face"
    steps = np.diff(t)
    k = int(np.argmax(steps))
    share = min(k + 1, len(t) - k - 1) / len(t)
    two = steps[k] > 0.5 * (t[-1] - t[0]) and share >= ENDS_SHARE
    return "ends" if two else "face"


def seat_pairs(robot: Robot) -> tuple[SeatPair, ...]:
    """One :class:`SeatPair` per joint whose two links have CAD, in joint order.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> pairs = seat_pairs(load_robot())
    >>> p = pairs[1]          # joint 2: the frame's bore beside the lower arm's hub bore
    >>> p.joint, p.status, round(1e3 * p.gap), round(1e3 * p.reach)
    ('joint_2', 'ok (bore)', 160, 0)
    """
    axes = joint_axes(robot)
    out = []
    for j, jt in enumerate(robot.joints):
        ends = (axes[2 * j], axes[2 * j + 1])
        links = [robot.links[ax.link] for ax in ends]
        if any(lk.mesh is None for lk in links):
            continue
        missing = tuple(lk.name for lk in links if jt.name not in lk.regions)
        if missing:
            out.append(SeatPair(jt.name, jt.parent, jt.child, math.nan, math.nan, 0, 0,
                                False, missing))
            continue
        samples = [link_sample(lk) for lk in links]
        p, c = (seat_side(s.points, s.normals, lk.regions[jt.name], ax.origin, ax.axis)
                for s, lk, ax in zip(samples, links, ends, strict=True))
        overlap = min(p.r_hi, c.r_hi) - max(p.r_lo, c.r_lo)
        review = any(is_review(lk.regions[jt.name]) for lk in links)
        out.append(SeatPair(jt.name, jt.parent, jt.child, c.t - p.t, overlap, p.n, c.n,
                            review, (), _held(p, c), _reach(p, c)))
    return tuple(out)
