"""Virtual lab, compare and history/apply (the commands: tests/cli/test_validation.py)."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.effects import parse_effect
from flexarm.robot.formats import read as read_robot
from flexarm.robot.formats import write as write_robot
from flexarm.validation.diagnosis.history import robot_with_effects
from flexarm.validation.static.compare import compare_static, write_report


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


def test_write_report_files(tmp_path, demo, lab):
    files = write_report(tmp_path, compare_static(demo[1], lab(seed=4)))
    assert all(f.is_file() for f in files)
