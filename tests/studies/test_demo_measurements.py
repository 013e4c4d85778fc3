"""The measurement step: the updated robot file carries the diagnosed effect, and the
model read back from it matches the lab data."""

from __future__ import annotations

from flexarm.robot.formats import read
from flexarm.studies.demo_measurements import measurement_step


def test_updated_robot_file_explains_the_lab_data(tmp_path):
    said = []
    step = measurement_step(tmp_path, said.append)
    assert said == ["measurements: nominal model vs lab data, then diagnosis"]
    f = step.figures
    assert f["measurements_rms_final_um"] < f["measurements_rms_nominal_um"] / 4
    assert 0.8 < f["measurements_chi2_red_final"] < 1.2
    # the hidden effect is nonlinear: it lives in the file's effects, not in its springs
    assert [e.kind for e in read(tmp_path / "robot_v1.toml").effects] == ["backlash"]
    assert step.lines[0].startswith("## Measurements")
    assert sum(line.startswith("| baseline") for line in step.lines) == 2
    assert (tmp_path / "measurements.csv").stat().st_size > 0
