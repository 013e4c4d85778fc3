"""The local edge a seat is meshed with, and the nodes the import report expects there."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexarm.robot import load_robot
from flexarm.robot.seat_geometry import NODE_AREA
from flexarm.robot.seat_mesh import (
    MIN_SEAT_NODES,
    SEAT_NODES,
    seat_areas,
    seat_edge,
    seat_local_sizes,
    seat_mesh_nodes,
)
from flexarm.robot.tolerances import tol


@pytest.mark.parametrize("area", [1e-4, 3.46e-3, 2e-2, 4e-2])
def test_the_local_edge_puts_exactly_the_target_nodes_on_a_small_seat(area):
    h = 0.08
    edge = seat_edge(area, h)
    nodes = area / (NODE_AREA * edge**2)
    if area / (NODE_AREA * h**2) >= MIN_SEAT_NODES:  # enough at the mesh size: kept
        assert edge == h
    elif edge > tol.seat_local_edge_min * h:
        assert nodes == pytest.approx(SEAT_NODES, rel=1e-12)
    else:  # the finest edge allowed: fewer, as the estimate says
        assert edge == tol.seat_local_edge_min * h and nodes < SEAT_NODES


def test_the_m20ia_joint4_seat_area_asks_for_an_18_mm_edge_at_30_mm():
    # 34.6 cm^2 (the published M-20iA's seat on link_3): 4.4 nodes at 30 mm
    edge = seat_edge(34.6e-4, 0.03)
    assert edge == pytest.approx(math.sqrt(34.6e-4 / (NODE_AREA * SEAT_NODES)), rel=1e-12)
    assert 0.018 < edge < 0.019


def test_local_sizes_cover_the_regions_that_need_them_and_the_estimate_agrees():
    robot = load_robot()
    link = robot.links[robot.link_index["turning_disc"]]  # joint_6 and tcp: both refined
    h = 0.08
    areas = seat_areas(link)
    sizes = {round(c.size, 12): c for c in seat_local_sizes(link, h)}
    nodes = seat_mesh_nodes(link, h)
    for name, reg in link.regions.items():
        flat = areas[name] / (NODE_AREA * h**2)
        if flat >= MIN_SEAT_NODES:
            assert nodes[name] == pytest.approx(flat)
            continue
        c = sizes[round(seat_edge(areas[name], h), 12)]
        assert c.radius == reg.r_max and c.half_width == reg.half_width
        np.testing.assert_allclose(c.center, reg.center)
        assert nodes[name] == pytest.approx(SEAT_NODES)
    assert seat_local_sizes(link, 1e-3) == ()  # fine enough everywhere
