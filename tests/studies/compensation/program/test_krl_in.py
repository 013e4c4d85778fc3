"""A KRL program as the module flexarm runs: the thesis's procedures written as KRL run
the same joint angles as the RAPID module, ``$BASE``, ``$TOOL``, speeds and zones of a
hand-written program land where KRL puts them, and status and turn pick the branch."""

from dataclasses import replace

import numpy as np
import pytest

from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.formats.krl import abc_from_matrix, status_turn, write_krl
from flexarm.robot.formats.krl_read import matrix_from_abc
from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.ik_path import TOOL0, rapid_conf
from flexarm.robot.kinematics import tcp_frame
from flexarm.studies.compensation.program.krl_in import krl_module
from flexarm.studies.compensation.program.program_path import program_paths
from flexarm.studies.contact.loaded_circle import THESIS_RAPID

PROCS = ["Path_10", "Path_20", "Path_30", "Path_40", "Path_50"]
DOWN = np.diag([-1.0, 1.0, -1.0])


@pytest.fixture(scope="module")
def robot():
    return load_demo_robot()


def test_the_thesis_as_krl_runs_the_joints_of_the_rapid_module(robot, tmp_path):
    module = read_rapid(THESIS_RAPID)
    pps = program_paths(robot, module, PROCS, step_mm=10)
    status = {}
    for pp in pps:
        ch = replace(robot.chain, tool=pp.tool)
        S, T = status_turn(np.degrees(pp.target_q), rapid_conf(ch, pp.target_q)[:, 3])
        status.update({n.lower(): (int(s), int(t))
                       for n, s, t in zip(pp.targets, S, T, strict=True)})
    write_krl(tmp_path / "thesis.src", module, PROCS, status=status)
    _text, krl = krl_module(tmp_path / "thesis.src", robot)
    for a, b in zip(pps, program_paths(robot, krl, PROCS, step_mm=10), strict=True):
        assert a.name == b.name and a.q.shape == b.q.shape
        assert np.abs(a.q - b.q).max() < 1e-9  # rad
        assert np.abs(a.frames - b.frames).max() < 1e-9  # m


def _e6pos(P, R, extra=""):
    a, b, c = abc_from_matrix(R)
    x, y, z = P
    return f"{{X {x!r},Y {y!r},Z {z!r},A {a!r},B {b!r},C {c!r}{extra}}}"


def test_base_tool_speeds_and_zones_of_a_hand_written_program(robot, tmp_path):
    B = np.eye(4)  # $BASE: 90 deg about z, then shifted [mm]
    B[:3, :3], B[:3, 3] = matrix_from_abc([90.0, 0.0, 0.0]), [100.0, -50.0, 20.0]
    want = np.array([[1200, 100, 600], [1200, -100, 600], [1250, -150, 600],
                     [1300, -100, 600], [1350, -150, 600]], dtype=float)  # robot base [mm]
    local = (want - B[:3, 3]) @ B[:3, :3]  # the same points in $BASE
    R = B[:3, :3].T @ DOWN
    dat = ["DEFDAT cell"] + [f"DECL E6POS p{k}={_e6pos(local[k], R)}" for k in (0, 1, 3, 4)]
    (tmp_path / "cell.dat").write_text("\n".join([*dat, "ENDDAT", ""]))
    (tmp_path / "cell.src").write_text("\n".join([
        "DEF cell( )", "BAS (#INITMOV,0 )", "BAS (#VEL_PTP,30 )",
        "$BASE = {X 100.0,Y -50.0,Z 20.0,A 90.0,B 0.0,C 0.0}",
        "$TOOL = {X 0.0,Y 0.0,Z 150.0,A 0.0,B 0.0,C 0.0}",
        "$LOAD = {M 12.5,CM {X 0.0,Y 0.0,Z 60.0,A 0.0,B 0.0,C 0.0},J {X 0.1,Y 0.1,Z 0.05}}",
        "PTP p0", "$VEL.CP = 0.25", "$APO.CDIS = 2.5", "LIN p1 C_DIS",
        f"LIN {_e6pos(local[2], R)} C_DIS", "$VEL.CP = 0.05", "CIRC p3, p4", "END", ""]))
    _text, module = krl_module(tmp_path / "cell.src", robot)
    moves = module.procedure("cell").motions
    assert [m.kind for m in moves] == ["MoveJ", "MoveL", "MoveL", "MoveC"]
    assert [m.line for m in moves] == [7, 10, 11, 13]
    # RAPID has no v250: v100\V:=250 [mm/s]; nor a 2.5 mm zone: z1\Z:=2.5
    assert [m.speed for m in moves] == ["v100", "v100", "v100", "v50"]
    assert dict(moves[1].options) == dict(moves[2].options) == {"V": "250", "Z": "2.5"}
    assert [m.zone for m in moves] == ["fine", "z1", "z1", "fine"]
    tool = module.data["krl_tool1"].value
    assert tool[1][0] == (0.0, 0.0, 150.0) and tool[2][0] == 12.5
    (pp,) = program_paths(robot, module, step_mm=5)
    assert np.abs(pp.target_frames[:, :3, 3] * 1e3 - want[[0, 1, 2, 3, 4]]).max() < 1e-9
    assert np.abs(pp.target_frames[:, :3, :3] - DOWN).max() < 1e-12
    assert pp.is_named.tolist() == [True, True, False, True, True]  # the inline target
    tcp = TOOL0[:3, :3] @ [0.0, 0.0, 0.15]  # 150 mm along the flange's z [m]
    assert np.abs(pp.tool[:3, 3] - tcp).max() < 1e-15


#: The branches of the pose below within the demo arm's limits: (S, T) -> joint 4 [deg];
#: T 0 turns joint 4 from -9.6 to 350.4 deg, T 16 joint 6 from -134.4 to 225.6 deg.
BRANCHES = {(2, 8): -9.6, (2, 0): 350.4, (6, 48): 170.4, (6, 16): 170.4, (1, 7): 174.3,
            (5, 63): -5.7}


@pytest.mark.parametrize("s, t", list(BRANCHES))
def test_status_and_turn_pick_the_branch(robot, tmp_path, s, t):
    R = matrix_from_abc([150.0, 20.0, 170.0])
    (tmp_path / "st.dat").write_text(
        f"DEFDAT st\nDECL E6POS p={_e6pos([1200.0, 200.0, 800.0], R, f',S {s},T {t}')}\n"
        "ENDDAT\n")
    (tmp_path / "st.src").write_text("DEF st( )\nPTP p\nEND\n")
    _text, module = krl_module(tmp_path / "st.src", robot)
    (pp,) = program_paths(robot, module, step_mm=5)
    q = pp.target_q[0]
    ch = replace(robot.chain, tool=pp.tool)
    S, T = status_turn(np.degrees(q), rapid_conf(ch, q)[3])
    assert (int(S), int(T)) == (s, t)
    assert np.degrees(q[3]) == pytest.approx(BRANCHES[s, t], abs=0.05)
    F = tcp_frame(ch, q)
    assert np.abs(F[:3, :3] - R).max() < 1e-9
    assert np.abs(F[:3, 3] - [1.2, 0.2, 0.8]).max() < 1e-9
