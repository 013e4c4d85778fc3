"""The plain CSV of poses: write then read gives the module's targets exactly."""

from importlib.resources import files

import numpy as np
import pytest

from flexarm.fe.errors import ReadError
from flexarm.robot.formats.poses_csv import Poses, module_poses, read_poses, write_poses
from flexarm.robot.formats.rapid import read_rapid

THESIS = files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod"


def test_round_trip_of_every_target_of_the_thesis_module(tmp_path):
    poses = module_poses(read_rapid(THESIS))
    path = write_poses(tmp_path / "p.csv", poses, ["from the thesis"])
    back = read_poses(path)
    assert back.names == poses.names and len(back.names) == 24  # each target once
    assert np.array_equal(back.points_mm, poses.points_mm)
    assert np.array_equal(back.quats, poses.quats)
    assert path.read_text().splitlines()[1] == "# from the thesis"


def test_columns_in_any_order(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text("qz,qy,qx,qw,z_mm,y_mm,x_mm,target,note\n0,1,0,0,3,2,1,a,x\n")
    p = read_poses(path)
    assert p.names == ("a",) and p.points_mm.tolist() == [[1, 2, 3]]
    assert p.quats.tolist() == [[0, 0, 1, 0]]


@pytest.mark.parametrize("text, message", [
    ("target,x_mm,y_mm,z_mm,qw\n", "line 1: missing column(s) qx, qy, qz"),
    ("# c\ntarget,x_mm,y_mm,z_mm,qw,qx,qy,qz\np,1,2,x,1,0,0,0\n", "line 3: expected 8 values"),
    ("target,x_mm,y_mm,z_mm,qw,qx,qy,qz\np,1,2,nan,1,0,0,0\n", "line 2: positions must be"),
    ("target,x_mm,y_mm,z_mm,qw,qx,qy,qz\np,1,2,3,0,0,0,0\n", "quaternion non-zero"),
    ("", "no header row"),
])
def test_bad_files_name_file_and_line(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ReadError, match="bad.csv") as info:
        read_poses(path)
    assert message in str(info.value)


def test_poses_need_a_row_per_name():
    with pytest.raises(ValueError, match="one row per name"):
        Poses(("a", "b"), [[0, 0, 0]], [[1, 0, 0, 0], [1, 0, 0, 0]])
