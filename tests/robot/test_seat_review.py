"""Seats given by hand (``--seat``) and suggestions written for review."""

from __future__ import annotations

import math

import pytest

from flexarm.robot.description import Region
from flexarm.robot.seat_review import (
    MissingSeat,
    ReviewRegion,
    is_review,
    parse_seat,
    seat_spec,
    with_seats,
)

from ..primitive_arm import primitive_arm_robot


def test_parse_seat_normalises_the_axis():
    link, joint, reg = parse_seat(" arm : joint_2 =0.1,0,0.2, 3,0,4, 0.01,0.05,0.002")
    assert (link, joint) == ("arm", "joint_2")
    assert reg.center == (0.1, 0.0, 0.2) and reg.axis == pytest.approx((0.6, 0.0, 0.8))
    assert (reg.r_min, reg.r_max, reg.half_width, reg.coupling) == (0.01, 0.05, 0.002, "rbe2")
    assert not is_review(reg)


@pytest.mark.parametrize("text, why", [
    ("arm=0,0,0,0,0,1,0,0.1,0.01", "expected LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w"),
    ("arm:j=0,0,0,0,0,1,0,0.1", "(got 8 numbers, not 9)"),
    ("arm:j=0,0,x,0,0,1,0,0.1,0.01", "(not a number in '0,0,x,0,0,1,0,0.1,0.01')"),
    ("arm:j=0,0,0,0,0,0,0,0.1,0.01", "the axis (ax,ay,az) must not be zero"),
    ("arm:j=0,0,0,0,0,1,0.1,0.1,0.01", "need 0 <= r_min < r_max and w > 0 [m], got "
     "r_min=0.1, r_max=0.1, w=0.01"),
    ("arm:j=0,0,0,0,0,1,0,0.1,nan", "(every number must be finite)"),
])
def test_parse_seat_errors_are_one_line_naming_the_value(text, why):
    with pytest.raises(ValueError) as err:
        parse_seat(text)
    msg = str(err.value)
    assert msg.startswith(f"--seat '{text}': ") and msg.endswith(why) and "\n" not in msg


def test_with_seats_puts_the_given_region_and_names_bad_links(tmp_path):
    robot = primitive_arm_robot(tmp_path)
    mine = ReviewRegion((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 0.0, 0.04, 0.003)
    out = with_seats(robot, [("arm", "joint_2", mine)])
    got = out.links[2].regions["joint_2"]
    assert got == Region(*mine.__dict__.values()) and not is_review(got)  # given: confirmed
    assert robot.links[2].regions == {}  # the input is not changed
    with pytest.raises(ValueError, match=r"^--seat hand:joint_2: no link 'hand' \(links: "
                                         r"base, column, arm, hub\)$"):
        with_seats(robot, [("hand", "joint_2", mine)])
    with pytest.raises(ValueError, match=r"^--seat arm:joint_1: link 'arm' has no joint "
                                         r"'joint_1' \(its joints: joint_2, joint_3\)$"):
        with_seats(robot, [("arm", "joint_1", mine)])


def test_missing_seat_warning_gives_a_seat_option_that_parses_back():
    reg = ReviewRegion((0.0, -0.0881, 0.0), (0.0, 1.0, 0.0), 0.0, 0.0527, 0.0105)
    line = MissingSeat("link_2", "joint_2", "no end face outside the other seats", reg).warning()
    assert "\n" not in line
    assert line.startswith("links.link_2: no bearing seat for joint_2 found on the CAD (no "
                           "end face outside the other seats); a suggested region is written "
                           "with review = true")
    option = line.split("--seat ", 1)[1].split(" ", 1)[0]
    link, joint, back = parse_seat(option)
    assert (link, joint) == ("link_2", "joint_2") and back.axis == reg.axis
    assert math.isclose(back.r_max, reg.r_max) and math.isclose(back.center[1], reg.center[1])
    assert seat_spec(reg) == "0,-0.0881,0,0,1,0,0,0.0527,0.0105"
    bare = MissingSeat("hub", "joint_3", "its CAD is not a closed surface").warning()
    assert "no region is written: give the seat with --seat hub:joint_3=cx,cy,cz" in bare
