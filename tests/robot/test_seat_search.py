"""The seat of one (link, joint) on the primitive arm: axes, facing side, bore or face."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.kinematics import rpy_matrix
from flexarm.robot.seat_geometry import SeatNotFound
from flexarm.robot.seat_sample import SurfaceSample, link_sample
from flexarm.robot.seat_search import (
    _facing,
    check_seat,
    find_seat,
    first_joint,
    joint_axes,
    other_sample,
    suggestion,
    tcp_axis,
)
from flexarm.robot.tolerances import tol

from ..primitive_arm import primitive_arm_robot


@pytest.fixture(scope="module")
def primitive(tmp_path_factory):
    return primitive_arm_robot(tmp_path_factory.mktemp("primitive_arm"))


@pytest.fixture(scope="module")
def samples(primitive):
    return {i: link_sample(lk) for i, lk in enumerate(primitive.links)}


def test_joint_axes_as_each_link_sees_them(primitive):
    axes = joint_axes(primitive)
    names = [(primitive.links[ax.link].name, ax.name) for ax in axes]
    assert names == [("base", "joint_1"), ("column", "joint_1"), ("column", "joint_2"),
                     ("arm", "joint_2"), ("arm", "joint_3"), ("hub", "joint_3")]
    # the parent sees the joint origin and the yawed axis, the child its own origin
    col, arm = axes[2], axes[3]
    assert col.origin == (0.0, -0.08, 0.42) and (col.link, col.other) == (arm.other, arm.link)
    np.testing.assert_allclose(col.axis, [0, -1, 0], atol=1e-12)
    assert arm.origin == (0.0, 0.0, 0.0) and arm.axis == (1.0, 0.0, 0.0)
    tcp = tcp_axis(primitive)
    assert (tcp.link, tcp.name, tcp.axis, tcp.other) == (3, "tcp", (0.0, 1.0, 0.0), 2)
    assert first_joint(primitive).name == "joint_1"


def test_other_sample_moves_the_child_into_the_parent_frame(primitive, samples):
    col = joint_axes(primitive)[2]  # the column looking at the arm (child) across joint_2
    jt = primitive.joints[1]
    pts, normals = other_sample(primitive, col, samples[2])
    q = samples[2]
    np.testing.assert_allclose(pts, q.points @ rpy_matrix(jt.rpy).T + np.asarray(jt.origin))
    np.testing.assert_allclose(normals, q.normals @ rpy_matrix(jt.rpy).T)
    back = other_sample(primitive, joint_axes(primitive)[3], samples[1])[0]  # and back
    np.testing.assert_allclose(back @ rpy_matrix(jt.rpy).T + jt.origin, samples[1].points,
                               atol=1e-12)


@pytest.mark.parametrize(("e_l", "e_o", "sides"), [
    ((0.0, 1.0), (0.2, 0.8), (1, -1)),   # the other link inside: a fork around its hub
    ((0.2, 0.8), (0.0, 1.0), (1, -1)),   # past both ends alike: this link is the hub
    ((0.0, 1.0), (0.5, 2.0), (1,)),
    ((0.0, 1.0), (-1.0, 0.5), (-1,)),
])
def test_facing_side(e_l, e_o, sides):
    assert _facing(e_l, e_o) == sides


def test_every_primitive_seat_faces_the_other_link(primitive, samples):
    want = {("base", "joint_1"): (1,), ("column", "joint_1"): (-1,),
            ("column", "joint_2"): (1,), ("arm", "joint_2"): (-1,),
            ("arm", "joint_3"): (1,), ("hub", "joint_3"): (-1,)}
    for ax in joint_axes(primitive):
        reg, mask, sides = find_seat(primitive, ax, samples, 0.04, grow=False)
        key = (primitive.links[ax.link].name, ax.name)
        assert sides == want[key], key
        assert reg.contains(samples[ax.link].points[mask]).all(), key
    # the hub seats on its 20 mm bore, not on an end face
    reg = find_seat(primitive, joint_axes(primitive)[5], samples, 0.04, grow=False)[0]
    assert reg.r_min < 0.02 < reg.r_max < 0.03


def test_check_seat_wants_enough_points_off_a_line():
    pts = np.c_[np.linspace(0.0, 1.0, 30), np.zeros(30), np.zeros(30)]
    sample = SurfaceSample(pts, pts, 1.0, 0.1, 1.0)
    need = tol.seat_min_sample_points
    few = np.arange(30) < need - 1
    with pytest.raises(SeatNotFound, match=rf"only {need - 1} sample points \(< {need}\)"):
        check_seat(sample, few)
    with pytest.raises(SeatNotFound, match="collinear"):
        check_seat(sample, np.ones(30, dtype=bool))


def test_suggestion_is_one_line_of_toml_values(primitive, samples):
    ax = joint_axes(primitive)[5]
    text = suggestion(ax, samples[ax.link])
    assert text.startswith("start from [links.regions.joint_3] center = [")
    assert "axis = [0, 1, 0], r_min = 0.0, r_max = " in text and "\n" not in text
