"""The plan-test command (flexarm/cli/plan.py)."""

from __future__ import annotations

import numpy as np

from flexarm.cli import main
from flexarm.robot.formats.rapid import read_rapid
from flexarm.validation.data.formats import read_static


def test_cli_plan_test(tmp_path, capsys):
    data = tmp_path / "data.csv"
    assert main(["lab", "--effect", "tilt:j1=3e7", "--dirs", "x,z", "--seed", "1",
                 "-o", str(data)]) == 0
    out_dir = tmp_path / "plan"
    assert main(["plan-test", str(data), "--hypotheses", "tilt:j1=3e7; stiffness:j2=1",
                 "--series", "4", "--poses", "60", "-o", str(out_dir)]) == 0
    text = capsys.readouterr().out
    assert "test plan: 4 series" in text and "if stiffness:j2=1: tilt:j1=3e7" in text
    plan = read_static(out_dir / "plan.csv")
    module = read_rapid(out_dir / "plan.mod")
    q = np.array([j.joints_deg for j in module.joint_targets.values()])
    starts = np.r_[0, np.flatnonzero(plan.series[1:] != plan.series[:-1]) + 1]
    np.testing.assert_allclose(np.degrees(plan.q[starts]), q, atol=1e-6)
    assert (out_dir / "plan_expected.png").stat().st_size > 0


def test_cli_plan_test_one_hypothesis(tmp_path, capsys):
    data = tmp_path / "data.csv"
    assert main(["lab", "--dirs", "z", "--poses", "P1", "--loads", "0:200:100",
                 "-o", str(data)]) == 0
    assert main(["plan-test", str(data), "--hypotheses", "tilt:j1=3e7",
                 "-o", str(tmp_path / "p")]) != 0
    err = capsys.readouterr().err
    assert "2 to 4 hypotheses" in err and "Traceback" not in err
    assert not (tmp_path / "p").exists()
