"""The compensated program as KUKA KRL and as a CSV of poses: the same targets as RAPID.

The KRL files are read back by a small parser of this test (no KRL parser is maintained
on PyPI), independent of the writer: positions to 1e-6 mm, orientations to 1e-9 rad
(scipy's ``Rotation.from_euler("ZYX", [A, B, C])`` against RAPID's quaternion), moves,
speeds, zones and the tool as the module says; and by flexarm's own reader
(:func:`~flexarm.robot.formats.krl_read.read_krl`), with the payload and the PTP speeds.
"""

import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from flexarm.robot.formats.krl_read import read_krl
from flexarm.robot.formats.poses_csv import module_poses, read_poses
from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.kinematics import link_frames
from flexarm.studies.compensation import compensate
from flexarm.studies.compensation.program.program_out import program_format

from ..conftest import MILLING, THESIS

KINDS = {"MoveL": "LIN", "MoveC": "CIRC", "MoveJ": "PTP"}


def parse_krl(src: str, dat: str):
    """(E6POS name -> dict of components, DEF name -> list of (move, targets, settings))."""
    points = {}
    for name, body in re.findall(r"^DECL E6POS (\w+)=\{([^}]*)\}$", dat, re.MULTILINE):
        points[name] = {k: float(v) for k, v in re.findall(r"(\w+) (\S+?)(?:,|$)", body)}
    routines = {}
    for name, body in re.findall(r"^DEF (\w+)\( \)\n(.*?)^END$", src, re.MULTILINE | re.DOTALL):
        moves, settings = [], {}
        for line in body.splitlines():
            line = line.split(";")[0].strip()
            if m := re.match(r"(\$[\w.]+) = (.*)$", line):
                settings[m.group(1)] = m.group(2)
            elif m := re.match(r"(PTP|LIN|CIRC) (.*?)( C_DIS| C_PTP)?$", line):
                moves.append((m.group(1), [t.strip() for t in m.group(2).split(", ")],
                               dict(settings), m.group(3) is not None))
        routines[name] = moves
    return points, routines


@pytest.fixture(scope="module", params=["thesis", "milling"])
def written(request, robot, arm, tmp_path_factory):
    """(result, folder) of a compensation written as RAPID, KRL and CSV."""
    if request.param == "thesis":
        res = compensate(THESIS, robot, "ballbar:800N", procs=["Path_30"], step_mm=10,
                         split_mm=60, arm=arm)
    else:
        res = compensate(MILLING, robot, "tool:fx=300", step_mm=5, split_mm=40, arm=arm)
    folder = tmp_path_factory.mktemp(request.param)
    for name in ("comp.mod", "comp.src", "comp.csv"):
        res.write_program(folder / name)
    return res, folder


def test_krl_holds_the_rapid_targets_moves_and_speeds(written):
    res, folder = written
    module = read_rapid(folder / "comp.mod")
    points, routines = parse_krl((folder / "comp.src").read_text(),
                                 (folder / "comp.dat").read_text())
    procs = [r.name for r in res.runs_before]
    assert list(routines) == ["comp", *procs]
    n = 0
    for p in procs:
        motions = module.procedure(p).motions
        assert len(routines[p]) == len(motions)
        for (move, names, settings, approx), m in zip(routines[p], motions, strict=True):
            assert move == KINDS[m.kind] and names == [t.name for t in m.targets]
            assert approx == (not m.is_fine)
            if move != "PTP":
                assert float(settings["$VEL.CP"]) == pytest.approx(float(m.speed[1:]) * 1e-3)
            for t in m.targets:
                e = points[t.name]
                assert np.abs([e["X"] - t.pos_mm[0], e["Y"] - t.pos_mm[1],
                               e["Z"] - t.pos_mm[2]]).max() <= 1e-6
                R = Rotation.from_euler("ZYX", [e["A"], e["B"], e["C"]], degrees=True)
                Q = Rotation.from_quat(np.roll(t.quat, -1))  # scipy is scalar last
                assert (R.inv() * Q).magnitude() <= 1e-9
                n += 1
    assert n > 20


def test_krl_read_back_by_flexarms_reader_equals_the_targets(written):
    res, folder = written
    module = read_rapid(folder / "comp.mod")
    prog = read_krl(folder / "comp.src")
    procs = [r.name for r in res.runs_before]
    assert prog.calls == tuple(procs) and set(prog.routines) == set(procs)
    assert [prog.main_settings[f"$VEL_AXIS[{i}]"] for i in range(1, 7)] == [10.0] * 6
    n = 0
    for p in procs:
        motions = module.procedure(p).motions
        moves = prog.routines[p]
        assert [m.kind for m in moves] == [KINDS[m.kind] for m in motions]
        for move, m in zip(moves, motions, strict=True):
            assert (move.approx is None) == m.is_fine
            for target, t in zip(move.targets, m.targets, strict=True):
                pos, R = prog.pose(target)
                assert np.abs(pos - t.pos_mm).max() <= 1e-6  # 1e-9 m
                Q = Rotation.from_quat(np.roll(t.quat, -1))
                assert (Rotation.from_matrix(R).inv() * Q).magnitude() <= 1e-9
                n += 1
            if move.kind != "PTP":
                assert move.settings["$VEL.CP"] == pytest.approx(float(m.speed[1:]) * 1e-3)
        load = moves[0].settings.get("$LOAD")
        if p == "Path_30":
            assert load is None  # tool0: no payload in the program, a comment says so
        else:  # tSpindle's tload: 20 kg, centre of mass 75 mm out of the flange
            assert load["M"] == 20.0 and [load["CM"][k] for k in "XYZ"] == [0.0, 0.0, 75.0]
    assert n > 20


def test_krl_tool_is_the_programs(written):
    res, folder = written
    _, routines = parse_krl((folder / "comp.src").read_text(), (folder / "comp.dat").read_text())
    tool = routines["Line" if "Line" in routines else "Path_30"][0][2]["$TOOL"]
    z = float(re.search(r"Z ([-\d.]+)", tool).group(1))
    assert z == (150.0 if "Line" in routines else 0.0)  # tSpindle 150 mm out; tool0


def test_krl_status_and_turn_follow_the_joints(written, robot):
    res, folder = written
    points, _ = parse_krl("", (folder / "comp.dat").read_text())
    for key, (q, _cfx) in res.joints.items():
        e = next(v for k, v in points.items() if k.lower() == key)
        wrist = link_frames(robot.chain, q)[5, :3, 3]
        behind = wrist[:2] @ [np.cos(q[0]), np.sin(q[0])] < 0
        assert int(e["T"]) == sum(1 << i for i in range(6) if q[i] < 0)
        assert int(e["S"]) & 1 == behind and (int(e["S"]) >> 2) & 1 == (q[4] <= 0)
        assert (int(e["S"]) >> 1) & 1 == 1  # the usual elbow on these paths


def test_pose_csv_round_trip(written):
    res, folder = written
    procs = [r.name for r in res.runs_before]
    want = module_poses(read_rapid(folder / "comp.mod"), procs)
    got = read_poses(folder / "comp.csv")
    assert got.names == want.names
    assert np.array_equal(got.points_mm, want.points_mm) and np.array_equal(got.quats, want.quats)


@pytest.mark.parametrize("name, fmt, message", [
    ("out.txt", None, "cannot tell the program format"),
    ("out.mod", "krl", "--format krl contradicts -o out.mod"),
    ("3axis.src", None, "-o: KRL module '3axis'"),
    ("out.src", "kuka", "--format kuka: expected one of rapid, krl, csv"),
])
def test_bad_output_names(name, fmt, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        program_format(name, fmt)


def test_status_turn_from_a_template_only_where_the_joints_are_unknown(written, tmp_path):
    from dataclasses import replace

    res, _ = written
    first, second = list(res.joints)[:2]
    template = {first.upper(): (5, 7), second: (3, 9)}
    partly = replace(res, joints={k: v for k, v in res.joints.items() if k != second})
    partly.write_program(tmp_path / "t.src", template=template)
    points, _ = parse_krl("", (tmp_path / "t.dat").read_text())
    by_key = {k.lower(): (int(v["S"]), int(v["T"])) for k, v in points.items()}
    assert by_key[second] == (3, 9)  # no joints: the template's
    assert by_key[first] != (5, 7)  # the joints win
    replace(res, joints={}).write_program(tmp_path / "d.src")
    points, _ = parse_krl("", (tmp_path / "d.dat").read_text())
    assert {(int(v["S"]), int(v["T"])) for v in points.values()} == {(2, 0)}
