"""The KRL reader: the subset flexarm writes read back, aggregates of any depth without
recursion, and anything else one line naming the file and line."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from flexarm.fe.errors import ReadError
from flexarm.robot.formats.krl import abc_from_matrix, write_krl
from flexarm.robot.formats.krl_read import matrix_from_abc, read_krl
from flexarm.robot.formats.rapid import read_rapid

from .test_krl import MODULE


def test_matrix_from_abc_is_scipys_zyx_and_inverts_abc_from_matrix():
    R = Rotation.random(500, random_state=3).as_matrix()
    abc = abc_from_matrix(R)
    assert np.abs(matrix_from_abc(abc) - R).max() < 1e-14
    assert np.abs(matrix_from_abc(abc) - Rotation.from_euler("ZYX", abc, degrees=True)
                  .as_matrix()).max() < 1e-14


@pytest.fixture()
def pair(tmp_path):
    mod = tmp_path / "cell.mod"
    mod.write_text(MODULE)
    out = tmp_path / "cell.src"
    write_krl(out, read_rapid(mod), ptp_percent=25)
    return out


def test_the_written_pair_reads_back(pair):
    prog = read_krl(pair)
    (cut,) = prog.routines.values()
    assert [m.kind for m in cut] == ["PTP", "LIN", "CIRC", "LIN"]
    assert [m.approx for m in cut] == [None, "C_DIS", "C_DIS", "C_DIS"]
    assert cut[2].targets[0] == "p30" and cut[2].targets[1]["Y"] == -140.0  # Offs inline
    assert [cut[k].settings["$VEL.CP"] for k in (1, 2, 3)] == [0.035, 0.0125, "$VEL_MA.CP"]
    assert cut[0].settings["$LOAD"]["CM"]["Z"] == 75.0 and cut[0].settings["$TOOL"]["B"] == 90
    assert prog.main_settings["$VEL_AXIS[6]"] == 25.0
    assert prog.data["p20"][0] == "E6POS" and prog.data["p20"][1]["E1"] == 250.0


def test_deep_aggregates_are_read_without_recursion(tmp_path):
    src, dat = tmp_path / "deep.src", tmp_path / "deep.dat"
    src.write_text("DEF deep( )\nEND\n")
    dat.write_text("DEFDAT deep\nDECL FOO f=" + "{A " * 100_000 + "1" + "}" * 100_000
                   + "\nENDDAT\n")
    value = read_krl(src).data["f"][1]
    for _ in range(100_000 - 1):
        value = value["A"]
    assert value == {"A": 1}


@pytest.mark.parametrize("change, message", [
    (("LIN p20", "LIN p99"), "target 'p99' is not declared in cell.dat"),
    (("LIN p20 C_DIS", "IF TRUE THEN"), "unsupported KRL statement 'IF TRUE THEN'"),
    (("$APO.CDIS = 2.5", "$APO.CDIS = {X 1"), "cannot read the value '{X 1'"),
    (("CIRC p30, ", "CIRC "), "CIRC takes 2 target(s), got 1"),
])
def test_what_it_cannot_read_is_one_line(pair, change, message):
    text = pair.read_text()
    old, new = change
    line = next(i + 1 for i, x in enumerate(text.splitlines()) if old in x)
    pair.write_text(text.replace(old, new, 1))
    with pytest.raises(ReadError) as info:
        read_krl(pair)
    assert str(info.value).startswith(f"{pair}, line {line}: {message}"), str(info.value)
    assert "\n" not in str(info.value)


def test_a_missing_dat_names_it(pair):
    pair.with_suffix(".dat").unlink()
    with pytest.raises(ReadError, match="cell.dat"):
        read_krl(pair)


def test_main_moves_bas_speeds_and_undefined_calls(tmp_path):
    src, dat = tmp_path / "own.src", tmp_path / "own.dat"
    dat.write_text("DEFDAT own\nDECL E6POS p={X 1,Y 2,Z 3,A 0,B 0,C 0}\nENDDAT\n")
    src.write_text("DEF own( )\nBAS (#VEL_PTP,30 )\nBAS (#TOOL,0 )\nPTP p\nEND\n")
    prog = read_krl(src)  # the main routine moves the arm itself: it is a routine too
    (move,) = prog.routines["own"]
    assert move.settings["$VEL_AXIS[6]"] == 30.0 and move.settings["$TOOL"] == "$NULLFRAME"
    src.write_text("DEF own( )\nBAS (#INITMOV,0 )\nmissing( )\nEND\n")
    with pytest.raises(ReadError, match=r"own.src, line 3: missing\( \) is not a DEF of own.src"):
        read_krl(src)
    src.write_text("DEF own( )\nBAS (#BASE,2 )\nEND\n")  # a table on the controller
    with pytest.raises(ReadError, match=r"own.src, line 2: 'BAS \(#BASE,2 \)' takes "
                       r"BASE_DATA\[2\] from the controller's \$config.dat"):
        read_krl(src)
    src.write_text("DEF own( )\nBAS (#BASE,n )\nEND\n")
    with pytest.raises(ReadError, match=r"own.src, line 2: unsupported call 'BAS \(#BASE,n \)'"):
        read_krl(src)
