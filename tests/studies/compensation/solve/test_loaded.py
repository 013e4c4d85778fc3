from dataclasses import replace

import numpy as np
import pytest

from flexarm.assembly.analyses import gravity_sag as assembled_sag
from flexarm.assembly.effects import added_deflection
from flexarm.assembly.statics import joint_moments
from flexarm.robot.effects import parse_effect
from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.ik_path import TOOL0
from flexarm.robot.kinematics import jacobian, tcp_frame
from flexarm.studies.compensation.solve.loaded import deflection, law_rotations, loaded_arm
from flexarm.studies.contact.ball_bar import predict_circle, rapid_circle

from ..conftest import THESIS


@pytest.fixture(scope="module")
def setup30(robot):
    return rapid_circle(robot, read_rapid(THESIS), "Path_30", step_mm=20.0)


def _bar(setup, F):
    w = np.zeros((len(setup.points), 6))
    w[:, :3] = F * setup.bar_dirs
    return w


def test_linear_part_is_the_circle_tests_prediction(robot, arm, setup30):
    """An independent implementation: the ball-bar prediction of the circle test."""
    la = loaded_arm(robot, arm=arm, gravity=False)
    d = deflection(la, setup30.ik.q, _bar(setup30, 800.0), TOOL0)
    ref = predict_circle(arm, setup30, [800.0]).deviation[0]
    assert np.abs(d[:, :3] - ref).max() < 1e-12 * np.abs(ref).max() + 1e-18


def test_gravity_sag_is_carried_to_the_tool_point(robot, arm, setup30):
    la = loaded_arm(robot, arm=arm)
    q = setup30.ik.q
    d = deflection(la, q, np.zeros((len(q), 6)), TOOL0)
    s = assembled_sag(arm, q)
    lever = setup30.points - tcp_frame(arm.chain, q)[:, :3, 3]
    u = s[:, :3] + np.cross(s[:, 3:], lever)
    assert np.abs(d[:, :3] - u).max() < 1e-15 and np.abs(d[:, 3:] - s[:, 3:]).max() < 1e-15
    assert 1e-4 < np.abs(u[:, 2]).max() < 1e-2  # a sag of millimetres


def test_backlash_rests_on_the_gravity_flank_and_cancels_relative(robot, arm, setup30):
    q = setup30.ik.q
    w = _bar(setup30, 200.0)
    la = loaded_arm(robot, [parse_effect("backlash:j2=0.1mrad")], arm=arm)
    rot = law_rotations(la, q, w, TOOL0)
    tau = joint_moments(arm, q, w[:, :3], np.cross(
        setup30.points - tcp_frame(arm.chain, q)[:, :3, 3], w[:, :3]))[:, 1, 0]
    assert np.array_equal(rot[:, 1], 5e-5 * np.sign(tau)) and not rot[:, [0, 2, 3, 4, 5]].any()
    J = jacobian(replace(robot.chain, tool=TOOL0), q)[:, :, 1]
    plain = loaded_arm(robot, arm=arm)
    extra = deflection(la, q, w, TOOL0) - deflection(plain, q, w, TOOL0)
    assert np.abs(extra - J * rot[:, 1:2]).max() < 1e-15
    rel = loaded_arm(robot, [parse_effect("backlash:j2=0.1mrad")], arm=arm, gravity=False)
    assert not law_rotations(rel, q, w, TOOL0).any()  # no reversal: the same flank at 0 N


def test_tool_and_balancer_match_the_static_lab_model(robot, arm, setup30):
    """At the robot's own TCP and relative to the unloaded state, the tool compliance and
    the balancer add what :func:`~flexarm.assembly.effects.added_deflection` adds."""
    q = setup30.ik.q
    w = _bar(setup30, 800.0)
    effects = [parse_effect("tool:cxx=1e-7,cyy=2e-7,czz=3e-7,cxy=5e-8"),
               parse_effect("balancer:j2=2e6,s=1e6")]
    la = loaded_arm(robot, effects, arm=arm, gravity=False)
    plain = loaded_arm(robot, arm=arm, gravity=False)
    tcp = robot.chain.tool
    extra = deflection(la, q, w, tcp) - deflection(plain, q, w, tcp)
    dtau = joint_moments(arm, q, w[:, :3], gravity=False)[:, :, 0]
    ref = added_deflection(arm, effects, q, w[:, :3], dtau)
    assert np.abs(extra[:, :3] - ref).max() < 1e-12 * np.abs(ref).max()
