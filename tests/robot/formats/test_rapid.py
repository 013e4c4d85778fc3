"""RAPID reader/writer: the thesis appendix-B module and every error path."""

from __future__ import annotations

import re
from importlib.resources import files

import numpy as np
import pytest

from flexarm.fe.errors import ReadError
from flexarm.robot.formats.rapid import (
    EXTAX_UNUSED,
    JointTarget,
    RobTarget,
    decode_cfx,
    quadrant,
    read_rapid,
    write_rapid,
)

THESIS = files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod"
TARGET_NAMES = ["Target_50", "Target_20", "Target_60", "Target_40"] + [
    f"Target_{k}" for k in range(70, 261, 10)
]
PROC_NAMES = ["main", "Path_10", "Path_20", "Path_30", "Path_40", "Path_50", "Path_60"]
P1 = "[[1000,0,500],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]]"


@pytest.fixture(scope="module")
def thesis():
    return read_rapid(THESIS)


def _module(tmp_path, body: str, decls: str = f"CONST robtarget p1:={P1};\n"):
    """Write MODULE M / decls / body / ENDMODULE; line 1 = MODULE, decls from line 2."""
    path = tmp_path / "bad.mod"
    path.write_text("MODULE M\n" + decls + body + "ENDMODULE\n")
    return path


def _raises(path, line: int, message: str, **kwargs):
    with pytest.raises(ReadError, match=re.escape(f"{path}, line {line}: {message}")):
        read_rapid(path, **kwargs)


# ----------------------------------------------------------------------------- thesis module

def test_thesis_module_names(thesis):
    assert thesis.name == "Module1"
    assert list(thesis.targets) == TARGET_NAMES
    assert len(thesis.targets) == 24
    assert list(thesis.procedures) == PROC_NAMES
    assert list(thesis.joint_targets) == ["calib_post"]
    assert np.array_equal(thesis.joint_targets["calib_post"].joints_deg, np.zeros(6))


def test_thesis_values_exactly_as_printed(thesis):
    t = thesis.targets
    assert t["Target_50"].pos_mm.tolist() == [883.561, -287.318, 583.49]
    assert t["Target_60"].pos_mm.tolist() == [882.84, 22.68, 583.24]
    assert t["Target_230"].pos_mm.tolist() == [1331.633410479, -70.634702977, 688.13]
    assert t["Target_240"].quat.tolist() == [0, 0.717223104, 0.696843612, 0]
    assert t["Target_70"].quat.tolist() == [0.5, 0.5, 0.5, -0.5]  # w first, as written
    assert t["Target_50"].conf.tolist() == [-1, -1, 0, 1]
    assert t["Target_60"].conf.tolist() == [0, 0, -1, 1]
    assert t["Target_70"].conf.dtype == np.int64
    for target in t.values():
        assert np.all(target.extax == EXTAX_UNUSED)
        assert not target.is_extax_used.any()
        assert target.pos_mm.flags.writeable is False


def test_thesis_motions(thesis):
    p30 = thesis.procedures["Path_30"]
    assert [m.kind for m in p30.motions] == ["MoveJ", "MoveC", "MoveC"]
    m = p30.motions[1]
    assert (m.cir_point.name, m.to_point.name) == ("Target_80", "Target_90")
    assert (m.speed, m.zone, m.tool, m.wobj) == ("v10", "fine", "tool0", "wobj0")
    assert m.is_fine and m.line == 71
    assert p30.line == 69
    p60 = thesis.procedures["Path_60"]
    assert p60.motions[1].options == (("Conc", None),)
    assert p60.motions[1].zone == "z100" and not p60.motions[1].is_fine
    assert [m.to_point.name for m in thesis.procedures["Path_20"].motions] == [
        "Target_40", "Target_50", "Target_60"]
    # main repeats Path_50 instruction for instruction
    main, p50 = thesis.procedures["main"], thesis.procedures["Path_50"]
    assert [[t.name for t in m.targets] for m in main.motions] == [
        [t.name for t in m.targets] for m in p50.motions]
    assert thesis.procedure("PATH_40") is thesis.procedures["Path_40"]
    with pytest.raises(KeyError, match="Path_99.*main, Path_10"):
        thesis.procedure("Path_99")


def test_thesis_configuration_data(thesis):
    cfx = {int(t.conf[3]) for t in thesis.targets.values()}
    assert cfx == {0, 1}  # wrist in front of axis 1 and of the lower arm everywhere
    assert decode_cfx(1) == {"wrist_in_front_of_axis1": True,
                             "wrist_in_front_of_lower_arm": True, "axis5_positive": False}
    assert decode_cfx(6) == {"wrist_in_front_of_axis1": False,
                             "wrist_in_front_of_lower_arm": False, "axis5_positive": True}
    # cf1 is the quadrant of axis 1 = direction of the wrist centre, 135 mm behind the
    # flange (tool0) along its z axis
    from flexarm.robot.paths import quat_to_matrix

    for name in ["Target_50", "Target_20", "Target_60", "Target_40"] + [
            f"Target_{k}" for k in range(70, 211, 10)]:
        t = thesis.targets[name]
        wc = t.pos_mm - 135.0 * quat_to_matrix(t.quat)[:, 2]
        assert quadrant(np.degrees(np.arctan2(wc[1], wc[0]))) == t.conf[0], name
    with pytest.raises(ValueError, match="0..7"):
        decode_cfx(8)


def test_quadrant_boundaries():
    assert quadrant([0, 89.9, 90, 179.9, 180, -0.1, -90, -90.1, -180, 360]).tolist() == [
        0, 0, 1, 1, 2, -1, -1, -2, -2, 4]


def test_write_read_round_trip(thesis, tmp_path):
    out = tmp_path / "copy.mod"
    write_rapid(out, thesis)
    again = read_rapid(out)
    assert list(again.targets) == list(thesis.targets)
    for name, t in thesis.targets.items():
        u = again.targets[name]
        for attr in ("pos_mm", "quat", "conf", "extax"):
            assert np.array_equal(getattr(t, attr), getattr(u, attr)), (name, attr)
    assert list(again.procedures) == PROC_NAMES
    for name, proc in thesis.procedures.items():
        for m, n in zip(proc.motions, again.procedures[name].motions, strict=True):
            assert (m.kind, m.speed, m.zone, m.tool, m.wobj, m.options) == (
                n.kind, n.speed, n.zone, n.tool, n.wobj, n.options)
            assert [t.name for t in m.targets] == [t.name for t in n.targets]
    assert np.array_equal(again.joint_targets["calib_post"].extax,
                          thesis.joint_targets["calib_post"].extax)


# ----------------------------------------------------------------------------- other syntax

def test_data_declarations_offs_reltool_inline(tmp_path):
    text = """%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%
MODULE Cell(SYSMODULE)
    ! tool 100 mm along the flange z axis
    PERS tooldata tPen:=[TRUE,[[0,0,100],[1,0,0,0]],[1.5,[0,0,50],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[500,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    CONST speeddata vSlow:=[50,500,5000,1000];
    CONST zonedata zTight:=[FALSE,1,1.5,1.5,0.15,1.5,0.15];
    CONST num r:=155;
    LOCAL CONST robtarget pDown:=[[1000,0,500],[0,0,1,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];
    VAR robtarget pEmpty;
    CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    FUNC num twice(num x)
        RETURN 2 * x;
    ENDFUNC
    PROC main()
        CONST robtarget pUp:=[[1000,0,600],[0,0,1,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];
        movej pDown, vSlow, zTight, tPen \\WObj:=wTable;
        MoveL Offs(pDown, r, -r/2, 2*(10+5)), v100 \\V:=120, z10, tPen\\WObj:=wTable;
        MoveL RelTool(pDown, 0, 0, 10 \\Rz:=90), v100, fine \\Inpos:=inpos50, tPen;
        MoveL [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;
        MoveC pUp, pDown, v100, fine, tPen;
        ConfL \\Off;
        MoveAbsJ jHome\\NoEOffs, v1000, fine, tool0;
    ENDPROC
ENDMODULE
"""
    path = tmp_path / "cell.mod"
    path.write_text(text)
    mod = read_rapid(path, ignore=("ConfL",))
    assert mod.name == "Cell"
    assert list(mod.targets) == ["pDown"]  # pEmpty has no value; pUp is routine data
    assert mod.data["tPen"].value == (True, ((0.0, 0.0, 100.0), (1.0, 0.0, 0.0, 0.0)),
                                      (1.5, (0.0, 0.0, 50.0), (1.0, 0.0, 0.0, 0.0), 0.0, 0.0,
                                       0.0))
    assert mod.data["tPen"].storage == "PERS" and mod.data["tPen"].line == 7
    assert mod.data["wTable"].value[2] == ""
    assert mod.data["vSlow"].value == (50.0, 500.0, 5000.0, 1000.0)
    assert mod.data["r"].value == 155.0
    assert mod.data["pEmpty"].value is None
    motions = mod.procedures["main"].motions
    assert [m.kind for m in motions] == ["MoveJ", "MoveL", "MoveL", "MoveL", "MoveC", "MoveAbsJ"]
    assert motions[0].speed == "vSlow" and motions[0].wobj == "wTable"
    assert motions[0].line == 20
    # Offs: displacement in the work-object frame, expressions on num data
    assert motions[1].to_point.pos_mm.tolist() == [1155.0, -77.5, 530.0]
    assert motions[1].options == (("V", "120"),)
    # RelTool: displacement along the tool z axis, which points down for q = [0,0,1,0]
    rel = motions[2].to_point
    assert np.allclose(rel.pos_mm, [1000, 0, 490], atol=1e-12)
    from flexarm.robot.paths import quat_to_matrix

    R = quat_to_matrix(rel.quat)
    assert np.allclose(R[:, 2], [0, 0, -1], atol=1e-12)  # still pointing down
    # pDown has tool x = -x; turning 90 deg about the (downward) tool z gives +y
    assert np.allclose(R[:, 0], [0, 1, 0], atol=1e-12)
    assert motions[2].options == (("Inpos", "inpos50"),)
    assert motions[3].to_point.pos_mm.tolist() == [1.0, 2.0, 3.0]
    assert motions[4].cir_point.name == "pUp"
    assert isinstance(motions[5].to_point, JointTarget)
    assert motions[5].to_point.joints_deg.tolist() == [0, 0, 0, 0, 30, 0]
    assert motions[5].options == (("NoEOffs", None),)
    assert isinstance(motions[0].to_point, RobTarget)


# ----------------------------------------------------------------------------- errors

@pytest.mark.parametrize(
    "statement, message",
    [
        ("WaitTime 1;", "unsupported instruction 'WaitTime' (supported: MoveL, MoveJ, MoveC, "
                        "MoveAbsJ)"),
        ("Path_30;", "unsupported instruction 'Path_30'"),
        ("IF TRUE THEN", "unsupported instruction 'IF'"),
        ("SearchL \\Stop, di1, sp, p1, v100, tool0;", "unsupported instruction 'SearchL'"),
        ("ConfL \\Off;", "unsupported instruction 'ConfL'"),
        ("n := 2;", "unsupported statement: assignment to 'n'"),
        ("MoveL p9, v10, fine, tool0;", "unknown data 'p9'"),
        ("MoveC p1, v10, fine, tool0;", "MoveC expects 5 arguments (CirPoint, ToPoint, Speed, "
                                        "Zone, Tool), got 4"),
        ("MoveL p1, v10, fine;", "MoveL expects 4 arguments"),
        ("MoveL p1 v10, fine, tool0;", "expected ',' between 'p1' and 'v10'"),
        ("MoveL p1, v10, fine, tool0 tool1;", "expected ',' between 'tool0' and 'tool1'"),
        ("MoveL p1, v10, fine, tool0 \\Foo:=1;", "unknown optional argument '\\Foo' for MoveL"),
        ("MoveL CRobT(), v10, fine, tool0;", "unsupported function 'CRobT' (supported: Offs, "
                                             "RelTool)"),
        ("MoveL Offs(p1, 1, 2), v10, fine, tool0;", "Offs expects (robtarget, dx, dy, dz)"),
        ("MoveL jt, v10, fine, tool0;", "MoveL: ToPoint 'jt' is not a robtarget"),
        ("MoveAbsJ p1, v10, fine, tool0;", "MoveAbsJ: ToJointPos 'p1' is not a jointtarget"),
        ("MoveL [[1,2,3],[1,0,0,0],[0,0,0,0]], v10, fine, tool0;",
         "malformed robtarget '[[1,2,3],[1,0,0,0],[0,0,0,0]]'"),
        ("MoveL Offs(p1, 1/(2-2), 0, 0), v10, fine, tool0;", "division by zero"),
        ("MoveL Offs(p1, 0, 0, p1), v10, fine, tool0;", "Offs expects (robtarget, dx, dy, dz)"),
    ],
)
def test_unsupported_and_bad_instructions(tmp_path, statement, message):
    decls = (f"CONST robtarget p1:={P1};\n"
             "CONST jointtarget jt:=[[0,0,0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n")
    path = _module(tmp_path, "PROC main()\n  MoveJ p1, v10, fine, tool0;\n  " + statement
                   + "\nENDPROC\n", decls)
    _raises(path, 6, message)  # MODULE, 2 decls, PROC, MoveJ, then the statement


def test_ignored_instruction_is_skipped(tmp_path):
    path = _module(tmp_path, "PROC main()\n  ConfL \\Off;\n  MoveJ p1, v10, fine, tool0;\n"
                             "ENDPROC\n")
    mod = read_rapid(path, ignore=("confl",))
    assert [m.line for m in mod.procedures["main"].motions] == [5]


@pytest.mark.parametrize(
    "decl, message",
    [
        ("CONST robtarget p2:=[[1,2,3],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9]];",
         "malformed robtarget 'p2': expected [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],"
         "[eax_a,...,eax_f]], got [[1,2,3],[1,0,0,0],[0,0,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09]]"),
        ("CONST robtarget p2:=[[1,2,3],[1,0,0,0],[0,0,0,1]];",
         "malformed robtarget 'p2': expected"),
        ("CONST robtarget p2:=[[1,2],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];",
         "malformed robtarget 'p2'"),
        ("CONST robtarget p2:=[[1,2,\"x\"],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];",
         "malformed robtarget 'p2'"),
        ("CONST robtarget p2:=[[1,2,3],[1,0,0,0],[0,0.5,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];",
         "malformed robtarget 'p2': configuration data [0,0.5,0,1] must be integers"),
        ("CONST robtarget p2:=[[1,2,3],[0.9,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];",
         "malformed robtarget 'p2': orientation [0.9,0,0,0] is not a unit quaternion "
         "(|q| = 0.9)"),
        ("CONST robtarget p2:=[[1,2,3],[0,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];",
         "malformed robtarget 'p2': orientation [0,0,0,0] is not a unit quaternion (|q| = 0)"),
        ("CONST robtarget p2;", "robtarget 'p2' has no value"),
        ("CONST num k;", "CONST 'k' has no value"),
        ("CONST robtarget p2:=[[1,2,3],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]]",
         "expected ';' after the declaration of 'p2', got 'PROC'"),
        ("CONST jointtarget j:=[[0,0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];",
         "malformed jointtarget 'j': expected [[rax_1,...,rax_6],[eax_a,...,eax_f]]"),
        ("CONST robtarget p2{2}:=[];", "array declarations are not supported ('p2')"),
        ("CONST robtarget p1:=[[1,2,3],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];",
         "'p1' is declared twice"),
        ("CONST num n:=[1,2];", "num 'n' must be a number"),
        ("CONST tooldata t:=p1;", "'t' of type tooldata cannot hold a target"),
        ("CONST robtarget p2:=[[1,2,3],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,9E9];",
         "expected ']' to close the aggregate, got ';'"),
        ("CONST robtarget p2:=[[1,2,3],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,\u22121]];",
         "unexpected character '\u2212'"),
        ("CONST robtarget p2:=[[1,2,3],[1,0,0,0],[0,0,0,1],[9E9,9E9,9E9,9E9,9E9,n]];",
         "unknown data 'n'"),
    ],
)
def test_malformed_declarations(tmp_path, decl, message):
    path = _module(tmp_path, "PROC main()\nENDPROC\n", f"CONST robtarget p1:={P1};\n{decl}\n")
    line = 4 if "got 'PROC'" in message else 3
    _raises(path, line, message)


def test_structure_errors(tmp_path):
    body = "PROC main()\n  MoveJ p1, v10, fine, tool0;\n"
    _raises(_module(tmp_path, body), 5, "missing ENDPROC for PROC main (line 3)")
    _raises(_module(tmp_path, body + "PROC other()\nENDPROC\n"), 5,
            "missing ENDPROC for PROC main (line 3)")
    _raises(_module(tmp_path, "PROC main()\n  MoveJ p1, v10, fine, tool0\nENDPROC\n"), 4,
            "missing ';' at the end of MoveJ")
    _raises(_module(tmp_path, "PROC go(num x)\nENDPROC\n"), 3,
            "PROC go: procedures with parameters are not supported")
    _raises(_module(tmp_path, "PROC a()\nENDPROC\nPROC A()\nENDPROC\n"), 5,
            "PROC 'A' is defined twice")
    _raises(_module(tmp_path, "MoveJ p1, v10, fine, tool0;\n"), 3,
            "unexpected 'MoveJ' at module level")
    _raises(_module(tmp_path, "FUNC num f()\n RETURN 1;\n"), 3, "missing ENDFUNC for the FUNC "
                                                               "on line 3")
    path = tmp_path / "nomodule.mod"
    path.write_text("! just a comment\nPROC main()\nENDPROC\n")
    _raises(path, 2, "expected 'MODULE', got 'PROC'")
    path.write_text("MODULE M\nPROC main()\nENDPROC\n")
    _raises(path, 3, "missing ENDMODULE for MODULE M")
    path.write_text("MODULE M\nENDMODULE\nMODULE N\n")
    _raises(path, 3, "unexpected 'MODULE' after ENDMODULE")
    with pytest.raises(ReadError, match="cannot read the file"):
        read_rapid(tmp_path / "missing.mod")


# ----------------------------------------------------------------------------- depth and size
@pytest.mark.parametrize("value, message", [
    ("[" * 200_000 + "1" + "]" * 200_000, "brackets nested more than 32 deep"),
    ("(" * 200_000 + "1" + ")" * 200_000, "brackets nested more than 32 deep"),
    ("[" * 33 + "1" + "]" * 33, "brackets nested more than 32 deep"),
], ids=["brackets", "parentheses", "33-deep"])
def test_deep_nesting_is_one_line_not_a_recursion_error(tmp_path, value, message):
    _raises(_module(tmp_path, "", f"CONST num x:={value};\n"), 2, message)


def test_nesting_up_to_the_limit_and_long_sign_chains_are_read(tmp_path):
    path = _module(tmp_path, "", "CONST num x:=" + "(" * 32 + "2" + ")" * 32 + ";\n"
                   "CONST num y:=" + "-" * 100_001 + "3;\nCONST num z:=-+-(4);\n")
    data = read_rapid(path).data
    assert (data["x"].value, data["y"].value, data["z"].value) == (2.0, -3.0, 4.0)


def test_deeply_nested_calls_in_a_move_are_one_line(tmp_path):
    target = "Offs(" * 50_000 + "p1" + ",1,0,0)" * 50_000
    _raises(_module(tmp_path, f"PROC main()\n  MoveL {target}, v10, fine, tool0;\nENDPROC\n"),
            4, "calls nested more than 32 deep")


def test_many_procedures_share_module_data_and_shadow_it(tmp_path):
    """Routine data shadow module data in their routine only (the routines do not copy the
    module's data: a module of thousands of targets and routines stays linear)."""
    procs = "".join(f"PROC r{k}()\n  CONST robtarget p1:=[[{k},0,0],[1,0,0,0],[0,0,0,0],"
                    "[9E9,9E9,9E9,9E9,9E9,9E9]];\n  MoveL p1, v10, fine, tool0;\nENDPROC\n"
                    f"PROC s{k}()\n  MoveL p1, v10, fine, tool0;\nENDPROC\n" for k in range(200))
    mod = read_rapid(_module(tmp_path, procs))
    assert len(mod.procedures) == 400
    assert mod.procedures["r7"].motions[0].to_point.pos_mm[0] == 7.0  # its own p1
    assert mod.procedures["s7"].motions[0].to_point.pos_mm.tolist() == [1000, 0, 500]


def test_arithmetic_runs_left_to_right_and_products_first(tmp_path):
    # 10-2-3 = 5 (not 11), 8/2/2 = 2 (not 8), 2*3-4/2 = 4, -2*-3 = 6
    path = _module(tmp_path, "PROC main()\n  MoveL Offs(p1, 10-2-3, 8/2/2, 2*3-4/2+-2*-3), "
                             "v10, fine, tool0;\nENDPROC\n")
    (motion,) = read_rapid(path).procedures["main"].motions
    assert motion.to_point.pos_mm.tolist() == [1005.0, 2.0, 510.0]
