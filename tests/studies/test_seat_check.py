"""Can the file be built?  The build's region checks on the CAD sample, without meshing."""

from __future__ import annotations

import dataclasses

import pytest

from flexarm.robot.description import Region
from flexarm.robot.seat_review import ReviewRegion
from flexarm.robot.seats import detect_regions
from flexarm.studies.seat_check import build_problems, review_regions

from ..primitive_arm import primitive_arm_robot


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    return detect_regions(primitive_arm_robot(tmp_path_factory.mktemp("primitive_arm")))


def _set(robot, link, name, region):
    links = list(robot.links)
    i = robot.link_index[link]
    regions = dict(links[i].regions)
    if region is None:
        del regions[name]
    else:
        regions[name] = region
    links[i] = dataclasses.replace(links[i], regions=regions)
    return dataclasses.replace(robot, links=tuple(links))


def test_detected_regions_build(robot):
    assert build_problems(robot) == () and review_regions(robot) == ()


def test_each_reason_is_one_line_naming_link_and_region(robot):
    missing = _set(robot, "arm", "joint_3", None)
    (line,) = build_problems(missing)
    assert line.startswith("links.arm.regions: no region for joint_3")
    off = _set(robot, "arm", "joint_3", Region((0.0, 5.0, 0.0), (0, 1, 0), 0.0, 0.05, 0.01))
    assert build_problems(off) == (
        "links.arm.regions.joint_3: holds 0 CAD sample points that cannot carry 6 "
        "rigid-body DOFs (it misses the surface)",)
    # the whole column as joint_1's seat takes joint_2's too
    big = _set(robot, "column", "joint_1", Region((0, 0, 0.25), (0, 0, 1), 0.0, 0.2, 0.3))
    (line,) = build_problems(big)
    assert line.startswith("links.column: regions 'joint_1' and 'joint_2' overlap (")


def test_a_suggestion_that_holds_surface_builds_but_is_listed(robot):
    reg = robot.links[2].regions["joint_3"]
    marked = _set(robot, "arm", "joint_3", ReviewRegion(*dataclasses.astuple(reg)))
    assert build_problems(marked) == () and review_regions(marked) == ("arm:joint_3",)
