"""``flexarm show-regions``: the table, the files, the exit code."""

from __future__ import annotations

import dataclasses

import pytest

from flexarm.cli import main
from flexarm.robot.formats import toml
from flexarm.robot.seats import detect_regions

from ..primitive_arm import SEATS, primitive_arm_robot

H = "0.04"


@pytest.fixture(scope="module")
def robot_files(tmp_path_factory):
    """The primitive arm as TOML: with detected regions, and with one seat left out."""
    folder = tmp_path_factory.mktemp("primitive_arm")
    robot = detect_regions(primitive_arm_robot(folder), mesh_size=float(H))
    good = folder / "robot.toml"
    toml.write(good, robot)
    links = list(robot.links)
    links[2] = dataclasses.replace(links[2], regions={
        n: r for n, r in links[2].regions.items() if n != "joint_3"})
    bad = folder / "missing.toml"
    toml.write(bad, dataclasses.replace(robot, links=tuple(links)))
    return good, bad


def test_table_of_every_region(robot_files, capsys):
    assert main(["show-regions", "--robot", str(robot_files[0]), "--mesh-size", H]) == 0
    out = capsys.readouterr().out.splitlines()
    assert "tet mesh at 40 mm" in out[0]
    blank = out.index("")
    rows = [ln.split() for ln in out[2:blank]]
    assert {(r[0], r[1]) for r in rows} == set(SEATS)
    assert all(r[-1] == "ok" and int(r[2]) >= 6 for r in rows)
    assert not any(ln.startswith("wrote") for ln in out)
    # the seat pairs: faces that meet, and the hub's bore on the arm's end face
    assert out[blank + 1].startswith("seat pairs (gap along the joint axis")
    pairs = {ln.split()[0]: ln for ln in out[blank + 3:]}
    assert list(pairs) == ["joint_1", "joint_2", "joint_3"]
    assert pairs["joint_1"].endswith("  ok") and pairs["joint_3"].endswith("  ok (bore)")
    assert all(min(int(v) for v in ln.split()[5:7]) >= 6 for ln in pairs.values())


def test_a_missing_seat_exits_1(robot_files, capsys):
    assert main(["show-regions", "--robot", str(robot_files[1]), "--mesh-size", H]) == 1
    captured = capsys.readouterr()
    row = next(ln for ln in captured.out.splitlines() if ln.startswith("arm ")
               and " joint_3 " in ln)
    assert row.endswith("missing: the build needs one")
    assert "arm: no region for joint_3" in captured.err


def test_links_option(robot_files, capsys):
    assert main(["show-regions", "--robot", str(robot_files[0]), "--mesh-size", H,
                 "--links", "hub, arm"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = [ln.split()[:2] for ln in out[2:out.index("")]]
    assert rows == [["arm", "joint_2"], ["arm", "joint_3"], ["hub", "joint_3"], ["hub", "tcp"]]
    # pairs of the links shown; the column's side of joint_2 was not meshed: "-"
    pairs = [ln.split() for ln in out[out.index("") + 3:]]
    assert [p[0] for p in pairs] == ["joint_2", "joint_3"] and pairs[0][5] == "-"
    assert main(["show-regions", "--robot", str(robot_files[0]), "--links", "nope"]) == 2
    assert "unknown link 'nope'" in capsys.readouterr().err


def test_bad_robot_is_one_line_error(tmp_path, capsys):
    assert main(["show-regions", "--robot", str(tmp_path / "none.toml")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("flexarm show-regions: error:") and "\n" not in err


def test_writes_pictures_and_csv(robot_files, tmp_path, capsys):
    from flexarm.fe.errors import FlexarmError, MissingDependencyError
    from flexarm.reduction.render import render_backend

    try:
        render_backend()
    except (FlexarmError, MissingDependencyError) as exc:
        pytest.skip(f"no off-screen rendering here: {exc}")
    out = tmp_path / "regions"
    assert main(["show-regions", "--robot", str(robot_files[0]), "--mesh-size", H,
                 "-o", str(out)]) == 0
    wrote = [ln.split(" ", 1)[1] for ln in capsys.readouterr().out.splitlines()
             if ln.startswith("wrote ")]
    names = ["regions.csv"] + [f"regions_{n}.png" for n in ("base", "column", "arm", "hub")]
    assert wrote == [str(out / n) for n in names]
    assert all((out / n).stat().st_size > 0 for n in names)
