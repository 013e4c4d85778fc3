"""The measurement commands lab | compare | diagnose (flexarm/cli/validation.py)."""

from __future__ import annotations

import json

import pytest

from flexarm.assembly.emodel import emodel
from flexarm.cli import main
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.effects import parse_effect
from flexarm.robot.formats import write as write_robot
from flexarm.validation import read_measurements, write_frf
from flexarm.validation.diagnosis.history import robot_with_effects
from flexarm.validation.workflow import compare

from ..validation.helpers import PERTURB, frf_data


def test_cli_lab_diagnose_apply_compare(tmp_path, capsys):
    data = tmp_path / "data.csv"
    assert main(["lab", "--effect", "backlash:j2=0.1mrad", "--effect", "stiffness:j1=1.3",
                 "--dirs", "x,y,z,-x,-y,-z", "--seed", "3", "-o", str(data)]) == 0
    truth = json.loads((tmp_path / "data.truth.json").read_text())
    assert truth["effects"][0]["kind"] == "backlash"
    assert "truth" not in data.read_text()
    new = tmp_path / "new.toml"
    assert main(["diagnose", str(data), "--apply", "-o", str(new),
                 "--report", str(tmp_path / "rep")]) == 0
    out = capsys.readouterr().out
    assert "ACCEPTED: joint 2 backlash" in out and (tmp_path / "rep" / "history.png").is_file()
    assert main(["compare", str(data), "--robot", str(new), "-o", str(tmp_path / "c")]) == 0
    assert "chi2_red" in capsys.readouterr().out
    assert (tmp_path / "c" / "residual_vs_torque.png").is_file()
    assert read_measurements(data).n_series == 18


def test_cli_bad_effect(tmp_path, capsys):
    assert main(["lab", "--effect", "backlash:j9=1mrad", "-o", str(tmp_path / "x.csv")]) == 2
    assert "joint 9" in capsys.readouterr().err


def test_cli_compare_modal_and_frf(tmp_path, capsys):
    robot = load_demo_robot()
    arm = emodel(robot, method="surface")
    static, modal = tmp_path / "s.csv", tmp_path / "m.csv"
    assert main(["lab", "--poses", "P1,P2", "--loads", "0:400:200", "--modal", str(modal),
                 "--n-modes", "3", "-o", str(static)]) == 0
    assert read_measurements(modal).freq_hz.shape == (6,)
    assert main(["compare", str(modal), "-o", str(tmp_path / "rm")]) == 0
    out = capsys.readouterr().out
    assert "chi2_red" in out and "error_%" in out
    assert (tmp_path / "rm" / "frequency_errors.png").exists()
    path = write_frf(tmp_path / "f.csv", frf_data(arm, robot))
    assert main(["compare", str(path), "-o", str(tmp_path / "rf")]) == 0
    assert "peak_model_Hz" in capsys.readouterr().out
    assert (tmp_path / "rf" / "frf_overlay.png").exists()


def test_cli_lab_prints_what_it_wrote(tmp_path, capsys):
    static, modal = tmp_path / "s.csv", tmp_path / "m.csv"
    assert main(["lab", "--poses", "P1", "--loads", "0:200:100", "--dirs", "x,-z",
                 "--modal", str(modal), "--n-modes", "2", "--ref-noise", "45um",
                 "-o", str(static)]) == 0
    assert capsys.readouterr().out.splitlines() == [
        f"wrote {modal} (2 frequencies)",
        f"wrote {static} (6 readings, 2 series) and {tmp_path / 's.truth.json'}"]
    truth = json.loads((tmp_path / "s.truth.json").read_text())
    # "15um" and "45um" read exactly, like a measurement column
    assert (truth["noise_m"], truth["ref_noise_m"], truth["freq_noise"]) == (1.5e-5, 4.5e-5,
                                                                             0.005)
    assert truth["robot"] == "demo" and "flexible_mesh_m" not in truth


def test_cli_compare_prints_the_api_text(tmp_path, capsys):
    """compare prints the result's text() and one line per file its writer wrote."""
    static = tmp_path / "s.csv"
    assert main(["lab", "--poses", "P1", "--loads", "0:400:200", "--seed", "2",
                 "-o", str(static)]) == 0
    capsys.readouterr()
    assert main(["compare", str(static), "--noise", "20", "-o", str(tmp_path / "r")]) == 0
    lines = capsys.readouterr().out.splitlines()
    text = compare(static, noise_um=20.0).text().splitlines()
    assert lines[:len(text)] == text and len(text) == 2 + 3 + 1
    assert lines[len(text):] == [f"wrote {tmp_path / 'r' / n}" for n in (
        "errors.csv", "deflection_vs_force.png", "residuals.csv", "residual_vs_torque.png",
        "residual_by_pose.png")]


def test_cli_validation_errors_are_one_line(tmp_path, capsys):
    static = tmp_path / "s.csv"
    assert main(["lab", "--noise", "15parsec", "-o", str(static)]) == 2
    assert "--noise 15parsec: unknown length unit 'parsec'" in capsys.readouterr().err
    assert main(["lab", "--poses", "P1", "--loads", "0:100:100", "--dirs", "z",
                 "-o", str(static)]) == 0
    assert main(["diagnose", str(static), "--apply"]) == 2
    assert "--apply needs -o" in capsys.readouterr().err
    robot = load_demo_robot()
    nonlinear = tmp_path / "nl.toml"
    write_robot(nonlinear, robot_with_effects(robot, emodel(robot, method="surface"),
                                              [parse_effect("backlash:j2=0.1mrad")]))
    assert main(["diagnose", str(static), "--robot", str(nonlinear)]) == 2
    assert "starts from a linear model" in capsys.readouterr().err


@pytest.mark.slow
def test_cli_lab_modal_diagnose_links(tmp_path, capsys):
    """flexarm lab --effect links:c=1 --modal m.csv; diagnose s.csv --flexible [--modal m.csv]."""
    s, m = tmp_path / "s.csv", tmp_path / "m.csv"
    pert = [a for j, k in enumerate(PERTURB) for a in ("--effect", f"stiffness:j{j + 1}={k}")]
    assert main(["lab", "--effect", "links:c=1", *pert, "--dirs", "x,y,z,-x,-y,-z",
                 "--modal", str(m), "--seed", "1", "-o", str(s)]) == 0
    assert main(["diagnose", str(s), "--flexible"]) == 0
    out = capsys.readouterr().out
    assert "add modal data" in out and "ACCEPTED" not in out
    assert main(["diagnose", str(s), "--flexible", "--modal", str(m)]) == 0
    assert "ACCEPTED: link flexibility" in capsys.readouterr().out
