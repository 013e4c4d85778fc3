"""A CSV of poses as the program of ``lab --program`` and ``compare --program``: the same
measured path as the RAPID module holding the same moves (1e-9 m), the same procedure and
figures in ``compare``, and bad files as one line naming file, line and column."""

import re

import numpy as np
import pytest

from flexarm.validation.data.formats import read_measurements

from ..cli_run import run_cli

#: A milling pass of five poses 60 mm apart, tool0 pointing down.
XS = (1100.0, 1160.0, 1220.0, 1280.0, 1340.0)
Y, Z, DOWN = -150.0, 500.0, "0,0,1,0"
HIDDEN = ["--effect", "stiffness:j2=0.7", "--effect", "backlash:j2=0.1mrad"]
LAB = ["--force", "tool:fx=300", "--step", "20", "--seed", "4", *HIDDEN]


def _rapid(path):
    """The pass as a RAPID module written by hand (what the CSV stands for)."""
    targets = "".join(f"    CONST robtarget c{k}:=[[{x:g},{Y:g},{Z:g}],[0,0,1,0],[-1,0,-1,0],"
                      "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];\n" for k, x in enumerate(XS))
    moves = "".join(f"        {'MoveJ' if k == 0 else 'MoveL'} c{k},v100,"
                    f"{'z1' if 0 < k < len(XS) - 1 else 'fine'},tool0\\WObj:=wobj0;\n"
                    for k in range(len(XS)))
    path.write_text(f"MODULE Mill\n{targets}    PROC Pass()\n{moves}    ENDPROC\nENDMODULE\n")
    return path


def _csv(path, orientation=True):
    head = "target,x_mm,y_mm,z_mm" + (",qw,qx,qy,qz" if orientation else "")
    rows = "".join(f"c{k},{x:g},{Y:g},{Z:g}" + (f",{DOWN}" if orientation else "") + "\n"
                   for k, x in enumerate(XS))
    path.write_text(f"# procedure: Pass\n{head}\n{rows}")
    return path


def cli(*args: str) -> str:
    code, out, err = run_cli([*args, "-q"])
    assert code == 0, err
    return out


def figures(text: str) -> tuple[str, str]:
    """(procedure, RMS and peak) of a ``compare --program`` report."""
    proc = re.search(r"readings against (\w+)", text).group(1)
    return proc, re.search(r"RMS .* mm, peak distance [\d.]+ mm", text).group(0)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    d = tmp_path_factory.mktemp("csv_program")
    mod, csv = _rapid(d / "pass.mod"), _csv(d / "pass.csv")
    cli("lab", "--program", str(mod), *LAB, "-o", str(d / "m_mod.csv"))
    cli("lab", "--program", str(csv), *LAB, "-o", str(d / "m_csv.csv"))
    return d


def test_a_csv_program_measures_the_path_of_the_same_rapid_module(runs):
    a = read_measurements(runs / "m_mod.csv")
    b = read_measurements(runs / "m_csv.csv")
    assert a.n_rows == b.n_rows >= 12  # 240 mm at 20 mm
    assert np.abs(a.points - b.points).max() <= 1e-9  # m
    assert np.array_equal(a.force, b.force) and set(a.force.round(6)) == {300.0}
    assert "# procedure: Pass" in (runs / "m_csv.csv").read_text()


def test_compare_picks_the_same_procedure_and_figures_from_either_program(runs, tmp_path):
    d = runs
    by_mod = figures(cli("compare", str(d / "m_csv.csv"), "--program", str(d / "pass.mod")))
    by_csv = figures(cli("compare", str(d / "m_csv.csv"), "--program", str(d / "pass.csv")))
    # the programmed path only: no robot, no orientation needed
    bare = figures(cli("compare", str(d / "m_csv.csv"), "--program",
                       str(_csv(tmp_path / "bare.csv", orientation=False))))
    assert by_mod == by_csv == bare
    assert by_mod[0] == "Pass"
    rms = float(re.search(r"distance from the programmed path ([\d.]+) mm", by_mod[1]).group(1))
    assert 0.05 < rms < 5.0  # a real deflection under 300 N, in mm


def test_a_positions_only_csv_runs_with_orientation(runs, tmp_path):
    bare = _csv(tmp_path / "bare.csv", orientation=False)
    cli("lab", "--program", str(bare), "--orientation", DOWN, *LAB, "-o", str(tmp_path / "m.csv"))
    a = read_measurements(runs / "m_mod.csv")
    assert np.abs(read_measurements(tmp_path / "m.csv").points - a.points).max() <= 1e-9


BAD = [
    ("lab", "x_mm,y_mm,z_mm,qw,qx,qy,qz\n1100,-150,500,0,0,1,0\n1200,-150,500,0,0,0.9,0\n",
     "bad.csv, line 3, column 'qw': qw, qx, qy, qz is not a unit quaternion"),
    ("lab", "x_mm,y_mm,z_mm\n1100,-150,500\n", "bad.csv: positions only (x, y, z): give the "
     "tool orientation"),
    ("lab", "x_mm,y_mm,z_mm,qw,qx,qy,qz\n1100,-150,500,0,0,1,0\n5000,0,500,0,0,1,0\n",
     "bad.csv, line 3: target p2 at (5000.0, 0.0, 500.0) mm is out of the arm's reach"),
    ("compare", "x_mm,y_mm,z_mm,speed\n1100,-150,500,3\n", "bad.csv, line 1, column 'speed': "
     "unknown column"),
    ("compare", "x_mm,y_mm,z_mm\n1100,-150,abc\n", "bad.csv, line 2, column 'z_mm'"),
]


@pytest.mark.parametrize("command, text, message", BAD)
def test_a_bad_csv_program_is_one_line_naming_file_line_and_column(runs, tmp_path, command,
                                                                   text, message):
    bad = tmp_path / "bad.csv"
    bad.write_text(text)
    args = ["lab", "--program", str(bad), *LAB, "-o", str(tmp_path / "m.csv")] \
        if command == "lab" else ["compare", str(runs / "m_csv.csv"), "--program", str(bad)]
    code, _out, err = run_cli(args)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert message in lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv"]  # nothing written


def test_orientation_without_program_is_refused(tmp_path):
    code, _out, err = run_cli(["lab", "--orientation", DOWN, "-o", str(tmp_path / "s.csv")])
    assert code == 2 and "--orientation goes with --program" in err
    assert list(tmp_path.iterdir()) == []
