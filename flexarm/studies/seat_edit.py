"""Edit the bearing seats of an existing robot file: give seats by hand, find others again.

What ``import-urdf --seat`` does at import, for a robot file that exists: seats given by
hand (``LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w``, metres, link frame) replace the
region of that name; the links named in ``redetect`` (or every link) lose their found
regions and the finder (:func:`~flexarm.robot.seats.find_seats`) places them again, pairing
each with the seat across its joint, a hand-given one included; a seat still not found
gets a suggestion marked ``review = true``.  Nothing else of the robot changes.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..robot.description import Robot
from ..robot.seat_review import is_review, seat_spec, with_seats
from ..robot.seats import find_seats

__all__ = ["SeatEdit", "edit_seats"]


@dataclass(frozen=True, eq=False)
class SeatEdit:
    """The edited ``robot``, the ``changes`` ((link, region, before, after) with the
    ``cx,…,w`` spec of each side, ``"-"`` where there was none) and the seats still
    ``missing`` (:class:`~flexarm.robot.seat_review.MissingSeat`)."""

    robot: Robot
    changes: tuple = ()
    missing: tuple = ()

    def lines(self) -> list[str]:
        """One line per changed region, then one per region still awaiting review."""
        out = [f"{link}:{name}: {before} -> {after}"
               for link, name, before, after in self.changes]
        if not self.changes:
            out.append("no seat changed")
        out += [m.warning() for m in self.missing]
        return out


def _spec(link, name: str) -> str:
    region = link.regions.get(name)
    if region is None:
        return "-"
    return seat_spec(region) + (" (review)" if is_review(region) else "")


def edit_seats(robot: Robot, seats=(), redetect=()) -> SeatEdit:
    """``robot`` with the seats ``(link, joint, Region)`` given by hand and the regions of
    the links ``redetect`` (names, or ``("all",)``) found again on their CAD.

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> from flexarm.robot.seat_review import parse_seat
    >>> robot = load_robot()
    >>> edit = edit_seats(robot, [parse_seat("frame:joint_2=0.175,-0.18,0,0,1,0,0.06,0.1,0.08")])
    >>> print(edit.lines()[0])
    frame:joint_2: 0.175,-0.18,0,0,1,0,0.06,0.09,0.085 -> 0.175,-0.18,0,0,1,0,0.06,0.1,0.08
    """
    names = robot.link_index
    wanted = tuple(redetect)
    every = "all" in wanted
    for name in wanted:
        if name != "all" and name not in names:
            raise ValueError(f"--redetect {name}: no link '{name}' (links: {', '.join(names)})")
    edited = with_seats(robot, seats) if seats else robot
    given = {(link, joint) for link, joint, _ in seats}
    missing = ()
    if wanted:
        links = tuple(dataclasses.replace(lk, regions={
            n: r for n, r in lk.regions.items() if (lk.name, n) in given})
            if every or lk.name in wanted else lk for lk in edited.links)
        found = find_seats(dataclasses.replace(edited, links=links))
        edited, missing = found.robot, found.missing
    changes = tuple(
        (old.name, n, _spec(old, n), _spec(new, n))
        for old, new in zip(robot.links, edited.links, strict=True)
        for n in dict.fromkeys([*old.regions, *new.regions])
        if _spec(old, n) != _spec(new, n))
    return SeatEdit(edited, changes, missing)
