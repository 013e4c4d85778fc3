"""Seat pairs that face each other: hulls that overlap along the joint axis."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from flexarm.fe.material import MATERIALS
from flexarm.robot.description import Joint, Link, ModelOptions, Robot, Tool
from flexarm.robot.joints import JointModel
from flexarm.robot.seat_facing import face_each_other
from flexarm.robot.seat_pairs import PAIR_GAP, seat_pairs
from flexarm.robot.seat_sample import link_sample
from flexarm.robot.seats import find_seats


def _turret(folder, sink: float = 0.02, lid: float | None = None):
    """A base cylinder (r 0.15 m, z 0..0.3) and a turret cylinder (r 0.1 m, 0.4 m tall)
    whose bottom sits ``sink`` [m] below the base's top face (the joint plane z = 0.3):
    the two hulls overlap there.  ``lid``: the turret's radius is that instead."""
    steel = MATERIALS["steel"]
    base = trimesh.creation.cylinder(0.15, 0.3, sections=64)
    base.apply_translation((0.0, 0.0, 0.15))
    base.export(folder / "base.stl")
    top = trimesh.creation.cylinder(lid or 0.1, 0.4, sections=64)
    top.apply_translation((0.0, 0.0, 0.2 - sink))
    top.export(folder / "turret.stl")
    links = (Link("base", folder / "base.stl", steel), Link("turret", folder / "turret.stl",
                                                             steel))
    joint = Joint("joint_1", "base", "turret", (0.0, 0.0, 0.3), (0.0, 0.0, 1.0), -math.pi,
                  math.pi, JointModel(torsion=1e5))
    return Robot("turret", links, (joint,), tool=Tool(xyz=(0.0, 0.0, 0.38)),
                 options=ModelOptions(mesh_size=0.04, mesher="gmsh"))


def test_faces_that_overlap_become_a_face_and_the_band_in_its_plane(tmp_path):
    """The base's top face (z = 0.3) and the turret's bottom (20 mm lower) are 20 mm
    apart: the base's face stays, and the turret's seat becomes its band about that
    plane: its bottom face and as much of its wall above as puts the centroid there."""
    robot = _turret(tmp_path)
    res = find_seats(robot, tcp=False, base=False)
    (pair,) = seat_pairs(res.robot)
    assert pair.ok and abs(pair.gap) < 0.5 * PAIR_GAP
    assert res.paired == (("turret", "joint_1"),) and res.missing == ()
    face = res.robot.links[0].regions["joint_1"]
    band = res.robot.links[1].regions["joint_1"]
    assert face.r_min == 0.0 and face.center[2] == pytest.approx(0.3, abs=1e-6)
    # the turret frame: its bottom face at z = -0.02, the base's face plane at z = 0
    assert band.center[2] - band.half_width < -0.02 < band.center[2] + band.half_width
    assert band.center[2] + band.half_width > 0.02 and band.r_min == 0.0
    assert band.r_max == pytest.approx(0.1, abs=0.005)
    assert pair.overlap == pytest.approx(0.097, abs=0.003)  # both discs: r 0..0.1


def test_seats_that_meet_are_left_alone(tmp_path):
    robot = _turret(tmp_path, sink=0.0)
    res = find_seats(robot, tcp=False, base=False)
    (pair,) = seat_pairs(res.robot)
    assert res.paired == () and pair.ok and abs(pair.gap) < 1e-3
    assert all(lk.regions["joint_1"].r_min == 0.0 for lk in res.robot.links)  # two faces


def test_a_seat_given_by_hand_is_kept_and_the_other_faces_it(tmp_path):
    """The base's top face given by hand, the turret's bottom face 20 mm lower: the
    turret's seat moves to face it, whatever the two ways round would score."""
    from flexarm.robot.description import Region

    robot = _turret(tmp_path)
    given = Region((0.0, 0.0, 0.3), (0.0, 0.0, 1.0), 0.0, 0.09, 0.004)
    bottom = Region((0.0, 0.0, -0.02), (0.0, 0.0, 1.0), 0.0, 0.07, 0.004)
    samples = {i: link_sample(lk) for i, lk in enumerate(robot.links)}
    regions = {0: {"joint_1": given}, 1: {"joint_1": bottom}}
    changed = face_each_other(robot, samples, regions, 0.04, fixed={(0, "joint_1")})
    assert changed == [(1, "joint_1")] and regions[0]["joint_1"] is given
    band = regions[1]["joint_1"]
    inside = samples[1].points[band.contains(samples[1].points)]
    assert abs(inside[:, 2].mean()) < 0.5 * PAIR_GAP
    assert inside[:, 2].min() == pytest.approx(-0.02, abs=1e-3)  # its bottom face in it


def test_no_band_where_the_other_link_does_not_surround_the_axis(tmp_path):
    """A turret 30 mm above the base (a true gap): no surface of either at the other's
    face, so the pair keeps its faces and reports the gap."""
    robot = _turret(tmp_path, sink=-0.03)
    res = find_seats(robot, tcp=False, base=False)
    (pair,) = seat_pairs(res.robot)
    assert res.paired == () and not pair.ok
    assert pair.gap == pytest.approx(0.03, abs=1e-3)
    assert pair.status == "gap 30.0 mm > 5 mm along the axis"
    assert np.isfinite(pair.overlap)
