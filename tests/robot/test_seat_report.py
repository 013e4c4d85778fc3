"""Regions measured on the CAD sample: the primitive arm's detected seats, the demo arm's
hand-made ones."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexarm.robot.description import Region
from flexarm.robot.seat_report import region_order, region_references, seat_report, seat_row
from flexarm.robot.seats import detect_regions
from flexarm.robot.tolerances import tol

from ..primitive_arm import SEATS, primitive_arm_robot


@pytest.fixture(scope="module")
def primitive_seats(tmp_path_factory):
    return detect_regions(primitive_arm_robot(tmp_path_factory.mktemp("primitive_arm")))


def test_primitive_seat_report(primitive_seats):
    rows = {(r.link, r.region): r for r in seat_report(primitive_seats).rows}
    assert set(rows) == set(SEATS)
    for key, row in rows.items():
        assert row.rank == 6 and row.n_points >= tol.seat_min_sample_points, key
        assert row.axis_offset < 1e-3, key  # every seat closes a ring about its axis
    # the base's top face disc: area pi r^2 of its region radius, axial extent zero
    top = rows[("base", "joint_1")]
    assert top.axial == pytest.approx(0.0, abs=1e-9)
    assert top.area == pytest.approx(math.pi * top.r_hi**2, rel=0.05)
    assert rows[("hub", "joint_3")].origin_offset == pytest.approx(0.03, abs=1e-3)


def test_primitive_references_and_order(primitive_seats):
    refs = region_references(primitive_seats)
    # the column sees joint_2 at its origin in the column frame, yawed to -y
    np.testing.assert_allclose(refs[("column", "joint_2")][0], [0.0, -0.08, 0.42])
    np.testing.assert_allclose(refs[("column", "joint_2")][1], [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(refs[("hub", "tcp")][0], [0.0, 0.06, 0.0])
    np.testing.assert_allclose(refs[("base", "base")][0], [0.0, 0.0, 0.0])
    assert region_order(primitive_seats, primitive_seats.links[0]) == ["joint_1", "base"]
    assert region_order(primitive_seats, primitive_seats.links[3]) == ["joint_3", "tcp"]


def test_seat_row_of_an_empty_region():
    reg = Region((5.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.0, 0.1, 0.1)
    row = seat_row("link", "joint_1", reg, np.zeros((4, 3)), 1e-4, ((0, 0, 0), (0, 0, 1)))
    assert (row.n_points, row.area, row.rank) == (0, 0.0, 0)
    assert math.isnan(row.axis_offset) and math.isnan(row.origin_offset)


def test_demo_seat_report_of_the_hand_made_regions(demo_robot):
    rep = seat_report(demo_robot)
    assert len(rep.rows) == sum(len(lk.regions) for lk in demo_robot.links)
    assert all(r.rank == 6 and r.n_points >= tol.seat_min_sample_points for r in rep.rows)
    text = rep.text()
    assert text.splitlines()[1].split()[:3] == ["link", "region", "points"]
    assert len(text.splitlines()) == 2 + len(rep.rows)
