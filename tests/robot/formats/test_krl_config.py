"""The controller's tables of a KRL program: ``BAS (#TOOL, n)``, ``BAS (#BASE, n)`` and
``$TOOL = TOOL_DATA[n]`` read ``$config.dat`` (given, or found beside the ``.src``) and
set the same variables as the frames written out; a missing file or entry is one line
naming the program's line and the file to give."""

import pytest

from flexarm.fe.errors import ReadError
from flexarm.robot.formats.krl_config import read_krl_config
from flexarm.robot.formats.krl_read import read_krl

from .test_krl_calls import pos, write

TOOL3 = {"X": 10.0, "Y": -20.0, "Z": 150.0, "A": 0.0, "B": 30.0, "C": 0.0}
LOAD3 = {"M": 12.5, "CM": {"X": 0.0, "Y": 0.0, "Z": 60.0, "A": 0.0, "B": 0.0, "C": 0.0},
         "J": {"X": 0.1, "Y": 0.1, "Z": 0.05}}
BASE2 = {"X": 100.0, "Y": -50.0, "Z": 20.0, "A": 90.0, "B": 0.0, "C": 0.0}


def krl(d: dict) -> str:
    """A KRL aggregate of a dict."""
    return "{" + ",".join(f"{k} {krl(v) if isinstance(v, dict) else repr(v)}"
                          for k, v in d.items()) + "}"


#: A controller's $config.dat as KSS writes it, with what flexarm passes over.
CONFIG = ["&ACCESS RO", "&REL 3", "DEFDAT  $CONFIG", ";FOLD BASISTECH GLOBALS",
          "DECL INT GRIPPER_NO=0", "SIGNAL $ROB_STOPPED $OUT[1]", ";ENDFOLD",
          "DECL E6AXIS XHOME={A1 0.0,A2 -90.0,A3 90.0,A4 0.0,A5 0.0,A6 0.0,E1 0.0}",
          "DECL FRAME TOOL_DATA[16]", "TOOL_DATA[1]={X 0.0,Y 0.0,Z 0.0,A 0.0,B 0.0,C 0.0}",
          f"TOOL_DATA[3]={krl(TOOL3)}  ; spindle", "DECL LOAD LOAD_DATA[16]",
          "LOAD_DATA[1]={M -1.0,CM {X 0.0,Y 0.0,Z 0.0,A 0.0,B 0.0,C 0.0},J {X 0.0,Y 0.0,Z 0.0}}",
          f"LOAD_DATA[3]={krl(LOAD3)}", "DECL FRAME BASE_DATA[32]", f"BASE_DATA[2]={krl(BASE2)}",
          "ENDDAT"]


def program(folder, lines):
    return write(folder, "cell", ["DEF cell( )", "BAS (#INITMOV,0 )", *lines, "LIN p",
                                  "PTP XHOME", "END"], ["DECL E6POS p=" + pos(1200.0)])


@pytest.fixture()
def config(tmp_path):
    path = tmp_path / "System" / "$config.dat"
    path.parent.mkdir()
    path.write_text("\n".join([*CONFIG, ""]))
    return path


def test_the_tables_are_read_and_the_rest_passed_over(config):
    cfg = read_krl_config(config)
    assert cfg.tables["TOOL"] == {1: dict.fromkeys("XYZABC", 0.0), 3: TOOL3}
    assert cfg.tables["LOAD"][3] == LOAD3 and cfg.tables["BASE"] == {2: BASE2}
    assert cfg.positions["XHOME"][0] == "E6AXIS"


def test_bas_tool_and_base_equal_the_frames_written_out(tmp_path, config):
    by_table = read_krl(program(tmp_path, ["BAS (#TOOL,3 )", "BAS (#BASE,2 )"]), config)
    a = by_table.routines["cell"][0]
    by_frame = read_krl(program(tmp_path, [f"$TOOL = {krl(TOOL3)}", f"$LOAD = {krl(LOAD3)}",
                                           f"$BASE = {krl(BASE2)}"]), config)
    b = by_frame.routines["cell"][0]
    assert a.settings == b.settings and a.settings["$TOOL"] == TOOL3
    assert a.settings["$LOAD"] == LOAD3 and a.settings["$BASE"] == BASE2
    by_assign = read_krl(program(tmp_path, ["$TOOL = TOOL_DATA[3]", "$LOAD = LOAD_DATA[3]",
                                            "$BASE = BASE_DATA[2]"]), config)
    assert by_assign.routines["cell"][0].settings == b.settings
    assert by_table.routines["cell"][1].targets == ("XHOME",)  # a position of $config.dat
    assert by_table.config == str(config)


def test_a_load_kuka_marks_as_not_given_leaves_no_payload(tmp_path, config):
    prog = read_krl(program(tmp_path, [f"$LOAD = {krl(LOAD3)}", "BAS (#TOOL,1 )"]), config)
    s = prog.routines["cell"][0].settings
    assert s["$TOOL"] == dict.fromkeys("XYZABC", 0.0) and "$LOAD" not in s


def test_a_config_beside_the_program_is_found(tmp_path, config):
    src = program(tmp_path, ["BAS (#TOOL,3 )"])
    (tmp_path / "$config.dat").write_text(config.read_text())
    assert read_krl(src).routines["cell"][0].settings["$TOOL"] == TOOL3


@pytest.mark.parametrize("line, message", [
    ("BAS (#TOOL,3 )", "'BAS (#TOOL,3 )' takes TOOL_DATA[3] from the controller's "
     "$config.dat (R1/System/$config.dat), which is not beside cell.src: give that file "
     "(--krl-config PATH/$config.dat)"),
    ("$BASE = BASE_DATA[2]", "'$BASE = BASE_DATA[2]' takes BASE_DATA[2] from the "
     "controller's $config.dat"),
])
def test_without_the_config_the_line_says_which_file_to_give(tmp_path, line, message):
    src = program(tmp_path, [line])
    with pytest.raises(ReadError) as info:
        read_krl(src)
    assert str(info.value).startswith(f"{src}, line 3: {message}"), str(info.value)


@pytest.mark.parametrize("line, entry", [("BAS (#TOOL,7 )", "TOOL_DATA[7]"),
                                         ("BAS (#BASE,1 )", "BASE_DATA[1]"),
                                         ("$TOOL = TOOL_DATA[9]", "TOOL_DATA[9]")])
def test_an_index_with_no_entry_names_both_files(tmp_path, config, line, entry):
    src = program(tmp_path, [line])
    with pytest.raises(ReadError) as info:
        read_krl(src, config)
    text = str(info.value)
    assert text.startswith(f"{src}, line 3: {entry} is not in {config}"), text
    assert "\n" not in text


def test_a_bad_entry_names_the_config_line(tmp_path, config):
    config.write_text(config.read_text().replace("TOOL_DATA[3]={X 10.0", "TOOL_DATA[3]={X"))
    with pytest.raises(ReadError, match=r"\$config.dat, line 11: "):
        read_krl(program(tmp_path, ["BAS (#TOOL,3 )"]), config)
    config.unlink()
    with pytest.raises(ReadError, match=r"\$config.dat: "):
        read_krl(program(tmp_path, []), config)
