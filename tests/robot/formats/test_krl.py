"""KUKA KRL output: A, B, C against scipy, status and turn, speeds, zones, tools, names."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from flexarm.robot.formats.krl import (
    abc_from_matrix,
    krl_texts,
    read_status_turn,
    status_turn,
    write_krl,
)
from flexarm.robot.formats.rapid import read_rapid


def test_abc_rebuilds_every_rotation_with_scipys_zyx():
    R = Rotation.random(3000, random_state=7).as_matrix()
    # and the gimbal: B = ±90 deg exactly and a hair away
    G = Rotation.from_euler("ZYX", [[30, 90, 50], [-20, -90, 10], [30, 90 - 1e-9, 50]],
                            degrees=True).as_matrix()
    R = np.concatenate([R, G])
    abc = abc_from_matrix(R)
    back = Rotation.from_euler("ZYX", abc, degrees=True).as_matrix()
    assert np.abs(back - R).max() < 1e-14
    assert np.all(np.abs(abc[:, 1]) <= 90.0)


def test_status_and_turn_bits():
    q = np.array([[10, 20, 30, 40, 50, 60], [-10, -20, -30, -40, -50, -60],
                  [0, 0, 0, 0, 0, 0]], float)
    S, T = status_turn(q, [0, 7, 4])
    # S: bit 0 overhead (cfx bit 2), bit 1 in front of the lower arm (not cfx bit 1),
    # bit 2 axis 5 <= 0; T: one bit per negative axis
    assert S.tolist() == [2, 5, 7] and T.tolist() == [0, 63, 0]


MODULE = """MODULE Cell
    PERS tooldata tSp:=[TRUE,[[0,0,150],[0.70710678,0,0.70710678,0]],[20,[0,0,75],[1,0,0,0],0,0,0]];
    CONST speeddata vCut:=[35,500,5000,1000];
    CONST zonedata zTight:=[FALSE,2.5,3,3,0.3,3,0.3];
    CONST robtarget p10:=[[1100,-150,500],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p20:=[[1400,-150,500],[0,0,1,0],[-1,0,-1,0],[250,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p30:=[[1350,-100,500],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC Cut()
        MoveJ p10,v100,fine,tSp\\WObj:=wobj0;
        MoveL p20,vCut,zTight,tSp\\WObj:=wobj0;
        MoveC p30,Offs(p10,0,10,0),v20\\V:=12.5,z5,tSp\\WObj:=wobj0;
        MoveL p10,vmax,z0,tSp\\WObj:=wobj0;
    ENDPROC
ENDMODULE
"""


@pytest.fixture()
def cell(tmp_path):
    path = tmp_path / "cell.mod"
    path.write_text(MODULE)
    return read_rapid(path)


def test_speeds_zones_tool_and_inline_targets(cell):
    src, dat = krl_texts(cell, "cell")
    body = src.split("DEF Cut( )")[1].splitlines()
    tool = Rotation.from_euler("ZYX", [0, 90, 0], degrees=True).as_matrix()
    assert abc_from_matrix(tool).round(9).tolist() == [0.0, 90.0, 0.0]
    assert body[1] == "$TOOL = {X 0.0,Y 0.0,Z 150.0,A 0.0,B 90.0,C 0.0}"
    # the tooldata's tload: 20 kg, centre of mass 75 mm out, no inertia given
    assert body[2] == "$LOAD = {M 20.0,CM {X 0.0,Y 0.0,Z 75.0,A 0.0,B 0.0,C 0.0},J {X 0.0," \
                      "Y 0.0,Z 0.0}}"
    body = body[:2] + body[3:]
    assert body[2].startswith("PTP p10  ;")  # fine: no approximation
    assert body[3:6] == ["$VEL.CP = 0.035", "$APO.CDIS = 2.5"] + body[5:6]
    assert body[5].startswith("LIN p20 C_DIS")
    # \V wins over v20; z5; the Offs target inline, without S and T
    assert body[6:8] == ["$VEL.CP = 0.0125", "$APO.CDIS = 5.0"]
    assert body[8].startswith("CIRC p30, {X 1100.0,Y -140.0,Z 500.0,A ") and " C_DIS" in body[8]
    assert body[9:11] == ["$VEL.CP = $VEL_MA.CP", "$APO.CDIS = 0.3"]  # vmax, z0 = 0.3 mm
    # PTP axis speeds: the program gives none, so the slow default, said in a comment
    head = src.split("DEF Cut( )")[0].splitlines()
    assert head[head.index("BAS (#INITMOV,0 )") + 1].startswith("; PTP axis speeds")
    assert [x for x in head if x.startswith("$VEL_AXIS")] == \
        [f"$VEL_AXIS[{i}] = 10.0" for i in range(1, 7)]
    assert "$VEL_AXIS[6] = 35.0" in krl_texts(cell, "cell", ptp_percent=35)[0]
    assert "DECL E6POS p20={X 1400.0,Y -150.0,Z 500.0," in dat and ",E1 250.0,E2 0.0" in dat
    assert dat.count("DECL E6POS") == 3


WTABLE = ("    PROC Cut()", "    PERS wobjdata wTable:=[FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],"
          "[[0,0,0],[1,0,0,0]]];\n    PROC Cut()")


@pytest.mark.parametrize("changes, message", [
    ([("PROC Cut()", "PROC This_name_is_far_too_long_for_krl()")], "a KRL name is at most 24"),
    ([("v100,fine", "vWhat,fine")], "speed 'vWhat'"),
    ([("z5,", "zWhat,")], "zone 'zWhat'"),
    ([("MoveJ p10,v100,fine,tSp", "MoveJ p10,v100,fine,tool9")], "tool 'tool9'"),
    ([WTABLE, ("fine,tSp\\WObj:=wobj0", "fine,tSp\\WObj:=wTable")],
     "work object 'wTable'"),
    ([("PROC Cut()", "PROC p20()")], "'p20' names both a procedure and a target"),
])
def test_what_krl_cannot_take_is_one_line_naming_it(tmp_path, changes, message):
    path = tmp_path / "cell.mod"
    text = MODULE
    for old, new in changes:
        assert old in text
        text = text.replace(old, new)
    path.write_text(text)
    out = tmp_path / "cell.src"
    with pytest.raises(ValueError, match=message) as info:
        write_krl(out, read_rapid(path))
    assert "\n" not in str(info.value)
    assert not out.exists() and not out.with_suffix(".dat").exists()


def test_status_turn_are_written_and_a_template_is_read(cell, tmp_path):
    _src, dat = krl_texts(cell, "cell", status={"P20": (6, 35)})
    assert ",S 6,T 35," in dat.splitlines()[4] and ",S 2,T 0," in dat.splitlines()[3]
    template = tmp_path / "old.dat"
    template.write_text(dat.replace("S 6,T 35", "S 'B110',T 'B100011'"))
    assert read_status_turn(template) == {"p10": (2, 0), "p20": (6, 35), "p30": (2, 0)}
