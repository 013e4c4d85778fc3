"""KRL programs as a real cell has them, run on the demo arm: a program split over several
files of its folder runs the path of the same program in one file (1e-12 m), and the
controller's tool and base tables (``BAS (#TOOL, 3)``, ``BAS (#BASE, 2)``) the path of
the same frames written as ``$TOOL``, ``$LOAD`` and ``$BASE``."""

import numpy as np
import pytest

from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.formats.krl import abc_from_matrix
from flexarm.robot.formats.krl_read import matrix_from_abc
from flexarm.studies.compensation.program.krl_in import krl_module
from flexarm.studies.compensation.program.program_path import program_paths

from ....robot.formats.test_krl_calls import split_program, write
from ....robot.formats.test_krl_config import BASE2, CONFIG, LOAD3, TOOL3, krl

DOWN = np.diag([-1.0, 1.0, -1.0])


@pytest.fixture(scope="module")
def robot():
    return load_demo_robot()


def _paths(robot, src, config=None):
    text, module = krl_module(src, robot, config=config)
    return text, program_paths(robot, module, step_mm=5)


def test_a_program_split_over_files_runs_the_path_of_the_one_file_program(robot, tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    text, split = _paths(robot, split_program(tmp_path / "a"))
    one = tmp_path / "b" / "main.src"
    for suffix in (".src", ".dat"):  # the same program, the called routines pasted in
        parts = [(tmp_path / "a" / f"{m}{suffix}").read_text() for m in ("main", "approach")]
        if suffix == ".src":
            lib = (tmp_path / "a" / "lib.src").read_text().replace("GLOBAL DEF", "DEF")
            one.write_text(parts[0] + parts[1].replace("&ACCESS RVP\n", "") +
                           lib.split("END\n", 1)[1])
        else:
            body = [x for p in parts for x in p.splitlines()
                    if x.startswith("DECL")]
            one.with_suffix(".dat").write_text("\n".join(["DEFDAT main", *body, "ENDDAT", ""])
                                               .replace("DECL GLOBAL", "DECL"))
    _t, whole = _paths(robot, one)
    (a,), (b,) = split, whole
    assert a.name == b.name == "main" and a.q.shape == b.q.shape and len(a.targets) == 5
    assert np.abs(a.frames[:, :3, 3] - b.frames[:, :3, 3]).max() <= 1e-12  # m
    assert np.abs(a.frames[:, :3, :3] - b.frames[:, :3, :3]).max() <= 1e-12
    assert np.abs(a.q - b.q).max() <= 1e-12  # rad
    move = next(x for x in text.splitlines() if "MoveL p1," in x)
    assert move.endswith("! approach.src, line 4")  # where it came from
    assert "! flexarm: also read approach.src" in text


def test_the_controllers_tool_and_base_tables_run_the_frames_written_out(robot, tmp_path):
    config = tmp_path / "$config.dat"
    config.write_text("\n".join([*CONFIG, ""]))
    B = np.eye(4)
    B[:3, :3] = matrix_from_abc([BASE2[k] for k in "ABC"])
    B[:3, 3] = [BASE2[k] for k in "XYZ"]
    want = np.array([[1200, 100, 600], [1200, -100, 600], [1300, -100, 650]], dtype=float)
    local = (want - B[:3, 3]) @ B[:3, :3]  # the points in BASE_DATA[2] [mm]
    a, b, c = abc_from_matrix(B[:3, :3].T @ DOWN)
    dat = [f"DECL E6POS p{k}={{X {x!r},Y {y!r},Z {z!r},A {a!r},B {b!r},C {c!r}}}"
           for k, (x, y, z) in enumerate(local)]
    moves = ["PTP p0", "LIN p1", "LIN p2"]
    runs = {}
    for name, head in (("tables", ["BAS (#TOOL,3 )", "BAS (#BASE,2 )"]),
                       ("frames", [f"$TOOL = {krl(TOOL3)}", f"$LOAD = {krl(LOAD3)}",
                                   f"$BASE = {krl(BASE2)}"])):
        (tmp_path / name).mkdir()
        src = write(tmp_path / name, "cell", ["DEF cell( )", "BAS (#INITMOV,0 )", *head,
                                              *moves, "END"], dat)
        runs[name] = _paths(robot, src, config)
    (t, (pa,)), (f, (pb,)) = runs["tables"], runs["frames"]
    assert np.abs(pa.target_frames[:, :3, 3] * 1e3 - want).max() < 1e-9  # in the robot base
    assert np.abs(pa.frames - pb.frames).max() <= 1e-12 and np.abs(pa.q - pb.q).max() <= 1e-12
    assert np.abs(pa.tool - pb.tool).max() <= 1e-15
    tooldata = [x for x in t.splitlines() if "PERS tooldata" in x]
    assert tooldata == [x for x in f.splitlines() if "PERS tooldata" in x]
    assert ",[12.5,[0,0,60]," in tooldata[0]  # LOAD_DATA[3]'s payload
