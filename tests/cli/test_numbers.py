"""Every number of the command line goes through one reader (flexarm/cli/_numbers.py):
each option's default is a value of its own type, negative numbers are values, the help
states the rule, and a number in an environment variable is refused like an option's."""

from __future__ import annotations

import argparse

import pytest

from flexarm.cli import main, parser
from flexarm.fe import TetMesh
from flexarm.meshes import write_volume_mesh


def _subparsers(top: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    action = next(a for a in top._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def test_every_default_is_a_value_of_its_own_type():
    """A typed default reads back as itself (its unit is the one the help names), and a
    text default ("15um", "0:800:100") is inside its range."""
    checked = 0
    for name, sub in _subparsers(parser()).items():
        for action in sub._actions:
            if not callable(action.type) or action.default in (None, argparse.SUPPRESS):
                continue
            if isinstance(action.default, str):
                action.type(action.default)
            elif isinstance(action.default, (int, float)):
                assert action.type(repr(action.default)) == action.default, (name, action.dest)
            checked += 1
    assert checked > 50, checked


@pytest.mark.parametrize("argv, dest, value", [
    (["chatter", "--normal", "-1"], "normal", -1.0),
    (["chatter", "--normal", "-1e1"], "normal", -10.0),
    (["chatter", "--dir", "-.5"], "dir", -0.5),
    (["chatter", "--dir=-0.5rad"], "dir", pytest.approx(-28.64788975654116, rel=1e-15)),
    (["plan-test", "s.csv", "--hypotheses", "tilt:j1=3e7;base:k=2e7", "--min-height", "-0.2",
      "-o", "p"], "min_height", -0.2),
    (["circle", "--pivot", "-100,20,-3"], "pivot", [-0.1, 0.02, -0.003]),
    (["modes", "--pose", "-5,10,0,0,0,0"], "pose", "-5,10,0,0,0,0"),
    (["compliance", "--force", "0.8kN"], "force", 800.0),
    (["lab", "-o", "s.csv"], "noise", 1.5e-5),
    (["lab", "--loads", "0:0.4kN:200", "-o", "s.csv"], "loads", [0.0, 200.0, 400.0]),
])
def test_negative_numbers_and_units_are_values(argv, dest, value):
    got = getattr(parser().parse_args(argv), dest)
    assert (got.tolist() if hasattr(got, "tolist") else got) == value


def test_help_states_the_rule(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "a bare number is in the unit the option's help names" in text
    assert "lab --noise 25um" in text


def test_an_environment_number_is_refused_with_its_name(tmp_path, capsys, monkeypatch):
    mesh = tmp_path / "bar.vtu"
    write_volume_mesh(mesh, TetMesh.box((1.0, 0.05, 0.05), (8, 1, 1), order=1))
    out = tmp_path / "se.h5"
    argv = ["reduce", str(mesh), "--interface", "root:0,0.025,0.025,1,0,0,0.05,0.001",
            "--method", "guyan", "-o", str(out)]
    for text, why in [("abc", "not a number"), ("-4", "must be > 0 and <= 1e6 GB"),
                      ("inf", "not a finite number")]:
        monkeypatch.setenv("FLEXARM_MEMORY_GB", text)
        assert main(argv) == 2
        line = capsys.readouterr().err.strip().splitlines()[-1]
        assert line.startswith(f"flexarm reduce: error: FLEXARM_MEMORY_GB={text}: {why}"), line
        assert not out.exists()
    monkeypatch.setenv("FLEXARM_MEMORY_GB", "4GB")
    assert main(argv) == 0 and out.is_file()


@pytest.mark.parametrize("argv, line", [
    (["compliance", "--force", "1e30"],
     "flexarm compliance: error: --force 1e30: must be > 0 and <= 1e6 N"),
    (["chatter", "--kc", "-5e5"], "flexarm chatter: error: --kc -5e5: outside 0..1e10 N/m"),
    (["lab", "--noise", "25", "-o", "s.csv"],
     "flexarm lab: error: --noise 25: give a unit, e.g. 25um (accepted: m, mm, um, cm, in)"),
    (["show", "se.h5", "--frames", "0"], "flexarm show: error: --frames 0: outside 2..200"),
])
def test_a_refused_value_is_the_only_line(argv, line, capsys):
    assert main(argv) == 2
    assert capsys.readouterr().err.splitlines() == [line]


def test_other_usage_errors_keep_the_usage(capsys):
    assert main(["compliance", "--model", "nope"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("usage: flexarm compliance") and len(err) > 1
    assert err[-1].startswith("flexarm compliance: error: argument --model: invalid choice")
