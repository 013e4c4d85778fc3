"""The regions job: FE nodes on the tet meshes, the table, the CSV and the pictures."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flexarm.robot.description import Region
from flexarm.robot.seats import detect_regions
from flexarm.studies.show_regions import show_regions

from ..primitive_arm import SEATS, primitive_arm_robot

H = 0.04  # [m] tet edge: gmsh meshes the primitives in a fraction of a second each
SIZE = (480, 360)


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    return detect_regions(primitive_arm_robot(tmp_path_factory.mktemp("primitive_arm")),
                          mesh_size=H)


@pytest.fixture(scope="module")
def result(robot):
    return show_regions(robot, mesh_size=H)


def test_every_detected_region_works_on_the_tet_mesh(robot, result):
    """What the build checks, on the tet meshes at the size the seats were found
    for: every region holds non-collinear surface nodes and no node is in two."""
    from flexarm.assembly.build import link_mesh
    from flexarm.reduction.interfaces import select_region

    assert result.ok and result.mesh_size == H
    rows = {(r.link, r.region): r for r in result.rows}
    assert set(rows) == set(SEATS)
    # the counts are those of the build's own selection on the cached mesh
    arm = robot.links[2]
    mesh = link_mesh(arm, H, mesher=robot.options.mesher)
    for name, reg in arm.regions.items():
        cyl = _cylinder(name, reg)
        assert rows[("arm", name)].fe_nodes == select_region(mesh, cyl).size
    for key, row in rows.items():
        assert row.fe_nodes >= 6 and row.status == "ok", key
        assert row.seat.rank == 6 and row.seat.axis_offset < 1e-3, key
    # a 20 mm bore through the 60 mm hub: its wall's nodes, on both rims at least
    assert rows[("hub", "joint_3")].fe_nodes >= 2 * 16


def _cylinder(name, reg):
    from flexarm.reduction.interfaces import CylinderRegion

    return CylinderRegion(name, reg.center, reg.axis, reg.r_min, reg.r_max, reg.half_width)


def test_table_lists_links_and_regions(result):
    lines = result.text().splitlines()
    assert "tet mesh at 40 mm" in lines[0]
    assert lines[1].split() == ["link", "region", "FE_nodes", "area_cm2", "r_mm", "axial_mm",
                                "off_axis_mm", "off_origin_mm", "status"]
    body = [ln.split() for ln in lines[2:lines.index("")]]
    assert [(b[0], b[1]) for b in body] == [(r.link, r.region) for r in result.rows]
    hub = next(b for b in body if b[:2] == ["hub", "joint_3"])
    assert hub[5] == "60.0" and hub[-1] == "ok"  # axial extent of the bore [mm]


def test_missing_and_overlapping_regions_are_reported(robot):
    links = list(robot.links)
    col = dict(links[1].regions)
    del col["joint_2"]
    links[1] = dataclasses.replace(links[1], regions=col)
    base = dict(links[0].regions)  # a foundation region as tall as the base
    base["base"] = Region((0.0, 0.0, 0.15), (0.0, 0.0, 1.0), 0.0, 0.2, 0.16)
    links[0] = dataclasses.replace(links[0], regions=base)
    res = show_regions(dataclasses.replace(robot, links=tuple(links)), mesh_size=H)
    rows = {(r.link, r.region): r for r in res.rows}
    assert not res.ok
    assert rows[("column", "joint_2")].status.startswith("missing")
    assert rows[("column", "joint_2")].fe_nodes == 0
    assert rows[("column", "joint_1")].status == "ok"
    assert rows[("base", "joint_1")].status.startswith("overlaps region 'base'")
    assert rows[("arm", "joint_2")].status == "ok"
    assert "missing" in res.text().splitlines()[-1] or any(
        ln.endswith("missing: the build needs one") for ln in res.text().splitlines())


def test_csv_and_one_picture_per_link(robot, result, tmp_path, gl):
    import imageio.v3 as iio

    files = result.write(tmp_path, window_size=SIZE)
    assert [p.name for p in files] == ["regions.csv"] + [f"regions_{lk.name}.png"
                                                         for lk in robot.links]
    csv = (tmp_path / "regions.csv").read_text().splitlines()
    head = csv[0].split(",")
    assert head[:3] == ["link", "region", "fe_nodes"] and head[-1] == "status"
    assert len(csv) == 1 + len(result.rows)
    hub = next(ln.split(",") for ln in csv if ln.startswith("hub,joint_3,"))
    assert float(hub[head.index("r_min_m")]) == pytest.approx(
        robot.links[3].regions["joint_3"].r_min, rel=1e-5)
    # each picture shows its regions' colours: the first region's blue (tab10 #1f77b4)
    # and the second's orange on a white background
    for lk in robot.links:
        img = iio.imread(tmp_path / f"regions_{lk.name}.png")[..., :3].astype(int)
        assert img.shape[:2] == (SIZE[1], SIZE[0])
        for colour in ((0x1F, 0x77, 0xB4), (0xFF, 0x7F, 0x0E)):
            near = np.abs(img - np.array(colour)).sum(axis=-1) < 60
            assert near.sum() > 50, (lk.name, colour)


def test_show_regions_writes_with_out_dir(robot, tmp_path, gl):
    res = show_regions(robot, tmp_path, mesh_size=H)
    assert res.files[0] == tmp_path / "regions.csv" and len(res.files) == 1 + len(robot.links)
    assert all(p.stat().st_size > 0 for p in res.files)


def test_seat_pairs_on_the_tet_meshes(result):
    """Each joint's two seats: the CAD gap along the axis and the FE nodes of each side,
    as the region rows count them."""
    nodes = {(r.link, r.region): r.fe_nodes for r in result.rows}
    assert [p.pair.joint for p in result.pairs] == ["joint_1", "joint_2", "joint_3"]
    assert result.pairs_ok
    for p in result.pairs:
        assert (p.parent_nodes, p.child_nodes) == (nodes[(p.pair.parent, p.pair.joint)],
                                                   nodes[(p.pair.child, p.pair.joint)])
        assert min(p.parent_nodes, p.child_nodes) >= 6
    j1, j2, j3 = (p.pair for p in result.pairs)
    # faces that meet (the base's top and the column's bottom: both at z = 0.3 m)
    assert abs(j1.gap) < 1e-3 and abs(j2.gap) < 1e-3 and j1.held == ""
    # the hub's bore (0..60 mm) on the arm's end face: its middle 30 mm off, its end on it
    assert j3.held == "bore" and j3.gap == pytest.approx(0.03, abs=2e-3) and j3.reach < 1e-3
    assert [p.status for p in result.pairs] == ["ok", "ok", "ok (bore)"]
    table = result.text().split("\n\n")[1].splitlines()
    assert table[1].split() == ["joint", "parent", "child", "gap_mm", "overlap_mm", "nodes_p",
                                "nodes_c", "status"]
    assert table[4].split()[:4] == ["joint_3", "arm", "hub", f"{1e3 * j3.gap:.1f}"]


def test_a_region_to_review_is_shown_and_still_builds(robot):
    from flexarm.robot.seat_review import ReviewRegion

    links = list(robot.links)
    hub = dict(links[3].regions)
    hub["joint_3"] = ReviewRegion(*dataclasses.astuple(hub["joint_3"]))
    links[3] = dataclasses.replace(links[3], regions=hub)
    res = show_regions(dataclasses.replace(robot, links=tuple(links)), mesh_size=H,
                       links=["hub"])
    rows = {r.region: r for r in res.rows}
    assert rows["joint_3"].status.startswith("review: suggested where no seat was found")
    assert rows["tcp"].status == "ok" and res.ok  # the build takes it
