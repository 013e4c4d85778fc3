"""The compensation loop on the command line: lab, diagnose --apply, compensate, lab
--program, compare --program (demo arm, Path_30 at 800 N, one seed)."""

import re
from importlib.resources import files

import pytest

from flexarm.validation.data.formats import read_measurements

from ..cli_run import run_cli

THESIS = str(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")
#: The lab arm of tests/studies/compensation/lab/test_lab_run.py: stiffness ±30 %, backlash.
HIDDEN = [a for j, s in enumerate((1.3, 0.7, 1.3, 0.7, 1.3, 0.7))
          for a in ("--effect", f"stiffness:j{j + 1}={s}")] + ["--effect", "backlash:j2=0.1mrad"]
PATH = ["--proc", "Path_30", "--force", "ballbar:800N", "--step", "4"]


def cli(*args: str) -> str:
    code, out, err = run_cli([*args, "-q"])
    assert code == 0, err
    return out


def rms_mm(text: str) -> float:
    return float(re.search(r"RMS radial deviation from the programmed circle ([\d.]+) mm",
                           text).group(1))


@pytest.fixture(scope="module")
def loop(tmp_path_factory):
    """The five steps; (folder, RMS radial [mm] measured before and after)."""
    d = tmp_path_factory.mktemp("loop")
    cli("lab", *HIDDEN, "--seed", "1", "-o", str(d / "static.csv"))
    cli("lab", "--program", THESIS, *PATH, *HIDDEN, "--seed", "1", "-o", str(d / "before.csv"))
    cli("diagnose", str(d / "static.csv"), "--apply", "-o", str(d / "identified.toml"))
    cli("compensate", THESIS, "--robot", str(d / "identified.toml"), *PATH, "--split", "30",
        "-o", str(d / "compensated.mod"))
    lab = cli("lab", "--program", str(d / "compensated.mod"), "--reference", THESIS, *PATH,
              *HIDDEN, "--seed", "2", "-o", str(d / "after.csv"))
    before = cli("compare", str(d / "before.csv"), "--program", THESIS)
    after = cli("compare", str(d / "after.csv"), "--program", THESIS)
    assert "Path_30 (named in the file)" in after  # the lab's "# procedure:" comment
    assert rms_mm(lab) == rms_mm(after)  # the lab and compare read the same path
    return d, rms_mm(before), rms_mm(after)


def test_the_loop_cuts_the_measured_circle_error_tenfold(loop):
    _d, before, after = loop
    print(f"Path_30 at 800 N in the lab: {before:.4f} mm -> {after:.4f} mm "  # noqa: T201
          f"RMS radial ({before / after:.0f}x)")
    assert 1.0 < before < 2.0
    assert before / after >= 10  # no joint torque reverses on this circle


def test_the_measured_path_is_a_path_csv(loop):
    d, _, _ = loop
    data = read_measurements(d / "after.csv")
    assert type(data).__name__ == "PathData" and data.n_rows > 100
    assert set(data.force.round(6)) == {800.0}
    text = (d / "after.csv").read_text()
    assert "# procedure: Path_30" in text and "backlash width=0.0001" in text


def test_several_procedures_write_one_file_each(tmp_path):
    out = cli("lab", "--program", THESIS, "--proc", "Path_30,Path_40", "--force", "tool:fz=100",
              "--step", "20", "-o", str(tmp_path / "m.csv"))
    assert out.splitlines()[-2:] == [f"wrote {tmp_path / 'm_Path_30.csv'}",
                                     f"wrote {tmp_path / 'm_Path_40.csv'}"]


@pytest.mark.parametrize("args, message", [
    (["lab", "--program", THESIS], "--program needs --force"),
    (["lab", "--program", THESIS, "--force", "ballbar:800N", "--proc", "Path_99"],
     "no procedure 'Path_99'"),
    (["lab", "--program", THESIS, "--force", "push:800"], "--force 'push:800'"),
    (["compare", "STATIC", "--program", THESIS], "a StaticData file; --program compares a path"),
])
def test_bad_input_is_one_line(tmp_path, args, message):
    static = files("flexarm") / "data" / "examples" / "static_example.csv"
    args = [str(static) if a == "STATIC" else a for a in args]
    code, _out, err = run_cli([*args, "-o", str(tmp_path / "m.csv")] if args[0] == "lab"
                              else args)
    assert code == 2
    assert message in err.strip().splitlines()[-1] and len(err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
