"""Bearing seats found on the CAD: a primitive arm, the demo arm, the ABB IRB 4600.

The parts have their own tests: the sample (``test_seat_sample``), rings, bores and faces
(``test_seat_geometry``), one seat's search (``test_seat_search``) and the report
(``test_seat_report``)."""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from flexarm.reduction.tolerances import tol as red_tol
from flexarm.robot import seat_facing, seats
from flexarm.robot.description import Region
from flexarm.robot.kinematics import rpy_matrix
from flexarm.robot.seat_pairs import seat_pairs
from flexarm.robot.seats import detect_regions, region_references, seat_report
from flexarm.robot.tolerances import tol

from ..primitive_arm import SEATS, primitive_arm_robot

IRB_URDF = Path("/work/shared/data/irb4600/urdf/irb4600_60_205.urdf")
IRB_MESH = 0.06  # [m] the coarse mesh of the build tests


def _axis_distance(point, origin, axis) -> float:
    d = np.asarray(point, float) - np.asarray(origin, float)
    a = np.asarray(axis, float)
    return float(np.linalg.norm(d - (d @ a) * a))


def _link_regions(robot):
    return {(lk.name, n): reg for lk in robot.links for n, reg in lk.regions.items()}


# ------------------------------------------------------------------------------ primitives
@pytest.fixture(scope="module")
def primitive(tmp_path_factory):
    return primitive_arm_robot(tmp_path_factory.mktemp("primitive_arm"))


@pytest.fixture(scope="module")
def primitive_seats(primitive):
    return detect_regions(primitive)


def test_primitive_arm_gets_every_seat(primitive, primitive_seats):
    """Faces of boxes and cylinders, a bore, the flange and the foundation: each centre
    where the geometry puts it (1 mm), on the axis the joint gives in that link's frame."""
    regions = _link_regions(primitive_seats)
    assert set(regions) == set(SEATS)
    refs = region_references(primitive_seats)
    for key, want in SEATS.items():
        reg = regions[key]
        np.testing.assert_allclose(reg.center, want, atol=1e-3, err_msg=str(key))
        axis = refs[key][1]
        assert abs(np.dot(reg.axis, axis)) == pytest.approx(1.0, abs=1e-12), key
    # joint_2's frame is yawed: the column sees its axis along -y, the arm along its x
    np.testing.assert_allclose(regions[("column", "joint_2")].axis, [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(regions[("arm", "joint_2")].axis, [1, 0, 0], atol=1e-12)
    # the hub (a tube written in mm) seats on its bore: a ring about r = 20 mm through
    # its 60 mm; the flange region is the far end face outside that ring
    bore, tcp = regions[("hub", "joint_3")], regions[("hub", "tcp")]
    assert bore.r_min < 0.02 < bore.r_max < 0.03 and bore.half_width >= 0.03
    assert bore.r_max < tcp.r_min < 0.045 < tcp.r_max and tcp.coupling == "rbe3"
    # faces are discs: the column's 0.16 m square end gives one inside its corners
    col = regions[("column", "joint_1")]
    assert col.r_min == 0.0 and 0.04 < col.r_max < 0.08 * math.sqrt(2)


def test_given_regions_are_kept(primitive):
    mine = Region((0.0, 0.0, 0.001), (0.0, 0.0, 1.0), 0.0, 0.05, 0.002)
    links = list(primitive.links)
    links[1] = dataclasses.replace(links[1], regions={"joint_1": mine})
    robot = dataclasses.replace(primitive, links=tuple(links))
    kept = detect_regions(robot, tcp=False, base=False)
    regions = _link_regions(kept)
    assert regions[("column", "joint_1")] is mine
    assert ("base", "base") not in regions and ("hub", "tcp") not in regions
    assert len(regions) == len(SEATS) - 2
    replaced = detect_regions(robot, overwrite=True)
    assert _link_regions(replaced)[("column", "joint_1")] != mine


def test_missing_seat_names_link_joint_and_a_start(primitive):
    """joint_3 moved 0.5 m off the arm: its axis misses the arm entirely."""
    joints = list(primitive.joints)
    joints[2] = dataclasses.replace(joints[2], origin=(0.6, 0.6, 0.5))
    robot = dataclasses.replace(primitive, joints=tuple(joints))
    with pytest.raises(ValueError) as err:
        detect_regions(robot)
    msg = str(err.value)
    assert msg.startswith("links.arm: no bearing seat for joint_3")
    assert "[links.regions.joint_3] center = [" in msg and "half_width = " in msg
    assert "\n" not in msg


def test_overlapping_seats_are_refused(primitive):
    """A hand-made column region reaching both ends collides with a detected seat."""
    long = Region((0.0, 0.0, 0.25), (0.0, 0.0, 1.0), 0.0, 0.2, 0.3)
    links = list(primitive.links)
    links[1] = dataclasses.replace(links[1], regions={"joint_1": long})
    robot = dataclasses.replace(primitive, links=tuple(links))
    with pytest.raises(ValueError, match="links.column: regions 'joint_1' and 'joint_2' "
                                         "overlap"):
        detect_regions(robot)


def test_no_flange_or_foundation_face_warns_and_skips(primitive, tmp_path):
    """A hub whose CAD misses its flange axis, a base that is an upside-down cone (no
    face looks down): both skipped with a warning that points at the caller."""
    import trimesh

    far = trimesh.creation.box((0.05, 0.05, 0.05))
    far.apply_translation((0.5, 0.0, 0.5))
    far.export(tmp_path / "far.stl")
    cone = trimesh.creation.cone(0.15, 0.3, sections=64)
    cone.apply_transform(trimesh.transformations.rotation_matrix(math.pi, [1, 0, 0]))
    cone.apply_translation((0.0, 0.0, 0.3))
    cone.export(tmp_path / "cone.stl")
    links = list(primitive.links)
    links[0] = dataclasses.replace(links[0], mesh=tmp_path / "cone.stl")
    links[2] = dataclasses.replace(links[2], regions={
        "joint_3": Region((0.05, 0.6, 0.0), (0.0, 1.0, 0.0), 0.0, 0.04, 0.01)})
    links[3] = dataclasses.replace(links[3], mesh=tmp_path / "far.stl", units="m", regions={
        "joint_3": Region((0.5, 0.0, 0.5), (0.0, 1.0, 0.0), 0.0, 0.04, 0.03)})
    robot = dataclasses.replace(primitive, links=tuple(links))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = detect_regions(robot)
    assert [str(w.message) for w in caught] == [
        "links.hub: no flange face for a 'tcp' region (no flange face closes a ring about the "
        "axis); the TCP is carried rigidly by the flange seat",
        "links.base: no foundation face for a 'base' region (no surface faces away from the "
        "first joint); the base stays rigid"]
    assert all(w.filename == __file__ for w in caught)
    regions = _link_regions(found)
    assert ("hub", "tcp") not in regions and ("base", "base") not in regions
    assert ("base", "joint_1") in regions and ("column", "joint_1") in regions


def test_parts_and_tolerances_are_importable_from_seats():
    from flexarm.robot import seat_report as report
    from flexarm.robot import seat_sample, seat_search

    assert seats.surface_sample is seat_sample.surface_sample
    assert seats.SeatReport is report.SeatReport and seats.seat_row is report.seat_row
    assert seats.SEAT_FRACTION == seat_search.SEAT_FRACTION
    assert (seats.RING_COVERAGE, seats.FACE_SLOPE, seats.MIN_SAMPLE_POINTS,
            seats.FOREIGN_AREA) == (tol.seat_ring_coverage, tol.seat_face_slope,
                                    tol.seat_min_sample_points, tol.seat_foreign_area)
    assert seats.MIN_MESH_NODES == tol.seat_mesh_nodes_factor * red_tol.min_region_nodes
    assert all(hasattr(seats, name) for name in seats.__all__)


# ------------------------------------------------------------------------------ demo arm
def test_demo_detected_seats_match_the_hand_made_ones(demo_robot, monkeypatch):
    """Same axis; centres within 5 cm; the detected bore radius inside the hand-made
    ring.  The tube shaft's fork is the exception by design: the hand-made seat is one
    cheek, the detected one holds both (and so the hand-made centre).  Found from the CAD
    samples: no link is meshed on the way."""
    from flexarm.meshes import pipeline

    def no_mesher(*args, **kwargs):
        raise AssertionError("seat detection meshed a link")

    monkeypatch.setattr(pipeline, "tetrahedralizer", no_mesher)
    found = _link_regions(detect_regions(demo_robot, overwrite=True))
    given = _link_regions(demo_robot)
    assert set(found) == set(given)
    for key, hand in given.items():
        reg = found[key]
        assert abs(np.dot(reg.axis, hand.axis)) == pytest.approx(1.0, abs=1e-12), key
        assert hand.r_min <= 0.5 * (reg.r_min + reg.r_max) <= hand.r_max, key
        gap = np.subtract(reg.center, hand.center)
        if key == ("tube_shaft", "joint_5"):
            assert abs(gap @ reg.axis) + 0.0175 <= reg.half_width  # the cheek, y 65-100 mm
        else:
            assert np.linalg.norm(gap) < 0.05, (key, gap)
    # cast hubs: the bores of the lower arm run through both walls (190 and 180 mm)
    assert found[("lower_arm", "joint_2")].half_width > 0.09
    assert found[("lower_arm", "joint_3")].half_width > 0.085


# ------------------------------------------------------------------------------ IRB 4600
@pytest.fixture(scope="module")
def irb():
    if not IRB_URDF.is_file():
        pytest.skip(f"no IRB 4600 description at {IRB_URDF}")
    from flexarm.robot.formats.urdf import read

    with warnings.catch_warnings():  # the importer's own default regions miss the CAD
        warnings.simplefilter("ignore")
        robot = read(IRB_URDF)
    return detect_regions(robot, overwrite=True, mesh_size=IRB_MESH)


def _in_parent(robot, joint, point):
    """A point of the joint's child frame in the parent frame (zero angle)."""
    return rpy_matrix(joint.rpy) @ np.asarray(point) + np.asarray(joint.origin)


def test_irb4600_every_joint_seat_on_both_links(irb):
    regions = _link_regions(irb)
    rows = {(r.link, r.region): r for r in seat_report(irb).rows}
    refs = region_references(irb)
    for jt in irb.joints:
        for link in (jt.parent, jt.child):
            key = (link, jt.name)
            reg, row = regions[key], rows[key]
            origin, axis = refs[key]
            assert (reg.r_max, reg.half_width) != (0.15, 0.08), key  # not the default
            assert row.n_points >= 300 and row.rank == 6, key
            assert _axis_distance(reg.center, origin, axis) < 1e-9, key
            # the seat surrounds the axis (hull faces are tilted: a little off centre; a
            # hull's outline where the other seat is, more)
            assert row.axis_offset < seat_facing.OFF_AXIS * row.r_hi, key
            assert np.linalg.norm(np.subtract(reg.center, origin)) < 0.36, key
        # the two seats of a joint meet: their centres within 8 cm of each other
        child = _in_parent(irb, jt, regions[(jt.child, jt.name)].center)
        assert np.linalg.norm(child - regions[(jt.parent, jt.name)].center) < 0.08, jt.name
    # ... and face each other within 5 mm along the axis; joint_5's hub is held at both
    # ends in link_4's fork, whose hull cheeks differ: 7-11 mm, reported, not moved
    pairs = {p.joint: p for p in seat_pairs(irb)}
    assert all(pairs[j].ok for j in irb.joint_names if j != "joint_5"), pairs
    assert 0.005 < -pairs["joint_5"].gap < 0.012


def test_irb4600_seats_where_the_hulls_meet(irb):
    regions = _link_regions(irb)
    # the base's top face reaches 23 mm into link_1's hull above its flat bottom (its
    # z = -0.3415 m): link_1's seat holds that bottom and its skirt up to the plane of
    # the base's face, where their centroids meet
    base, link_1 = regions[("base_link", "joint_1")], regions[("link_1", "joint_1")]
    assert 0.15 < base.center[2] < 0.213 and base.r_min == 0.0
    assert link_1.contains(np.array([[0.1, 0.0, -0.3415]])).all()
    assert link_1.center[2] + link_1.half_width > base.center[2] - 0.495
    # the wrist: link_4's fork holds both ends of link_5's hub (two-sided seats)
    assert regions[("link_4", "joint_5")].half_width > 0.1
    assert regions[("link_5", "joint_5")].half_width > 0.06
    # the flange face (x = 0) carries the tool; the foundation is the bottom face z = 0
    assert regions[("link_6", "tcp")].center[0] == pytest.approx(0.0, abs=2e-3)
    assert regions[("base_link", "base")].center[2] == pytest.approx(0.0, abs=0.01)


def test_irb4600_wrist_link_builds(irb):
    """The two-sided hub seat and the face seat of link_5 on its pytetwild mesh: the
    build accepts them (enough nodes, rank 6, no overlap) and reduces the link."""
    from flexarm.assembly.build import BuildOptions, build_link

    lb = build_link(irb, 5, BuildOptions(mesh_size=IRB_MESH))
    assert lb.regions == ("joint_5", "joint_6")
    assert lb.superelement.n_dofs == 2 * 6 + irb.options.cb_modes
    f = lb.freq_hz
    assert np.isfinite(f).all() and f[0] > 1e3  # a compact cast-iron block: kHz


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:.*placeholder stiffness")
def test_irb4600_builds_and_its_cb_arm_is_softer_than_the_emodel(irb):
    """The whole robot at 60 mm (~55 s cold, meshing dominates): every link reduced,
    then CB(10) and E-model modes at the home pose."""
    from flexarm.assembly.analyses import modes
    from flexarm.assembly.arm import ArmSpec, build_arm
    from flexarm.assembly.build import BuildOptions, build_robot

    builds = build_robot(irb, BuildOptions(mesh_size=IRB_MESH))
    assert [lb.regions[0] for lb in builds] == ["base"] + list(irb.joint_names)
    q = np.zeros(len(irb.joints))
    f_cb = modes(build_arm(irb, ArmSpec("cb", mesh_size=IRB_MESH)).model, q).freq_hz
    f_e = modes(build_arm(irb, ArmSpec("emodel")).model, q).freq_hz
    print("\nIRB 4600 home pose, first modes [Hz]:")  # noqa: T201
    print("  CB(10)  ", np.round(f_cb[:6], 2))  # noqa: T201
    print("  E-model ", np.round(f_e[:6], 2))  # noqa: T201
    assert np.isfinite(f_cb).all() and (f_cb[:6] > 0).all()
    assert f_cb[0] <= f_e[0] * (1 + 1e-9)


def test_foundation_face_inside_a_joint_seat_is_skipped_with_a_warning(primitive):
    """A joint-1 seat given by hand that reaches down to the foundation face (a base
    shorter than the seat): the 'base' region would share its nodes, so it is skipped with
    a warning (the base stays rigid) and the given seat is kept, instead of an error."""
    links = list(primitive.links)
    given = Region((0.0, 0.0, 0.15), (0.0, 0.0, 1.0), 0.0, 0.16, 0.16)  # the whole base
    links[0] = dataclasses.replace(links[0], regions={"joint_1": given})
    robot = dataclasses.replace(primitive, links=tuple(links))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = detect_regions(robot)
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1 and messages[0].startswith(
        "links.base: no foundation face for a 'base' region (it would overlap the seat of "
        "joint_1 (")
    assert messages[0].endswith("the base stays rigid")
    regions = _link_regions(found)
    assert ("base", "base") not in regions and regions[("base", "joint_1")] == given
    assert ("column", "joint_1") in regions
