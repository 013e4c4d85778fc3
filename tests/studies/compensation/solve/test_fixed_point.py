from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import fsolve

from flexarm.robot.effects import parse_effect
from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.kinematics import tcp_frame
from flexarm.studies.compensation.program.program_path import program_paths
from flexarm.studies.compensation.solve.fixed_point import correct_targets
from flexarm.studies.compensation.solve.forces import BallBar
from flexarm.studies.compensation.solve.ik_batch import displaced, pose_errors
from flexarm.studies.compensation.solve.loaded import deflection, law_rotations, loaded_arm
from flexarm.studies.contact.ball_bar import default_pivot

from ..conftest import THESIS


@pytest.fixture(scope="module")
def case(robot, arm):
    mod = read_rapid(THESIS)
    (pp,) = program_paths(robot, mod, ["Path_40"], step_mm=5)
    la = loaded_arm(robot, [parse_effect("backlash:j2=0.1mrad"),
                            parse_effect("hardening:j3=0.5,t=400Nm")], arm=arm)
    w = BallBar(800.0).at(pp.target_frames, default_pivot(mod, "Path_40"))
    rot = law_rotations(la, pp.q, BallBar(800.0).at(pp.frames, default_pivot(mod, "Path_40")),
                        pp.tool)[pp.target_samples]
    return pp, la, w, rot


def test_the_loaded_targets_land_on_the_program(case):
    pp, la, w, rot = case
    c = correct_targets(la, pp.tool, pp.target_frames, pp.target_q, w, rot)
    assert c.is_converged.all() and c.is_reached.all() and c.iterations <= 10
    assert np.abs(c.after).max() < 1e-12
    assert 1e-3 < np.abs(c.before[:, :3]).max() < 5e-3  # millimetres before
    # the commanded frames are the joint angles' frames, shifted by the written offsets
    ch = replace(la.arm.chain, tool=pp.tool)
    assert np.abs(tcp_frame(ch, c.q) - c.frames).max() < 1e-11
    assert np.abs(pose_errors(pp.target_frames, c.frames) - c.offsets).max() < 1e-15
    # loaded by the deflection at the commanded pose, they are the programmed frames
    d = deflection(la, c.q, w, pp.tool, rot)
    assert np.abs(pose_errors(pp.target_frames, displaced(c.frames, d))).max() < 1e-12


def test_same_joint_angles_as_a_general_root_finder(case):
    """One target solved by scipy's fsolve on the joint angles: FK(q) moved by d(q) is the
    programmed frame."""
    pp, la, w, rot = case
    c = correct_targets(la, pp.tool, pp.target_frames, pp.target_q, w, rot)
    ch = replace(la.arm.chain, tool=pp.tool)
    k = 1

    def residual(q):
        T = tcp_frame(ch, q[None])
        d = deflection(la, q[None], w[k:k + 1], pp.tool, rot[k:k + 1])
        return pose_errors(pp.target_frames[k:k + 1], displaced(T, d))[0]

    q = fsolve(residual, pp.target_q[k], xtol=1e-12)
    assert np.abs(q - c.q[k]).max() < 1e-10


def test_without_load_or_gravity_nothing_moves(robot, arm, case):
    pp = case[0]
    la = loaded_arm(robot, arm=arm, gravity=False)
    c = correct_targets(la, pp.tool, pp.target_frames, pp.target_q,
                        np.zeros((len(pp.targets), 6)))
    assert not c.offsets.any() and c.iterations == 1
