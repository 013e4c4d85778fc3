import csv

import numpy as np
import pytest

from flexarm.studies.compensation import compensate
from flexarm.studies.compensation.result import CSV_COLUMNS

from .conftest import THESIS


@pytest.fixture(scope="module")
def result(robot, arm):
    return compensate(THESIS, robot, "ballbar:400N", procs=["Path_30", "Path_10"], arm=arm,
                      step_mm=5)


def test_files_hold_the_shifts(result, tmp_path, figures):
    mod, table, png = result.write(tmp_path / "c.mod")
    assert (mod.name, table.name, png.name) == ("c.mod", "c.csv", "c.png")
    lines = table.read_text().splitlines()
    assert lines[0].startswith("# flexarm compensate: E-model of")
    rows = list(csv.DictReader(lines[1:]))
    assert tuple(rows[0]) == CSV_COLUMNS and len(rows) == len(result.shifts)
    for row, s in zip(rows, result.shifts, strict=True):
        assert row["target"] == s.name
        got = [float(row[f"shift_{c}_mm"]) for c in "xyz"]
        assert np.allclose(got, s.shift[:3] * 1e3, atol=1e-6)
        assert float(row["dx_before_mm"]) == pytest.approx(s.before[0] * 1e3, abs=1e-6)
        assert abs(float(row["dx_after_mm"])) < 1e-6
    fig = figures["c.png"]
    polar = fig.axes[1]
    assert polar.name == "polar"
    before = result.runs_before[[r.name for r in result.runs_before].index("Path_30")]
    y = polar.lines[0].get_ydata()
    assert np.allclose(np.sort(y - np.median(y)), np.sort((before.radial - np.median(
        before.radial)) * 1e6))


def test_text_names_model_force_and_paths(result):
    lines = result.text().splitlines()
    assert "with the E-model of flexarm demo arm" in lines[0]
    assert lines[0].endswith("force: ball bar 400 N push")
    assert lines[2].split()[:3] == ["Path_30", "before", "RMS"]
    assert lines[3].split()[:4] == ["Path_10", "before", "RMS", "distance"]
