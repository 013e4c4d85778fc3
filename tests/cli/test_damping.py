"""``flexarm fit-damping``: modal CSV with damping -> robot TOML with fitted joint damping."""

from __future__ import annotations

import numpy as np

from flexarm.cli import main
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.formats import read as read_robot
from flexarm.validation.data.formats import write_modal
from flexarm.validation.dynamic.damping_fit import robot_with_damping
from flexarm.validation.lab.virtual_lab import run_lab

TRUE = [0.01, 0.03, 0.02, 0.05, 0.04, 0.06]


def test_cli_fit_damping_writes_the_robot_and_the_plot(tmp_path, capsys):
    lab = run_lab(robot_with_damping(load_demo_robot(), TRUE), poses="P1,P2,P3",
                  loads="0:100:100", dirs="z", modal=True, n_modes=12)
    modal = write_modal(tmp_path / "modal.csv", lab.shapes)
    out = tmp_path / "damped.toml"
    assert main(["fit-damping", str(modal), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "joints" in text and "<- written" in text and f"wrote {out}" in text
    back = read_robot(out)
    got = [j.emodel.damping_ratio if j.emodel is not None else j.model.damping_ratio
           for j in back.joints]
    np.testing.assert_allclose(got, TRUE, rtol=0.02)  # noise-free damping
    assert (tmp_path / "damped.damping.png").stat().st_size > 10_000

    assert main(["fit-damping", str(modal), "-o", str(tmp_path / "x.toml"),
                 "--method", "rayleigh"]) == 0
    assert read_robot(tmp_path / "x.toml").joints[0].model.rayleigh is not None


def test_cli_fit_damping_errors_are_one_line(tmp_path, capsys):
    lab = run_lab(poses="P1", loads="0:100:100", dirs="z", modal=True, n_modes=4)
    freq_only = lab.write(tmp_path / "s.csv", tmp_path / "f.csv").modal
    assert main(["fit-damping", str(freq_only), "-o", str(tmp_path / "o.toml")]) == 2
    err = capsys.readouterr().err
    assert "no 'damping_ratio' column" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o.toml").exists()
    assert main(["fit-damping", str(freq_only), "-o", str(tmp_path / "o.txt")]) == 2
    assert ".toml" in capsys.readouterr().err


def test_cli_check_damping_names_the_joint(tmp_path, capsys):
    z = [0.03, 0.03, 0.03, 0.03, 0.06, 0.03]
    lab = run_lab(robot_with_damping(load_demo_robot(), z), poses="P1,P2,P3",
                  loads="0:100:100", dirs="z", modal=True, n_modes=8)
    modal = write_modal(tmp_path / "modal.csv", lab.shapes)
    png = tmp_path / "damping.png"
    assert main(["check-damping", str(modal), "--sigma-pct", "3", "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert "joint_5" in text.split("<- missing damping")[0].splitlines()[-1]
    assert text.count("<- missing damping") == 1
    assert f"wrote {png}" in text and png.stat().st_size > 10_000
    assert main(["check-damping", str(modal), "--max-hz", "1"]) == 2
    assert "at least 3 matched modes" in capsys.readouterr().err
