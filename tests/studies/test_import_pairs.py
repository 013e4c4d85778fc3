"""``import-urdf`` checks the two seats of every joint against each other: the gap along the
joint axis and about how many FE nodes each side will hold, in one report line, and one
warning naming the joint and the gap where they are more than 5 mm apart."""

from __future__ import annotations

import re

import pytest

from flexarm.robot.formats import toml
from flexarm.robot.seat_pairs import seat_pairs

from ..cli_run import run_cli
from ..primitive_arm import urdf_cylinder as _cyl

pytestmark = pytest.mark.filterwarnings("ignore:.*placeholder stiffness")


@pytest.fixture(scope="module")
def urdf(tmp_path_factory):
    """base_link (r 0.1 m, z 0..0.2) under link_1 (r 0.08 m, 0.3 m tall), joint j1 at the
    base's top face; link_1 carries link_2 (r 0.05 m, 0.1 m tall) on its top face (j2)."""
    folder = tmp_path_factory.mktemp("two_drums")
    path = folder / "drums.urdf"
    path.write_text(f"""<robot name="drums">
  <link name="base_link">{_cyl(0.1, 0.2, 0.1)}</link>
  <link name="link_1">{_cyl(0.08, 0.3, 0.15)}</link>
  <link name="link_2">{_cyl(0.05, 0.1, 0.05)}</link>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="link_1"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="100"/>
  </joint>
  <joint name="j2" type="revolute"><parent link="link_1"/><child link="link_2"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="100"/>
  </joint>
</robot>""")
    return path


def test_found_seats_pair_up_and_the_report_says_so(urdf, tmp_path):
    out_toml = tmp_path / "drums.toml"
    code, out, err = run_cli(["import-urdf", str(urdf), "-o", str(out_toml)])
    assert code == 0, err
    assert "do not pair up" not in err
    (line,) = [ln for ln in out.splitlines() if ln.startswith("seat pairs:")]
    assert line.startswith("seat pairs: 2 of 2 within 5 mm along the joint axis")
    # the seats of j1 on the two faces that touch: no gap (an independent measure: the
    # CAD surface each seat holds, in the joint frame)
    pairs = {p.joint: p for p in seat_pairs(toml.read(out_toml))}
    assert abs(pairs["j1"].gap) < 1e-3 and abs(pairs["j2"].gap) < 1e-3


def test_a_pair_50_mm_apart_is_a_warning_naming_the_joint_and_the_gap(urdf, tmp_path):
    # both seats of j1 by hand: the base's top face, and a band of link_1's side wall
    # 40..60 mm up from its bottom face: 50 mm apart along the axis
    top = "base_link:j1=0,0,0.2,0,0,1,0,0.1,0.004"
    band = "link_1:j1=0,0,0.05,0,0,1,0.07,0.09,0.01"
    out_toml = tmp_path / "apart.toml"
    code, out, err = run_cli(["import-urdf", str(urdf), "--seat", top, "--seat", band,
                              "-o", str(out_toml)])
    assert code == 0, err  # it can be built: the pair is a warning, not a refusal
    (warning,) = [ln for ln in err.splitlines() if "do not pair up" in ln]
    assert warning.startswith("warning: j1: its seats on base_link and link_1 do not pair "
                              "up: gap ")
    gap_mm = float(re.search(r"gap ([\d.]+) mm > 5 mm along the axis", warning).group(1))
    assert gap_mm == pytest.approx(50.0, abs=1.0)
    assert "--seat base_link:j1=" in warning
    assert "seat pairs: 1 of 2 within 5 mm" in out
    (pair,) = [p for p in seat_pairs(toml.read(out_toml)) if p.joint == "j1"]
    assert pair.gap == pytest.approx(0.05, abs=1e-3)


def test_a_coarse_build_refines_the_seats_to_the_nodes_the_report_expects(urdf, tmp_path):
    """At 80 mm every seat of the drums holds 1 to 3 nodes' worth of surface; the build
    refines the mesh over each to the estimate (12), which it meets."""
    from flexarm.robot import load_robot
    from flexarm.robot.seat_geometry import NODE_AREA
    from flexarm.robot.seat_mesh import SEAT_NODES, seat_areas
    from flexarm.studies.seat_check import pair_checks

    from ..published_robots import pair_table

    h = 0.08
    out_toml = tmp_path / "drums.toml"
    assert run_cli(["import-urdf", str(urdf), "-o", str(out_toml)])[0] == 0
    robot = load_robot(out_toml)
    for lk in robot.links:  # without local sizes: fewer than the pair check's 6 nodes
        assert all(a / (NODE_AREA * h**2) < 6 for a in seat_areas(lk).values()), lk.name
    code, out, err = run_cli(["build", "--robot", str(out_toml), "--mesh-size", str(h)])
    assert code == 0, err
    rows = pair_table(out)
    for c in pair_checks(robot, h):
        row = rows[c.pair.joint]
        real = (int(row[5]), int(row[6]))
        assert (c.parent_nodes, c.child_nodes) == (SEAT_NODES, SEAT_NODES)
        # the estimate is a flat face's count: the build meets it, within a third
        assert all(SEAT_NODES <= n <= 1.34 * SEAT_NODES for n in real), (c.pair.joint, real)
        assert row[-1] == "ok"
