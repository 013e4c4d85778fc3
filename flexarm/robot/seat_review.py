"""Seats that need a person: regions suggested for review, and seats given by hand.

A joint seat the finder cannot place (:mod:`flexarm.robot.seats`) still gets a region,
a :class:`ReviewRegion` about the surface nearest the joint origin, so that an import
never silently gives up: the robot file holds it with ``review = true`` and one
:class:`MissingSeat` warning line names the link, the joint and the fix.  The fix is a
seat given by hand, :func:`parse_seat` of ``LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w``
(metres, link frame), which :func:`with_seats` puts into the robot.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .description import Region, Robot

__all__ = ["ReviewRegion", "MissingSeat", "is_review", "parse_seat", "seat_spec",
           "with_seats", "SEAT_FORMAT"]

#: What ``--seat`` takes (metres, link frame; ``w`` is the half width along the axis).
SEAT_FORMAT = "LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w"


@dataclass(frozen=True)
class ReviewRegion(Region):
    """A :class:`~flexarm.robot.description.Region` nobody has confirmed: a suggestion
    where the seat finder failed, written ``review = true`` until a person replaces it
    (``show-regions`` and ``build`` say so).  Selects nodes like any region."""


def is_review(region: Region) -> bool:
    """Whether ``region`` is a suggestion awaiting review.

    >>> r = Region((0, 0, 0), (0, 0, 1), 0.0, 0.1, 0.01)
    >>> is_review(r), is_review(ReviewRegion(*dataclasses.astuple(r)))
    (False, True)
    """
    return isinstance(region, ReviewRegion)


@dataclass(frozen=True)
class MissingSeat:
    """A joint seat the finder could not place on ``link``: ``reason``, and the
    ``region`` suggested instead (a :class:`ReviewRegion`, None when the link has no
    CAD to suggest one on)."""

    link: str
    joint: str
    reason: str
    region: ReviewRegion | None = None

    def warning(self) -> str:
        """One line: the link, the joint, why, what was written and the fix.

        >>> reg = ReviewRegion((0.0, -0.09, 0.0), (0.0, 1.0, 0.0), 0.0, 0.05, 0.01)
        >>> print(MissingSeat("link_2", "joint_2", "no end face", reg).warning())
        ... # doctest: +NORMALIZE_WHITESPACE
        links.link_2: no bearing seat for joint_2 found on the CAD (no end face); a
        suggested region is written with review = true: check it with `flexarm
        show-regions`, then give the seat with --seat
        link_2:joint_2=0,-0.09,0,0,1,0,0,0.05,0.01 (metres, link frame)
        """
        if self.region is None:
            what, values = "no region is written:", SEAT_FORMAT.split("=", 1)[1]
        else:
            what = ("a suggested region is written with review = true: check it with "
                    "`flexarm show-regions`, then")
            values = seat_spec(self.region)
        return (f"links.{self.link}: no bearing seat for {self.joint} found on the CAD "
                f"({self.reason}); {what} give the seat with --seat {self.link}:{self.joint}"
                f"={values} (metres, link frame)")


def seat_spec(region: Region) -> str:
    """``cx,cy,cz,ax,ay,az,r_min,r_max,w`` of ``region`` (metres, 4 significant digits).

    >>> seat_spec(Region((0.15, 0.0, 0.525), (0.0, 1.0, 0.0), 0.0, 0.08, 0.01))
    '0.15,0,0.525,0,1,0,0,0.08,0.01'
    """
    vals = [*region.center, *region.axis, region.r_min, region.r_max, region.half_width]
    return ",".join(f"{v:.4g}" for v in vals)


def parse_seat(text: str, option: str = "--seat") -> tuple[str, str, Region]:
    """``(link, joint, region)`` of ``LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w``.

    The axis is normalised; every error is one line naming ``option`` and the value.

    Examples
    --------
    >>> link, joint, reg = parse_seat("link_2:joint_2=0,-0.1,0,0,2,0,0.02,0.09,0.012")
    >>> link, joint, reg.axis, reg.r_min, reg.half_width
    ('link_2', 'joint_2', (0.0, 1.0, 0.0), 0.02, 0.012)
    >>> parse_seat("link_2=0,0,0")
    Traceback (most recent call last):
    ...
    ValueError: --seat 'link_2=0,0,0': expected LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w
    """
    bad = f"{option} '{text}': expected {SEAT_FORMAT}"
    head, eq, values = text.partition("=")
    link, colon, joint = head.partition(":")
    if not (eq and colon and link.strip() and joint.strip()):
        raise ValueError(bad)
    try:
        v = [float(x) for x in values.split(",")]
    except ValueError:
        raise ValueError(f"{bad} (not a number in '{values}')") from None
    if len(v) != 9:
        raise ValueError(f"{bad} (got {len(v)} numbers, not 9)")
    if not all(math.isfinite(x) for x in v):
        raise ValueError(f"{bad} (every number must be finite)")
    a = np.asarray(v[3:6])
    norm = float(np.linalg.norm(a))
    if not norm > 0:
        raise ValueError(f"{option} '{text}': the axis (ax,ay,az) must not be zero")
    r_min, r_max, w = v[6:]
    if not (0 <= r_min < r_max and w > 0):
        raise ValueError(f"{option} '{text}': need 0 <= r_min < r_max and w > 0 [m], got "
                         f"r_min={r_min:g}, r_max={r_max:g}, w={w:g}")
    axis = tuple(float(x) for x in a / norm)
    return link.strip(), joint.strip(), Region(tuple(v[:3]), axis, r_min, r_max, w)


def with_seats(robot: Robot, seats) -> Robot:
    """``robot`` with the seats ``(link, joint, region)`` given by hand (replacing any
    region of that name); an unknown link or joint is one error naming it."""
    idx = robot.link_index
    regions = {i: dict(lk.regions) for i, lk in enumerate(robot.links)}
    for link, joint, region in seats:
        if link not in idx:
            raise ValueError(f"--seat {link}:{joint}: no link '{link}' (links: "
                             f"{', '.join(idx)})")
        on = [jt.name for jt in robot.joints if link in (jt.parent, jt.child)]
        if joint not in on and joint not in ("tcp", "base"):
            raise ValueError(f"--seat {link}:{joint}: link '{link}' has no joint '{joint}' "
                             f"(its joints: {', '.join(on) or 'none'})")
        regions[idx[link]][joint] = Region(region.center, region.axis, region.r_min,
                                           region.r_max, region.half_width, region.coupling)
    links = tuple(dataclasses.replace(lk, regions=regions[i])
                  for i, lk in enumerate(robot.links))
    return dataclasses.replace(robot, links=links)
