"""``flexarm compensate``: the module, its CSV and picture; one line and exit 2 on bad input."""

from importlib.resources import files

import pytest

from flexarm.robot.formats.rapid import read_rapid

from ..cli_run import run_cli

THESIS = str(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")


def test_writes_the_module_csv_and_picture(tmp_path, demo_robot):
    from flexarm.robot.formats import write as write_robot

    toml = tmp_path / "identified.toml"
    write_robot(toml, demo_robot)
    out = tmp_path / "compensated.mod"
    code, text, err = run_cli(["compensate", THESIS, "--robot", str(toml), "--force",
                               "ballbar:0.8kN", "--proc", "Path_30,Path_40", "--step", "5",
                               "--split", "60", "-o", str(out), "-q"])
    assert code == 0, err
    lines = text.splitlines()
    assert "targets shifted (largest 2.7" in lines[0]
    assert "Path_30      before RMS radial" in text and "note: Path_30: MoveC via" in text
    assert lines[-3:] == [f"wrote {out}", f"wrote {out.with_suffix('.csv')}",
                          f"wrote {out.with_suffix('.png')}"]
    mod = read_rapid(out)
    assert len(mod.procedures["Path_30"].motions) == 1 + 2 * 9
    assert out.read_text().splitlines()[2].startswith("    ! model: E-model of")


@pytest.mark.parametrize("args, message", [
    (["--force", "push:800"], "--force 'push:800': expected base:"),
    (["--force", "ballbar:800N", "--proc", "Path_99"], "no procedure 'Path_99'"),
    (["--force", "tool:fz=1e30"], "--force fz 1e30: outside"),
    (["--force", "ballbar:800N", "--pivot", "1,2"], "--pivot"),
    (["--force", "ballbar:800N", "--split", "0"], "--split 0: must be > 0"),
    (["--force", "missing.csv"], "missing.csv"),
])
def test_bad_input_is_one_line_and_nothing_written(tmp_path, args, message):
    out = tmp_path / "c.mod"
    code, _text, err = run_cli(["compensate", THESIS, *args, "-o", str(out)])
    assert code == 2
    last = err.strip().splitlines()[-1]
    assert last.startswith("flexarm compensate: error: ") and message in last
    assert list(tmp_path.iterdir()) == []


def test_missing_program_names_the_file(tmp_path):
    code, _t, err = run_cli(["compensate", str(tmp_path / "nope.mod"), "--force", "tool:fz=10",
                             "-o", str(tmp_path / "c.mod")])
    assert code == 2 and "nope.mod" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("name, extra, written", [
    ("c.src", [], ["c.src", "c.dat", "c.csv", "c.png"]),
    ("c.csv", [], ["c.csv", "c_deviation.csv", "c.png"]),
    ("c.poses", ["--format", "csv"], ["c.poses", "c_deviation.csv", "c.png"]),
])
def test_other_controllers_programs(tmp_path, name, extra, written):
    out = tmp_path / name
    code, text, err = run_cli(["compensate", THESIS, "--force", "ballbar:800N", "--proc",
                               "Path_30", "--step", "10", *extra, "-o", str(out), "-q"])
    assert code == 0, err
    assert text.splitlines()[-len(written):] == [f"wrote {tmp_path / w}" for w in written]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(written)


@pytest.mark.parametrize("args, message", [
    (["-o", "c.txt"], "-o c.txt: cannot tell the program format from the suffix"),
    (["--format", "krl", "-o", "c.mod"], "--format krl contradicts -o c.mod"),
    (["-o", "my-program.src"], "-o: KRL module 'my-program': a KRL name is at most 24"),
])
def test_bad_output_is_one_line_before_any_work(tmp_path, args, message):
    args = [str(tmp_path / a) if a.startswith(("c.", "my-")) else a for a in args]
    code, _text, err = run_cli(["compensate", THESIS, "--force", "ballbar:800N", *args])
    assert code == 2
    last = err.strip().splitlines()[-1]
    assert last.startswith("flexarm compensate: error: ") and message in last
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, message", [
    (["--krl-template", "old.dat", "-o", "c.mod"], "--krl-template goes with a KRL program"),
    (["--krl-template", "missing.dat", "-o", "c.src"], "missing.dat"),
])
def test_krl_template_is_checked_before_any_work(tmp_path, args, message):
    args = [str(tmp_path / a) if a.endswith((".mod", ".src", ".dat")) else a for a in args]
    code, _text, err = run_cli(["compensate", THESIS, "--force", "ballbar:800N", *args])
    assert code == 2 and message in err.strip().splitlines()[-1]
    assert len(err.strip().splitlines()) == 1 and list(tmp_path.iterdir()) == []
