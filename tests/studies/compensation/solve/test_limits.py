from dataclasses import replace

import numpy as np
import pytest

from flexarm.robot.effects import parse_effect
from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.kinematics import jacobian
from flexarm.studies.compensation.program.program_path import program_paths
from flexarm.studies.compensation.solve.forces import BallBar
from flexarm.studies.compensation.solve.limits import (
    Limits,
    law_jumps,
    limit_hits,
    near_singular,
    scaled_condition,
)
from flexarm.studies.compensation.solve.loaded import joint_torques, loaded_arm
from flexarm.studies.contact.ball_bar import default_pivot

from ..conftest import THESIS


@pytest.fixture(scope="module")
def path30(robot):
    mod = read_rapid(THESIS)
    (pp,) = program_paths(robot, mod, ["Path_30"], step_mm=2)
    return pp, BallBar(400.0).at(pp.frames, default_pivot(mod, "Path_30"))


def test_a_backlash_whose_torque_reverses_is_found_where_it_reverses(robot, arm, path30):
    """Joint 1 carries no weight: the bar's push turns its torque round twice a turn."""
    pp, w = path30
    la = loaded_arm(robot, [parse_effect("backlash:j1=0.2mrad")], arm=arm)
    jumps = law_jumps(la, pp, w)
    tau = joint_torques(la, pp.q, w, pp.tool)[:, 0]
    flips = np.flatnonzero(np.sign(tau[1:]) != np.sign(tau[:-1])) + 1
    assert len(jumps) == len(flips) >= 2
    assert sorted({j.motion for j in jumps}) == sorted(set(pp.path.segments[flips].tolist()))
    J = jacobian(replace(robot.chain, tool=pp.tool), pp.q)
    for jump, i in zip(jumps, flips, strict=True):
        assert (jump.joint, jump.kind, jump.jump) == (0, "backlash", pytest.approx(2e-4))
        assert jump.tcp_jump == pytest.approx(2e-4 * np.linalg.norm(J[i, :3, 0]), rel=1e-2)
        rows = pp.path.segments == jump.motion
        t = tau[rows]
        assert jump.preload == pytest.approx(min(t.max(), -t.min()))
        # the preload force adds torque of the motion's majority sign, of that size
        got = J[i, :3, 0] @ np.asarray(jump.preload_force)
        assert got == pytest.approx(np.sign(t.mean()) * jump.preload, rel=1e-3)
        assert "joint 1 backlash switches in MoveC via" in jump.text()
    mask = Limits(tuple(jumps)).jump_mask("Path_30", pp.path.segments)
    assert mask[flips].all() and not Limits(tuple(jumps)).jump_mask("Path_40", [0, 1]).any()


def test_gravity_keeps_joint_2_on_one_flank(robot, arm, path30):
    pp, w = path30
    la = loaded_arm(robot, [parse_effect("backlash:j2=0.1mrad"),
                            parse_effect("hardening:j2=0.5,t=400Nm")], arm=arm)
    assert law_jumps(la, pp, w) == []


def test_a_hysteresis_reversed_beyond_its_friction_jumps(robot, arm, path30):
    pp, w = path30
    big = loaded_arm(robot, [parse_effect("hysteresis:j1=0.1mrad,r=20Nm")], arm=arm)
    small = loaded_arm(robot, [parse_effect("hysteresis:j1=0.1mrad,r=5000Nm")], arm=arm)
    jumps = law_jumps(big, pp, w)
    assert jumps and {j.kind for j in jumps} == {"hysteresis"}
    assert law_jumps(small, pp, w) == []


def test_limit_hits_name_the_joint_and_the_reach():
    lower, upper = -np.ones(6), np.ones(6)
    q = np.zeros((3, 6))
    q[1, 2] = 1.2
    hits = limit_hits("P", ["a", "b", "c"], q, np.array([True, True, False]), lower, upper)
    assert [(h.target, h.kind, h.joint) for h in hits] == [("b", "limit", 2), ("c", "reach", -1)]
    assert "joint 3 at 68.75 deg passes its limit 57.30 deg" in hits[0].text()
    assert "out of the arm's reach" in hits[1].text()


def test_singular_wrist_is_reported(robot):
    q = np.radians([[0, 40, 0, 20, 50, 10], [0, 40, 0, 20, 0.05, 10]])
    cond = scaled_condition(robot.chain, q)
    assert cond[0] < 20 and cond[1] > 1000
    found = near_singular("P", robot.chain, ["ok", "wrist"], q, np.full((2, 6), 1e-3))
    assert [s.target for s in found] == ["wrist"] and "near a singularity" in found[0].text()
