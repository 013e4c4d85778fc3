"""A KUKA KRL program (``.src`` with its ``.dat``) as the program of ``lab --program``,
``compare --program`` and ``history``: the compensated ``.src`` measures the same path as
the compensated RAPID module (1e-9 m, demo arm and the thesis's Path_30), ``compare``
and ``history`` give the same procedure and figures from ``.mod``, ``.src`` and ``.csv``,
and bad KRL is one line naming file and line, with nothing written."""

import csv
import re

import numpy as np
import pytest

from flexarm.robot.formats.krl import write_krl
from flexarm.robot.formats.rapid import read_rapid
from flexarm.studies.compensation import compensate
from flexarm.studies.compensation.program import write_program
from flexarm.validation.data.formats import read_measurements

from ..cli_run import run_cli
from .test_lab_program import THESIS
from .test_lab_program_csv import LAB, XS, _csv, _rapid, cli, figures


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The milling pass compensated as RAPID and as KRL by the CLI, and both run."""
    d = tmp_path_factory.mktemp("krl_program")
    mod = _rapid(d / "pass.mod")
    for out in ("comp.mod", "kcomp.src"):
        cli("compensate", str(mod), "--force", "tool:fx=300", "-o", str(d / out))
    for prog, out in (("comp.mod", "m_mod.csv"), ("kcomp.src", "m_src.csv")):
        cli("lab", "--program", str(d / prog), "--reference", str(mod), *LAB, "-o", str(d / out))
    return d


def test_a_compensated_src_measures_the_path_of_the_compensated_module(runs):
    a = read_measurements(runs / "m_mod.csv")
    b = read_measurements(runs / "m_src.csv")
    assert a.n_rows == b.n_rows >= 12  # 240 mm at 20 mm
    assert np.abs(a.points - b.points).max() <= 1e-9  # m
    assert np.abs(a.force - b.force).max() < 1e-9 and set(b.force.round(6)) == {300.0}  # N
    assert "# procedure: Pass" in (runs / "m_src.csv").read_text()  # the KRL routine


def test_the_thesis_circle_measures_the_same_from_src_and_mod(tmp_path):
    res = compensate(THESIS, force="ballbar:800N", procs=["Path_30"], step_mm=10)
    write_program(res, tmp_path / "comp.mod")
    write_program(res, tmp_path / "comp.src")
    lab = ["--proc", "Path_30", "--force", "ballbar:800N", "--step", "10", "--seed", "3",
           "--reference", THESIS, "--effect", "stiffness:j2=0.7", "--effect",
           "backlash:j2=0.1mrad"]
    for s in ("mod", "src"):
        cli("lab", "--program", str(tmp_path / f"comp.{s}"), *lab, "-o",
            str(tmp_path / f"m_{s}.csv"))
    a, b = (read_measurements(tmp_path / f"m_{s}.csv") for s in ("mod", "src"))
    assert a.n_rows == b.n_rows > 90  # a 310 mm circle at 10 mm
    assert np.abs(a.points - b.points).max() <= 1e-9  # m


def test_compare_and_history_read_the_same_from_mod_src_and_csv(runs):
    d = runs
    write_krl(d / "mill.src", read_rapid(d / "pass.mod"))  # the original, as KRL
    programs = [d / "pass.mod", d / "mill.src", _csv(d / "pass.csv")]
    found = [figures(cli("compare", str(d / "m_src.csv"), "--program", str(p)))
             for p in programs]
    assert found[0] == found[1] == found[2] and found[0][0] == "Pass"
    rms = float(re.search(r"distance from the programmed path ([\d.]+) mm", found[0][1])[1])
    assert 0.05 < rms < 5.0  # a real deflection under 300 N, in mm
    rows = []
    for p in programs[:2]:
        out = d / f"history_{p.suffix[1:]}.png"
        cli("history", str(d / "m_mod.csv"), str(d / "m_src.csv"), "--program", str(p),
            "-o", str(out))
        text = out.with_suffix(".csv").read_text().splitlines()
        rows.append(list(csv.reader(x for x in text if not x.startswith("#"))))
    assert rows[0] == rows[1] and {r[1] for r in rows[0][1:]} == {"Pass"}


def _edit(folder, src_old=None, src_new=None, dat_old=None, dat_new=None):
    """The compensated pair copied as bad.src/bad.dat with one change; the changed line."""
    src = (folder / "kcomp.src").read_text().replace("DEF kcomp(", "DEF bad(")
    dat = (folder / "kcomp.dat").read_text().replace("DEFDAT kcomp", "DEFDAT bad")
    text = src if src_old is not None else dat
    old = src_old if src_old is not None else dat_old
    line = next(i + 1 for i, x in enumerate(text.splitlines()) if old in x)
    if src_old is not None:
        src = src.replace(src_old, src_new, 1)
    if dat_old is not None:
        dat = dat.replace(dat_old, dat_new, 1)
    return src, dat, line


BAD = [
    ("lab", None, "bad.dat: "),  # no .dat beside the .src
    ("compare", ("LIN c2", "LIN c9"), "bad.src, line {}: target 'c9' is not declared in bad.dat"),
    ("compare", ("LIN c2", "IF TRUE THEN"), "bad.src, line {}: unsupported KRL statement "
     "'IF TRUE THEN"),
    ("lab", ("BAS (#INITMOV,0 )", "BAS (#TOOL,3 )"), "bad.src, line {}: 'BAS (#TOOL,3 )' "
     "takes TOOL_DATA[3] from the controller's $config.dat"),
    ("lab", ("Pass( )", "Other( )"), "bad.src, line {}: Other( ) is not a DEF of bad.src"),
    ("lab", ("LIN c4", "LIN c4", "X 1340.", "X 5340."), "bad.src, line {}: target c4 at "
     "(5340.2, -149.9, 500.6) mm is out of the arm's reach"),
    ("lab", ("PTP c0", "PTP c0", "S 2,T 33", "S 2,T 32"), "bad.src, line {}: target c0 at "
     "(1100.2, -149.9, 500.4) mm is out of the arm's reach or needs a joint beyond its "
     "limits (with S 2 T 32)"),
]


@pytest.mark.parametrize("command, change, message", BAD)
def test_bad_krl_is_one_line_naming_file_and_line(runs, tmp_path, command, change, message):
    bad = tmp_path / "bad.src"
    if change is None:
        src, dat, line = _edit(runs, "LIN c2", "LIN c2")
        dat = None
    elif len(change) == 2:
        src, dat, line = _edit(runs, *change)
    else:  # the .dat changes; the message names the .src line that moves there
        src, dat, _ = _edit(runs, dat_old=change[2], dat_new=change[3])
        line = next(i + 1 for i, x in enumerate(src.splitlines()) if change[0] in x)
    bad.write_text(src)
    if dat is not None:
        bad.with_suffix(".dat").write_text(dat)
    before = sorted(p.name for p in tmp_path.iterdir())
    args = ["lab", "--program", str(bad), *LAB, "-o", str(tmp_path / "m.csv")] \
        if command == "lab" else ["compare", str(runs / "m_src.csv"), "--program", str(bad)]
    code, _out, err = run_cli(args)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert message.format(line) in lines[0], lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written


def test_a_krl_or_csv_program_is_split_where_its_module_text_says(runs):
    d = runs
    cli("compensate", str(d / "pass.mod"), "--force", "tool:fx=300", "-o", str(d / "poses.csv"))
    for prog in ("kcomp.src", "poses.csv"):  # their motions carry the file's lines
        out = d / f"split_{prog.replace('.', '_')}.mod"
        cli("compensate", str(d / prog), "--force", "tool:fx=300", "--split", "30", "-o",
            str(out))
        moves = read_rapid(out).procedure("Pass").motions
        assert [m.kind for m in moves] == ["MoveJ"] + ["MoveL"] * 8  # 60 mm in two


# --- a program as a KUKA cell has it: several files, the controller's tables ------------
def _pass_krl(folder, split: bool, head=("BAS (#INITMOV,0 )",)):
    """The milling pass as KRL: one file, or the middle moves in the module cut.src."""
    folder.mkdir(exist_ok=True)
    decl = [f"DECL E6POS c{k}={{X {x!r},Y -150.0,Z 500.0,A 0.0,B 0.0,C 180.0}}"
            for k, x in enumerate(XS)]
    middle = ["$VEL.CP = 0.1", "$APO.CDIS = 1", "LIN c1 C_DIS", "LIN c2 C_DIS", "LIN c3 C_DIS"]
    main = ["DEF pass( )", *head, "PTP c0", "cut( )", "LIN c4", "END"]
    if split:
        (folder / "cut.src").write_text("\n".join(["DEF cut( )", *middle, "END", ""]))
        (folder / "cut.dat").write_text("\n".join(["DEFDAT cut", *decl[1:4], "ENDDAT", ""]))
        decl = [decl[0], decl[4]]
    else:
        main += ["DEF cut( )", *middle, "END"]
    (folder / "pass.src").write_text("\n".join([*main, ""]))
    (folder / "pass.dat").write_text("\n".join(["DEFDAT pass", *decl, "ENDDAT", ""]))
    return folder / "pass.src"


#: The controller's tables: tool 3 is 150 mm along the flange's z.
CONFIG = ["DEFDAT $CONFIG", "DECL FRAME TOOL_DATA[16]",
          "TOOL_DATA[3]={X 0.0,Y 0.0,Z 150.0,A 0.0,B 0.0,C 0.0}", "ENDDAT", ""]


def test_a_program_over_two_files_measures_the_path_of_the_one_file_program(tmp_path):
    for name, split in (("one", False), ("two", True)):
        cli("lab", "--program", str(_pass_krl(tmp_path / name, split)), *LAB, "-o",
            str(tmp_path / f"m_{name}.csv"))
    a, b = (read_measurements(tmp_path / f"m_{n}.csv") for n in ("one", "two"))
    assert a.n_rows == b.n_rows >= 12  # 240 mm at 20 mm
    assert np.abs(a.points - b.points).max() <= 1e-12  # m
    assert "# procedure: pass" in (tmp_path / "m_two.csv").read_text()


def test_bas_tool_with_the_config_measures_the_path_of_the_tool_written_out(tmp_path):
    config = tmp_path / "System" / "$config.dat"
    config.parent.mkdir()
    config.write_text("\n".join(CONFIG))
    table = _pass_krl(tmp_path / "table", True, ("BAS (#INITMOV,0 )", "BAS (#TOOL,3 )"))
    frame = _pass_krl(tmp_path / "frame", True,
                      ("BAS (#INITMOV,0 )", "$TOOL = {X 0.0,Y 0.0,Z 150.0,A 0.0,B 0.0,C 0.0}"))
    cli("lab", "--program", str(table), "--krl-config", str(config), *LAB, "-o",
        str(tmp_path / "m_table.csv"))
    cli("lab", "--program", str(frame), *LAB, "-o", str(tmp_path / "m_frame.csv"))
    a, b = (read_measurements(tmp_path / f"m_{n}.csv") for n in ("table", "frame"))
    assert a.n_rows == b.n_rows >= 12
    assert np.abs(a.points - b.points).max() <= 1e-12  # m
    # the flange on the same targets deflects otherwise: the table's tool is applied
    plain = _pass_krl(tmp_path / "plain", True)
    cli("lab", "--program", str(plain), *LAB, "-o", str(tmp_path / "m_plain.csv"))
    c = read_measurements(tmp_path / "m_plain.csv")
    assert np.abs(a.points - c.points).max() > 1e-6  # m


REFUSED = [  # (change to the split pass, file, line, message); config: give --krl-config
    (("cut( )", "cutter( )"), "pass.src", 4, "cutter( ) is not a DEF of pass.src, nor a "
     "module cutter.src or a GLOBAL DEF in its folder", False),
    (("LIN c2 C_DIS", "pass( )"), "cut.src", 5, "pass( ) is called again while it runs "
     "(pass.src:pass -> cut.src:cut -> pass.src:pass): a recursion", False),
    (("PTP c0", "BAS (#TOOL,4 )\nPTP c0"), "pass.src", 3, "TOOL_DATA[4] is not in ", True),
    (("PTP c0", "BAS (#TOOL,3 )\nPTP c0"), "pass.src", 3, "'BAS (#TOOL,3 )' takes "
     "TOOL_DATA[3] from the controller's $config.dat (R1/System/$config.dat), which is not "
     "beside pass.src: give that file (--krl-config PATH/$config.dat)", False),
]


@pytest.mark.parametrize("command", ["lab", "compare", "compensate", "history"])
@pytest.mark.parametrize("change, where, line, message, config", REFUSED)
def test_refused_programs_are_one_line_with_exit_2_and_nothing_written(
        runs, tmp_path, command, change, where, line, message, config):
    src = _pass_krl(tmp_path / "prog", True)
    edited = src.with_name(where)
    edited.write_text(edited.read_text().replace(*change))
    cfg = tmp_path / "System" / "$config.dat"
    cfg.parent.mkdir()
    cfg.write_text("\n".join(CONFIG))
    extra = ["--krl-config", str(cfg)] if config else []
    before = sorted(p.name for p in tmp_path.rglob("*"))
    args = {"lab": ["lab", "--program", str(src), *LAB, "-o", str(tmp_path / "m.csv")],
            "compare": ["compare", str(runs / "m_src.csv"), "--program", str(src)],
            "compensate": ["compensate", str(src), "--force", "tool:fx=300", "-o",
                           str(tmp_path / "c.src")],
            "history": ["history", str(runs / "m_src.csv"), "--program", str(src), "-o",
                        str(tmp_path / "h.png")]}[command]
    code, _out, err = run_cli([*args, *extra])
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert f"{src.parent / where}, line {line}: {message}" in lines[0], lines[0]
    if config:
        assert str(cfg) in lines[0]  # both files named
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing written


def test_krl_config_goes_with_a_krl_program(runs, tmp_path):
    code, _out, err = run_cli(["compare", str(runs / "m_src.csv"), "--program",
                               str(runs / "pass.mod"), "--krl-config", str(tmp_path / "x.dat")])
    assert code == 2 and err.strip().endswith("--krl-config goes with a KRL program (a .src)")
