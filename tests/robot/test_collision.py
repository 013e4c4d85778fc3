"""Poses the robot can take, on the FANUC M-20iA as published (its collision hulls):
three poses known to collide (the wrist in the base, the arm in the floor, the wrist
folded onto the column) and three free ones; ``map`` masks the colliding grid poses."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from flexarm.robot.collision import CollisionChecker, PoseCheck

from ..cli_run import run_cli

URDF = Path(__file__).resolve().parents[3] / "shared/data/robots/fanuc_m20ia/urdf/m20ia.urdf"


_run = run_cli


@pytest.fixture(scope="module")
def m20ia(tmp_path_factory):
    if not URDF.is_file():
        pytest.skip(f"no M-20iA description at {URDF}")
    toml = tmp_path_factory.mktemp("m20ia") / "m20ia.toml"
    code, _, err = _run(["import-urdf", str(URDF), "--total-mass", "250", "--no-regions",
                         "-o", str(toml)])
    assert code == 0, err
    from flexarm.robot import load_robot

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return toml, load_robot(toml)


@pytest.fixture(scope="module")
def checker(m20ia):
    return CollisionChecker(m20ia[1])


COLLIDING = {  # pose [deg] -> what it hits
    (0, 0, 249.8, 0, 0, 0): ("link_1", "link_4"),  # the wrist inside the column and base
    (0, 90, 0, 0, 0, 0): "link_6",  # the arm laid forward into the floor
    (0, -40, 230, 0, 0, 0): ("base_link", "link_4"),  # folded back down into the base
}
FREE = [(0, 0, 0, 0, 0, 0), (0, 30, -36, 0, 0, 0), (45, -60, 20, 90, -45, 30)]


def test_only_adjacent_links_are_ignored(checker):
    assert checker.names[0] == "base_link" and len(checker.names) == 7
    # none of the hulls meet at rest: only the joints' neighbours are left out
    assert set(checker.ignored) == {("base_link", "link_1"),
                                    *((f"link_{k}", f"link_{k + 1}") for k in range(1, 6))}
    assert checker.floor_z == pytest.approx(0.0, abs=1e-9)  # base_link stands on z = 0


@pytest.mark.parametrize("pose", sorted(COLLIDING))
def test_known_collisions(checker, pose):
    hit = checker.check(np.radians(pose))
    assert not hit.ok
    what = COLLIDING[pose]
    if isinstance(what, tuple):
        assert what in hit.pairs, hit.text()
    else:
        assert what in hit.floor, hit.text()


@pytest.mark.parametrize("pose", FREE)
def test_free_poses(checker, pose):
    assert checker.check(np.radians(pose)) == PoseCheck()


def test_map_masks_every_colliding_grid_pose(m20ia, checker, tmp_path):
    toml, robot = m20ia
    code, out, err = _run(["map", "--robot", str(toml), "--model", "emodel", "--mass",
                           "surface", "--pose", "0,30,-36,0,0,0", "--n", "9",
                           "--no-frequencies", "-o", str(tmp_path)])
    assert code == 0, err
    table = np.genfromtxt(tmp_path / "map.csv", delimiter=",", names=True)
    Q = np.zeros((table.size, 6))
    Q[:, 1], Q[:, 2] = np.radians(table["q2_deg"]), np.radians(table["q3_deg"])
    hits = checker.colliding(Q)
    assert np.array_equal(table["collides"] == 1, hits) and 0 < hits.sum() < hits.size
    assert f"{int(hits.sum())} of 81 grid poses collide" in out
    for line in out.splitlines():  # the stiffest poses are poses it can take
        if line.startswith("stiffest in"):
            q2, q3 = (float(v) for v in re.findall(r"q[23]=\s*(-?[\d.]+) deg", line))
            assert not checker.check(np.radians([0, q2, q3, 0, 0, 0])).floor
            assert not checker.colliding(np.radians([0, q2, q3, 0, 0, 0]))


def test_pose_option_warns_of_a_colliding_pose(m20ia):
    toml = str(m20ia[0])
    code, _, err = _run(["compliance", "--robot", toml, "--mass", "surface", "--pose",
                         "0,0,249.8,0,0,0"])
    assert code == 0
    lines = [line for line in err.splitlines() if "cannot take" in line]
    assert len(lines) == 1 and lines[0].startswith("warning: --pose 0,0,249.8,0,0,0: ")
    assert "link_1 hits link_4" in lines[0] and "Traceback" not in err
    code, _, err = _run(["compliance", "--robot", toml, "--mass", "surface", "--pose",
                         "0,30,-36,0,0,0"])
    assert code == 0 and "cannot take" not in err
