import numpy as np
import pytest

from flexarm.robot.ik_path import TOOL0, ik_conf, ik_path, rapid_conf, target_frames
from flexarm.robot.paths import sample_procedure


def _solve(demo_robot, module, name, tool="tool0", step=10.0):
    proc = module.procedures[name]
    path = sample_procedure(proc, step_mm=step)
    return path, ik_path(demo_robot.chain, path, [m.to_point.conf for m in proc.motions],
                         demo_robot.lower, demo_robot.upper, tool=tool)


@pytest.mark.parametrize("tool", ["tool0", "robot"])
def test_path30_reachable_with_conf_and_round_trip(demo_robot, module, tool):
    path, sol = _solve(demo_robot, module, "Path_30", tool)
    # every target of Path_30 (70..110) reached with its programmed conf [0, 1, -1, 1]
    assert sol.is_conf_met.all()
    assert sol.conf_reached.tolist() == [[0, 1, -1, 1]] * 3
    err = np.abs(sol.frames[:, :3, 3] - path.points_m).max()
    assert err < 1e-9
    R = target_frames(path.points_mm, path.quats)[:, :3, :3]
    assert np.abs(sol.frames[:, :3, :3] - R).max() < 1e-9
    assert np.all(sol.q >= demo_robot.lower) and np.all(sol.q <= demo_robot.upper)
    # continuity: no jump between samples
    assert np.abs(np.diff(sol.q, axis=0)).max() < np.radians(10)


def test_tool0_is_the_flange_and_robot_tcp_is_150mm_out(demo_robot, module):
    _, s0 = _solve(demo_robot, module, "Path_30", "tool0")
    assert np.allclose(s0.tool, TOOL0)
    _, s1 = _solve(demo_robot, module, "Path_30", "robot")
    assert np.allclose(s1.tool[:3, 3], [0.15, 0.0, 0.0])
    # different tool -> different joint angles for the same programmed positions
    assert np.abs(s0.q - s1.q).max() > np.radians(1)


def test_every_target_conf_decodes_consistently(demo_robot, module):
    from dataclasses import replace

    ch = replace(demo_robot.chain, tool=TOOL0)
    for name in ("Target_70", "Target_120", "Target_170", "Target_50", "Target_20"):
        t = module.targets[name]
        T = target_frames(t.pos_mm, t.quat)[0]
        q = ik_conf(ch, T, t.conf, demo_robot.lower, demo_robot.upper)
        assert q is not None, name
        assert rapid_conf(ch, q).tolist() == list(t.conf)


def test_path60_inconsistent_conf_falls_back_to_continuity(demo_robot, module):
    path, sol = _solve(demo_robot, module, "Path_60")
    assert not sol.is_conf_met.all() and sol.notes
    assert np.abs(sol.frames[:, :3, 3] - path.points_m).max() < 1e-9
    assert np.abs(np.diff(sol.q, axis=0)).max() < np.radians(15)


def _moved(tmp_path, target: str, x_mm: float):
    """The thesis module with ``target``'s x moved to ``x_mm``; (path, module, line of the
    first motion to ``target``)."""
    import re
    from importlib.resources import files

    from flexarm.robot.formats.rapid import read_rapid

    text = (files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod").read_text()
    text, n = re.subn(rf"({target}:=\[\[)[-0-9.]+", rf"\g<1>{x_mm}", text)
    assert n == 1
    path = tmp_path / "moved.mod"
    path.write_text(text)
    return path, read_rapid(path)


@pytest.mark.parametrize(("target", "proc", "kind", "names", "is_target"), [
    # the procedure starts at the far target itself
    ("Target_50", "Path_10", "MoveL", "MoveL to Target_50", True),
    # a linear move towards it leaves the reach on the way
    ("Target_50", "Path_20", "MoveL", "MoveL to Target_50", False),
    # a circle through a far CirPoint
    ("Target_80", "Path_30", "MoveC", "MoveC via Target_80 to Target_90", False),
])
def test_unreachable_target_names_motion_and_line(demo_robot, tmp_path, target, proc, kind,
                                                  names, is_target):
    from flexarm.robot.ik_path import UnreachableTargetError

    file, mod = _moved(tmp_path, target, 8800.0)
    p = mod.procedures[proc]
    motion = next(m for m in p.motions if target in [t.name for t in m.targets])
    with pytest.raises(UnreachableTargetError) as err:
        _solve(demo_robot, mod, proc)
    msg = str(err.value)
    assert msg.startswith(f"{names} (line {motion.line}): ") and "\n" not in msg
    assert err.value.line == motion.line
    # the line is the instruction's line in the file
    assert kind in file.read_text().splitlines()[motion.line - 1]
    assert ("its target at (8800.0," in msg) == is_target
    assert is_target or "the target is at (" in msg
    # the sample it names is really out of reach: 2.55 m is the demo arm's reach at most
    dist = float(msg.split(" m from the base")[0].rsplit(", ", 1)[1])
    assert dist > 2.0


def test_reachable_again_when_moved_back(demo_robot, tmp_path):
    """The same edit with the original coordinate solves (the check is not a false alarm)."""
    _, mod = _moved(tmp_path, "Target_50", 883.561)
    _, sol = _solve(demo_robot, mod, "Path_10")
    assert sol.q.shape[1] == 6
