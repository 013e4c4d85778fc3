"""``flexarm export-arm``: a state-space file python-control can use, OP4 files, and
one-line errors for a bad extension."""

import numpy as np
import pytest

from flexarm.assembly.analyses import tcp_compliance
from flexarm.assembly.arm import build_arm
from flexarm.assembly.formats import read_state_space
from flexarm.cli import main


def test_export_arm_state_space(tmp_path, capsys, demo_robot):
    path = tmp_path / "arm_P1.npz"
    assert main(["export-arm", "--pose", "P1", "--format", "ss", "-o", str(path)]) == 0
    text = capsys.readouterr().out
    assert "24 states (12 modes), 12 inputs, 18 outputs" in text and f"wrote {path}" in text
    ss = read_state_space(path)
    C = tcp_compliance(build_arm(demo_robot).model, demo_robot.pose("P1"))
    assert np.abs(ss.dc_gain()[:6, :6] - C).max() < 1e-10 * np.abs(C).max()


def test_export_arm_op4_cb(tmp_path, capsys):
    path = tmp_path / "arm.op4"
    assert main(["export-arm", "--model", "cb", "--mesh-size", "0.06", "--modes", "10",
                 "-q", "-o", str(path)]) == 0
    out = capsys.readouterr().out
    assert "124 coordinates" in out and "arm_turning_disc.op4" in out
    assert (tmp_path / "arm_dofs.csv").is_file()


@pytest.mark.parametrize("argv,msg", [
    (["-o", "arm.txt"], "unknown state-space model extension '.txt'"),
    (["--format", "op4", "-o", "arm.mat"], "unknown arm matrices extension '.mat'"),
    (["--model", "full", "-o", "arm.op4"], "OP4 of the full-FE arm"),
])
def test_bad_output_is_one_line(tmp_path, capsys, argv, msg):
    argv = [a if not a.startswith("arm.") else str(tmp_path / a) for a in argv]
    assert main(["export-arm", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and msg in err[0]


def test_export_exudyn_checks_and_writes_a_script(tmp_path, capsys):
    pytest.importorskip("exudyn", reason="Exudyn (pip install flexarm[mbs])")
    path = tmp_path / "arm_exudyn.py"
    assert main(["export-exudyn", "--model", "emodel", "--pose", "P1", "-q",
                 "-o", str(path)]) == 0
    out = capsys.readouterr().out
    assert "Exudyn vs flexarm" in out and f"wrote {path}" in out
    rows = [r.split() for r in out.splitlines() if r.strip()[:1].isdigit()]
    assert len(rows) == 10 and max(abs(float(r[3])) for r in rows) < 1e-6  # diff in %
    # self-contained by default: the E-model has no link files, only the assembly
    assert f"wrote {path.with_suffix('.npz')}" in out and "import flexarm" not in path.read_text()
    with np.load(path.with_suffix(".npz")) as d:
        assert not any(d["link_files"]) and d["gravity"][2] == -9.80665
    assert main(["export-exudyn", "--model", "emodel", "--pose", "P1", "-q", "--no-check",
                 "--no-self-contained", "-o", str(path)]) == 0
    assert "ArmSpec(model='emodel'" in path.read_text()


def test_export_exudyn_needs_a_py_file(tmp_path, capsys):
    assert main(["export-exudyn", "-o", str(tmp_path / "arm.txt")]) == 2
    assert "Python script (.py)" in capsys.readouterr().err


def test_exudyn_impulse_command(tmp_path, capsys):
    pytest.importorskip("exudyn", reason="Exudyn (pip install flexarm[mbs])")
    assert main(["exudyn-impulse", "--model", "emodel", "--duration", "2", "--dt", "1e-3",
                 "-q", "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "zeta_logdec" in out and (tmp_path / "impulse.png").is_file()
    assert main(["exudyn-impulse", "--model", "emodel", "--direction", "0,0"]) == 2


def test_exudyn_circle_command(tmp_path, capsys):
    pytest.importorskip("exudyn", reason="Exudyn (pip install flexarm[mbs])")
    assert main(["exudyn-circle", "--proc", "Path_20", "-q", "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "Path_20 at 1000 mm/s" in out and (tmp_path / "path_Path_20.png").is_file()
    assert main(["exudyn-circle", "--proc", "Path_99"]) == 2
    assert "procedure must be one of" in capsys.readouterr().err
