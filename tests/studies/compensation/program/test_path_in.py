"""A CSV of poses as the program: the compensated poses are the input moved by exactly the
predicted offsets (1e-9 m), whatever the output (CSV of poses, RAPID, KUKA KRL read back
by flexarm's reader), and bad files are one line naming file and line."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from flexarm.fe.errors import ReadError
from flexarm.robot.formats.krl_read import read_krl
from flexarm.robot.formats.poses_csv import read_poses
from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.paths import sample_procedure
from flexarm.studies.compensation import compensate
from flexarm.studies.compensation.program.path_in import poses_module, read_program

from ..conftest import THESIS

#: A milling pass of 21 poses 15 mm apart, tool0 pointing down (quaternion 0,0,1,0).
X = np.linspace(1100.0, 1400.0, 21)
Y = -150.0 + 20.0 * np.sin(X / 50.0)
DOWN = (0.0, 0.0, 1.0, 0.0)
FORMS = {
    "quaternion": ("target,x_mm,y_mm,z_mm,qw,qx,qy,qz",
                   lambda k, x, y: f"cut_{k},{x:.6f},{y:.6f},500,0,0,1,0", None),
    "angles": ("x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg",
               lambda k, x, y: f"{x:.6f},{y:.6f},500,0,180,0", None),
    "path csv": ("step,x_mm,y_mm,z_mm,f_N", lambda k, x, y: f"{k},{x:.6f},{y:.6f},500,300",
                 DOWN),
}


def _csv(folder, form):
    head, row, _ = FORMS[form]
    path = folder / "pass.csv"
    rows = [row(k, x, y) for k, (x, y) in enumerate(zip(X, Y, strict=True))]
    path.write_text("# a milling pass\n" + head + "\n" + "".join(r + "\n" for r in rows))
    return path


@pytest.fixture(scope="module", params=list(FORMS))
def compensated(request, robot, arm, tmp_path_factory):
    """(form, folder, input positions [mm], result) with the outputs written."""
    folder = tmp_path_factory.mktemp(request.param.replace(" ", "_"))
    path = _csv(folder, request.param)
    res = compensate(path, robot, "tool:fx=300", arm=arm, step_mm=5,
                     orientation=FORMS[request.param][2])
    for name in ("out.csv", "out.mod", "out.src"):
        res.write_program(folder / name)
    P = np.c_[np.round(X, 6), np.round(Y, 6), np.full(len(X), 500.0)]
    return request.param, folder, P, res


def test_the_poses_move_by_exactly_the_predicted_offsets(compensated):
    form, folder, P, res = compensated
    got = read_poses(folder / "out.csv")
    want = {"quaternion": [f"cut_{k}" for k in range(21)],
            "path csv": [f"p{k}" for k in range(21)]}.get(form, [f"p{k + 1}" for k in range(21)])
    assert list(got.names) == want == [s.name for s in res.shifts]
    shift_mm = np.array([s.shift[:3] for s in res.shifts]) * 1e3
    assert np.abs(got.points_mm - P - shift_mm).max() <= 1e-6  # 1e-9 m
    assert 0.2 < np.linalg.norm(shift_mm, axis=1).max() < 2.0  # a real shift, ~0.7 mm
    # the RAPID output: the same numbers, one MoveJ then MoveL through them
    module = read_rapid(folder / "out.mod")
    motions = module.procedures["pass"].motions
    assert [m.kind for m in motions] == ["MoveJ"] + ["MoveL"] * 20
    assert np.array_equal(np.array([m.to_point.pos_mm for m in motions]), got.points_mm)
    # its unloaded path runs through the shifted poses
    path = sample_procedure(module.procedures["pass"], step_mm=5)
    ends = np.flatnonzero(np.r_[path.segments[1:] != path.segments[:-1], True])
    assert np.abs(path.points_mm[ends] - P - shift_mm).max() <= 1e-6


def test_the_compensated_csv_read_as_a_program_keeps_its_procedure(compensated, robot):
    _form, folder, _P, res = compensated
    assert "# procedure: pass" in (folder / "out.csv").read_text()
    _text, _enc, module = read_program(folder / "out.csv", robot)
    assert list(module.procedures) == ["pass"]  # what lab --reference pass.csv pairs it with
    moves = module.procedures["pass"].motions
    got = np.array([m.to_point.pos_mm for m in moves])
    assert np.abs(got - read_poses(folder / "out.csv").points_mm).max() == 0.0
    assert len(moves) == len(res.shifts)


def test_krl_read_back_by_flexarms_reader_holds_the_same_poses(compensated):
    _form, folder, _P, _res = compensated
    poses = read_poses(folder / "out.csv")
    prog = read_krl(folder / "out.src")
    moves = prog.routines["pass"]
    assert [m.kind for m in moves] == ["PTP"] + ["LIN"] * 20
    for m, name, p, q in zip(moves, poses.names, poses.points_mm, poses.quats, strict=True):
        assert m.targets == (name,)
        pos, R = prog.pose(name)
        assert np.abs(pos - p).max() <= 1e-6  # mm
        Q = Rotation.from_quat(np.roll(q, -1))
        assert (Rotation.from_matrix(R).inv() * Q).magnitude() <= 1e-9
    assert moves[1].settings["$VEL.CP"] == 0.1 and moves[1].approx == "C_DIS"
    assert prog.main_settings["$VEL_AXIS[1]"] == 10.0 and prog.calls == ("pass",)


def test_compensation_of_the_csv_cuts_the_predicted_deviation(compensated):
    _form, _folder, _P, res = compensated
    (before,), (after,) = res.runs_before, res.runs_after
    assert before.peak > 0.5e-3 and after.peak < before.peak / 100


ERRORS = [
    ("x_mm,y_mm,z_mm\n1200,0,500\n", None, "pass.csv: positions only (x, y, z): give the "
     "tool orientation"),
    ("x_mm,y_mm,z_mm,qw,qx\n1200,0,500,1,0\n", None, "pass.csv, line 1: give all of qw, qx, "
     "qy, qz or none of them"),
    ("x_mm,y_mm,z_mm,qw,qx,qy,qz,rx_deg,ry_deg,rz_deg\n1200,0,500,0,0,1,0,0,180,0\n", None,
     "pass.csv, line 1: give the orientation once"),
    ("x_mm,y_mm,z_mm,qw,qx,qy,qz\n1200,0,500,0,0,1,0\n1200,10,500,0,0,0.9,0\n", None,
     "pass.csv, line 3, column 'qw': qw, qx, qy, qz is not a unit quaternion (|q| = 0.9)"),
    ("target,x_mm,y_mm,z_mm\n1st,1200,0,500\n", DOWN, "pass.csv, line 2, column 'target': "
     "'1st' is not a RAPID name"),
    ("target,x_mm,y_mm,z_mm\na,1200,0,500\nA,1210,0,500\n", DOWN, "pass.csv, line 3, column "
     "'target': target 'A' is listed twice"),
    ("# far\nx_mm,y_mm,z_mm\n1200,0,500\n5000,0,500\n", DOWN, "pass.csv, line 4: target p2 at "
     "(5000.0, 0.0, 500.0) mm is out of the arm's reach"),
    ("x_mm,y_mm,z_mm,speed\n1200,0,500,3\n", DOWN, "pass.csv, line 1, column 'speed': unknown "
     "column"),
    ("x_mm,y_mm,z_mm\n1200,0,500\n", (0, 0, 2, 0), "--orientation 0,0,2,0: expected a unit "
     "quaternion"),
]


@pytest.mark.parametrize("text, orientation, message", ERRORS)
def test_bad_pose_files_are_one_line_naming_file_and_line(tmp_path, robot, text, orientation,
                                                         message):
    path = tmp_path / "pass.csv"
    path.write_text(text)
    with pytest.raises((ValueError, ReadError)) as info:
        poses_module(path, robot, orientation=orientation)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_an_orientation_for_a_rapid_module_is_refused(robot):
    with pytest.raises(ValueError, match="--orientation goes with a CSV of positions"):
        compensate(THESIS, robot, "tool:fx=300", orientation=DOWN)
