"""Virtual lab, compare, history/apply and the CLI commands lab | compare | diagnose."""

from __future__ import annotations

import json

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.robot.effects import parse_effect
from flexarm.robot.formats import read as read_robot
from flexarm.robot.formats import write as write_robot
from flexarm.validation import read_measurements
from flexarm.validation.compare import compare_static, write_report
from flexarm.validation.history import robot_with_effects


def test_lab_shared_reference_structure(lab):
    d = lab(seed=5, perturb=(1,) * 6)
    ref = d.reference_rows()
    assert np.all(d.disp[ref] == 0) and d.sigma is not None
    noiseless = lab(seed=5, noise=0.0, perturb=(1,) * 6)
    e = (d.disp - noiseless.disp)[ref[0] + 1 : ref[1]]
    # every row of a series shares -e_ref: rows are positively correlated
    assert np.corrcoef(e[:-1, 0], e[1:, 0])[0, 1] > -0.5


def test_parse_effect_errors():
    with pytest.raises(ValueError, match="joint"):
        parse_effect("backlash:x=1")
    with pytest.raises(ValueError, match="unit"):
        parse_effect("backlash:j2=0.1parsec")
    with pytest.raises(ValueError, match="unknown"):
        parse_effect("wobble:j2=1")


def test_compare_exact_model_in_band(demo, lab):
    d = lab(seed=2, perturb=(1,) * 6)
    cmp = compare_static(demo[1], d)
    assert cmp.band[0] - 0.05 < cmp.chi2_red < cmp.band[1]
    assert {r.pose for r in cmp.table} == {"P1", "P2", "P3"}


def test_apply_roundtrip(tmp_path, demo):
    robot, arm = demo
    eff = [parse_effect("backlash:j2=0.1mrad"), parse_effect("base:k=2e7"),
           parse_effect("stiffness:j3=1.3")]
    path = tmp_path / "r.toml"
    write_robot(path, robot_with_effects(robot, arm, eff))
    back = read_robot(path)
    effects = back.effects
    assert back.base.kind == "spring" and np.isclose(back.joints[2].model.torsion,
                                                     1.3 * robot.joints[2].model.torsion)
    assert effects[0].kind == "backlash" and np.isclose(effects[0].get("width"), 1e-4)


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


def test_write_report_files(tmp_path, demo, lab):
    files = write_report(tmp_path, compare_static(demo[1], lab(seed=4)))
    assert all(f.is_file() for f in files)
