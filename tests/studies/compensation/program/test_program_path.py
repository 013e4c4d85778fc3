import numpy as np
import pytest

from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.ik_path import TOOL0, ik_path
from flexarm.robot.kinematics import tcp_frame
from flexarm.studies.compensation.program.program_path import procedure_tool, program_paths

from ..conftest import MILLING, THESIS


def test_paths_match_the_sequential_ik_and_the_targets(robot):
    mod = read_rapid(THESIS)
    pps = program_paths(robot, mod, ["Path_30", "Path_40"], step_mm=5)
    for pp in pps:
        proc = mod.procedures[pp.name]
        ref = ik_path(robot.chain, pp.path, [m.to_point.conf for m in proc.motions],
                      robot.lower, robot.upper)
        assert np.abs(pp.q - ref.q).max() < 1e-9
        from dataclasses import replace

        ch = replace(robot.chain, tool=pp.tool)
        assert np.abs(tcp_frame(ch, pp.target_q) - pp.target_frames).max() < 1e-11
        assert pp.is_named.all() and len(pp.targets) == 5
    # the circle point sits on its motion; the destinations end them
    pp = pps[0]
    assert pp.targets == ("Target_70", "Target_80", "Target_90", "Target_100", "Target_110")
    assert pp.target_samples[0] == 0 and pp.target_samples[-1] == pp.path.n_points - 1
    assert np.linalg.norm(pp.points[pp.target_samples[1]] * 1e3 - [1333.34, 202.78, 588.13]) < 3


def test_tool_is_the_modules_tooldata(robot):
    mod = read_rapid(MILLING)
    T = procedure_tool(mod, "Line", robot.chain)
    spindle = np.eye(4)
    spindle[2, 3] = 0.15
    assert np.allclose(T, TOOL0 @ spindle)
    assert np.array_equal(procedure_tool(read_rapid(THESIS), "Path_30", robot.chain), TOOL0)
    assert np.array_equal(procedure_tool(mod, "Line", robot.chain, "robot"), robot.chain.tool)


def _edited(tmp_path, old, new):
    path = tmp_path / "m.mod"
    path.write_text(MILLING.read_text().replace(old, new))
    return path


def test_refuses_an_undeclared_tool_and_mixed_tools(tmp_path, robot):
    path = _edited(tmp_path, ",tSpindle\\WObj", ",tOther\\WObj")
    with pytest.raises(ValueError, match=f"{path}: Line: tool 'tOther' is not a tooldata"):
        program_paths(robot, read_rapid(path), ["Line"], step_mm=10)
    path = _edited(tmp_path, "mill_20,v20,fine,tSpindle", "mill_20,v20,fine,tool0")
    with pytest.raises(ValueError, match="Line uses several tools \\(tool0, tSpindle\\)"):
        program_paths(robot, read_rapid(path), ["Line"], step_mm=10)


def test_refuses_another_work_object_naming_the_line(tmp_path, robot):
    path = _edited(tmp_path, "mill_20,v20,fine,tSpindle\\WObj:=wobj0",
                   "mill_20,v20,fine,tSpindle\\WObj:=wTable")
    path.write_text(path.read_text().replace(
        "    PERS tooldata", '    PERS wobjdata wTable:=[FALSE,TRUE,"",[[0,0,0],[1,0,0,0]],'
        "[[0,0,0],[1,0,0,0]]];\n    PERS tooldata"))
    with pytest.raises(ValueError, match=f"{path}, line 18: work object 'wTable'"):
        program_paths(robot, read_rapid(path), ["Line"], step_mm=10)


def test_unknown_procedure_is_a_value_error(robot):
    with pytest.raises(ValueError, match="no procedure 'Path_99'"):
        program_paths(robot, read_rapid(THESIS), ["Path_99"])
