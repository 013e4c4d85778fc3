import numpy as np
import pytest

from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.paths import sample_procedure
from flexarm.studies.compensation.program.densify import densify
from flexarm.studies.compensation.program.program_path import program_paths

from ..conftest import MILLING, THESIS


@pytest.fixture(scope="module")
def split(robot, tmp_path_factory):
    mod = read_rapid(THESIS)
    pps = program_paths(robot, mod, ["main", "Path_30", "Path_50"], step_mm=5)
    text, notes = densify(THESIS.read_text(), mod, pps, robot.chain, 150.0)
    path = tmp_path_factory.mktemp("split") / "split.mod"
    path.write_text(text)
    return mod, read_rapid(path), notes


def test_long_arcs_become_sub_arcs_of_the_same_circle(split):
    mod, back, notes = split
    p30 = back.procedures["Path_30"].motions
    assert [m.kind for m in p30] == ["MoveJ"] + ["MoveC"] * 8
    assert {(m.speed, m.zone, m.tool, m.wobj) for m in p30} == {("v10", "fine", "tool0", "wobj0")}
    assert [m.to_point.name for m in p30[1:5]] == ["Target_90_1", "Target_90_2", "Target_90_3",
                                                  "Target_90"]
    centre = np.array([1333.34, 47.78, 588.13])
    for m in p30[1:]:
        for t in m.targets:
            assert abs(np.linalg.norm(t.pos_mm - centre) - 155.0) < 2e-6
    new = sample_procedure(back.procedures["Path_30"], step_mm=1.0).points_mm
    assert np.abs(np.linalg.norm(new - centre, axis=1) - 155.0).max() < 2e-6  # the same circle
    assert np.abs(new[:, 2] - centre[2]).max() < 1e-9
    assert len(notes) == 6 and notes[0].startswith("main: MoveC via Target_180 to Target_190")


def test_shared_motions_share_their_new_targets_and_the_rest_is_kept(split):
    mod, back, _ = split
    main = [t.name for m in back.procedures["main"].motions for t in m.targets]
    p50 = [t.name for m in back.procedures["Path_50"].motions for t in m.targets]
    assert main == p50
    assert [m.kind for m in back.procedures["Path_10"].motions] == ["MoveL", "MoveC", "MoveC"]
    assert set(mod.targets) < set(back.targets)
    assert len(back.targets) == len(mod.targets) + 2 * 7 + 7 + 5  # 4, 4; 4, 3 sub-arcs


def test_lines_split_and_short_motions_stay(robot):
    mod = read_rapid(MILLING)
    pps = program_paths(robot, mod, step_mm=2)
    text, notes = densify(MILLING.read_text(), mod, pps, robot.chain, 100.0)
    assert notes == ["Line: MoveL to mill_20 (line 17) split in 3 (100.0 mm each)",
                     "Pocket: MoveL to mill_40 (line 21) split in 2 (100.0 mm each)",
                     "Pocket: MoveL to mill_70 (line 23) split in 2 (90.0 mm each)"]
    assert "        MoveL mill_20_1,v20,fine,tSpindle\\WObj:=wobj0;\n" \
           "        MoveL mill_20_2,v20,fine,tSpindle\\WObj:=wobj0;\n" \
           "        MoveL mill_20,v20,fine,tSpindle\\WObj:=wobj0;" in text
    with pytest.raises(ValueError, match="split length must be > 0 mm"):
        densify(text, mod, pps, robot.chain, 0.0)
