import numpy as np
import pytest

from flexarm.robot.formats.rapid import read_rapid
from flexarm.studies.compensation.program.program_path import program_paths
from flexarm.studies.compensation.solve.forces import (
    BallBar,
    ConstantWrench,
    TargetWrenches,
    parse_force,
    path_wrenches,
    read_target_wrenches,
    target_wrenches,
)
from flexarm.studies.compensation.solve.ik_batch import rotation_matrices
from flexarm.validation.data.formats._lines import MeasurementFileError

from ..conftest import THESIS


@pytest.mark.parametrize("text, spec", [
    ("base:fz=-300", ConstantWrench((0.0, 0.0, -300.0))),
    ("tool:fx=0.3kN,mz=2Nm", ConstantWrench((300.0, 0.0, 0.0), (0.0, 0.0, 2.0), "tool")),
    ("ballbar:800N", BallBar(800.0)),
    ("ballbar:f=400,pull", BallBar(400.0, True)),
])
def test_parse_force(text, spec):
    assert parse_force(text) == spec


@pytest.mark.parametrize("text, match", [
    ("push:800", "expected base:"), ("base:fw=3", "'fw=3' is not one of"),
    ("ballbar:1e30", "outside"), ("tool:fz=nan", "not a finite number"),
    ("ballbar:", "expected ballbar:FORCE"), ("ballbar:-5", ">= 0 N"),
])
def test_parse_force_refuses_with_one_line(text, match):
    with pytest.raises(ValueError, match=match) as exc:
        parse_force(text)
    assert "\n" not in str(exc.value)


def test_tool_frame_force_turns_with_the_tool():
    T = np.tile(np.eye(4), (2, 1, 1))
    T[1, :3, :3] = rotation_matrices([0.0, 0.0, np.pi / 2])
    w = ConstantWrench((300.0, 0.0, 0.0), (0.0, 5.0, 0.0), "tool").at(T)
    assert np.allclose(w, [[300, 0, 0, 0, 5, 0], [0, 300, 0, -5, 0, 0]], atol=1e-12)
    assert np.array_equal(ConstantWrench((1.0, 2.0, 3.0)).at(T)[1], [1, 2, 3, 0, 0, 0])


def test_ball_bar_pushes_along_the_bar():
    T = np.tile(np.eye(4), (2, 1, 1))
    T[:, :3, 3] = [[1.0, 0.2, 0.5], [1.0, -0.1, 0.9]]
    pivot = np.array([1.0, 0.0, 0.5])
    w = BallBar(800.0).at(T, pivot)
    d = T[:, :3, 3] - pivot
    assert np.allclose(np.linalg.norm(w[:, :3], axis=1), 800.0)
    assert np.allclose(np.cross(w[:, :3], d), 0.0) and np.all(np.sum(w[:, :3] * d, 1) > 0)
    assert np.allclose(BallBar(800.0, pull=True).at(T, pivot), -w)
    with pytest.raises(ValueError, match="no pivot"):
        BallBar(800.0).at(T)


def test_per_target_csv_is_read_with_units_and_interpolated_along_the_path(tmp_path, robot):
    csv = tmp_path / "forces.csv"
    csv.write_text("# milling forces\ntarget,fx_kN,fy_N,fz_N,mz_Nm\n"
                   "Target_70,0.1,0,0,1\nTarget_80,0,200,0,0\nTarget_90,0,0,300,0\n"
                   "Target_100,0,0,0,0\nTarget_110,0,0,0,4\n")
    spec = parse_force(str(csv))
    assert isinstance(spec, TargetWrenches) and spec.names[0] == "Target_70"
    assert spec.wrenches[0].tolist() == [100.0, 0, 0, 0, 0, 1.0]
    (pp,) = program_paths(robot, read_rapid(THESIS), ["Path_30"], step_mm=5)
    assert np.array_equal(target_wrenches(spec, pp), spec.wrenches)
    w = path_wrenches(spec, pp)
    assert np.array_equal(w[pp.target_samples[[0, 2, 4]]], spec.wrenches[[0, 2, 4]])
    # linear in arc length between Target_70 (sample 0) and Target_80 (its circle point)
    arc = pp.path.arc_length_mm
    i = pp.target_samples[1] // 2
    share = arc[i] / arc[pp.target_samples[1]]
    assert np.allclose(w[i], (1 - share) * spec.wrenches[0] + share * spec.wrenches[1])


def test_per_target_csv_errors_name_file_line_and_target(tmp_path):
    bad = tmp_path / "f.csv"
    bad.write_text("target,fx_N,fy_N,fz_N\nT1,1,2,x\n")
    with pytest.raises(MeasurementFileError, match=r"f.csv, line 2, column 'fz_N'"):
        read_target_wrenches(bad)
    bad.write_text("target,fx,fy_N,fz_N\nT1,1,2,3\n")
    with pytest.raises(MeasurementFileError, match="missing unit suffix"):
        read_target_wrenches(bad)
    bad.write_text("target,fx_N,fy_N,fz_N\nT1,1,2,3\nt1,0,0,0\n")
    with pytest.raises(MeasurementFileError, match="line 3.*listed twice"):
        read_target_wrenches(bad)
    spec = TargetWrenches(("T1",), np.zeros((1, 6)), "f.csv")
    with pytest.raises(ValueError, match="f.csv: no row for target 'T2'"):
        spec.of(["t1", "T2"])
