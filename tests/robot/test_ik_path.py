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
