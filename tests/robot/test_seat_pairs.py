"""The two seats of a joint measured against each other on the CAD sample."""

from __future__ import annotations

import dataclasses
import math

import pytest

from flexarm.robot.description import Region
from flexarm.robot.seat_pairs import PAIR_GAP, SeatPair, SeatSide, pair_holds, seat_pairs
from flexarm.robot.seat_review import ReviewRegion

from .test_seat_facing import _turret

TOP = Region((0.0, 0.0, 0.3), (0.0, 0.0, 1.0), 0.0, 0.09, 0.004)  # base: its top face


def _with(robot, base=None, turret=None):
    links = list(robot.links)
    for i, reg in ((0, base), (1, turret)):
        links[i] = dataclasses.replace(links[i], regions={} if reg is None else
                                       {"joint_1": reg})
    return dataclasses.replace(robot, links=tuple(links))


@pytest.fixture(scope="module")
def turret(tmp_path_factory):
    return _turret(tmp_path_factory.mktemp("turret"))


def test_gap_is_child_minus_parent_along_the_axis(turret):
    """The turret's bottom face (its z = -0.02) against the base's top (0.3 = its 0)."""
    bottom = Region((0.0, 0.0, -0.02), (0.0, 0.0, 1.0), 0.0, 0.07, 0.004)
    (p,) = seat_pairs(_with(turret, TOP, bottom))
    assert p.gap == pytest.approx(-0.02, abs=1e-6) and not p.ok
    assert p.status == "gap 20.0 mm > 5 mm along the axis"
    # radius ranges 0..0.09 and 0..0.07 (sample points, just inside): 70 mm in common
    assert p.overlap == pytest.approx(0.07, abs=0.003)
    assert p.parent_points > 1000 and p.child_points > 1000


def test_a_suggestion_is_reported_as_review(turret):
    wall = ReviewRegion((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.095, 0.105, 0.004)
    (p,) = seat_pairs(_with(turret, TOP, wall))
    assert p.ok and p.review and p.status == "review"
    assert abs(p.gap) < 0.1 * PAIR_GAP
    assert p.overlap == pytest.approx(0.09 - 0.1, abs=0.002)  # face inside the ring


def test_a_missing_seat_and_an_empty_one(turret):
    (p,) = seat_pairs(_with(turret, TOP, None))
    assert p.missing == ("turret",) and math.isnan(p.gap) and not p.ok
    assert p.status == "missing on turret"
    far = Region((0.0, 0.0, 5.0), (0.0, 0.0, 1.0), 0.0, 0.07, 0.004)
    (p,) = seat_pairs(_with(turret, TOP, far))
    assert p.child_points == 0 and p.status == "a seat holds no CAD surface"


def test_pair_status_order():
    p = SeatPair("j", "a", "b", 0.001, 0.01, 10, 10)
    assert p.ok and p.status == "ok"
    assert dataclasses.replace(p, gap=-0.0051).status == "gap 5.1 mm > 5 mm along the axis"


def test_a_bore_pair_at_the_limit_holds_within_float32_round_off():
    """The demo arm's base bore and frame seat: a 5 mm design gap that the float32 STL
    coordinates read as 5.0000128 mm holds; 1 um more than the slack does not, and says
    how far the bore's range is from the other seat's."""
    p = SeatPair("j", "a", "b", 0.0553, 0.01, 10, 10, held="bore", reach=0.005000012815)
    assert p.ok and p.status == "ok (bore)"
    far = dataclasses.replace(p, reach=PAIR_GAP + 2e-6)
    assert not far.ok
    assert far.status == ("gap 55.3 mm > 5 mm along the axis (the bore seat's range "
                          "5.0 mm from the other's)")
    parent = SeatSide(10, 0.0, 0.0, 0.05, -0.01, 0.0, "bore")
    child = SeatSide(10, 0.03, 0.0, 0.05, 0.005000012815, 0.04, "face")
    assert pair_holds(parent, child)
    assert not pair_holds(parent, dataclasses.replace(child, t_lo=PAIR_GAP + 2e-6))
