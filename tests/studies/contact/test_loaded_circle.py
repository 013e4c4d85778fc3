from dataclasses import replace
from importlib.resources import files

import numpy as np
import pytest

from flexarm.assembly.arm import ArmSpec
from flexarm.assembly.nonlinear import Backlash
from flexarm.robot.effects import Effect, parse_effect
from flexarm.studies.contact.ball_bar import measured_deviation, predict_circle, rapid_circle
from flexarm.studies.contact.circle_data import static_circle_readings
from flexarm.studies.contact.circle_models import nonlinear_solver
from flexarm.studies.contact.loaded_circle import run_circle
from flexarm.validation import ModalData, PathData, read_measurements

EXAMPLE = files("flexarm") / "data" / "examples" / "circle_static_example.csv"
LOADS = [0.0, 200.0, 800.0]


@pytest.fixture(scope="module")
def emodel_run(robot):
    return run_circle(robot, loads=LOADS, step=10.0)


def test_emodel_run_is_the_linear_prediction(emodel_run, arm, robot, module):
    (run,) = emodel_run.runs
    p = run.prediction
    assert run.label == "E-model" and run.law_joints == () and p.method == "linear_solver"
    assert np.all(p.deviation[0] == 0.0)  # 0 N is the reference run
    assert np.abs(p.bar[2] - 4 * p.bar[1]).max() <= 1e-12 * np.abs(p.bar).max()
    ref = predict_circle(arm, rapid_circle(robot, module, "Path_30", step_mm=10.0), LOADS)
    np.testing.assert_allclose(p.deviation, ref.deviation, rtol=0,
                               atol=1e-12 * np.abs(ref.deviation).max())
    assert 2.5e-3 < np.abs(p.bar[2]).max() < 2.8e-3  # 2.62 mm along the weak Y at 800 N


def test_text_lists_the_setup_and_each_load(emodel_run):
    lines = emodel_run.text().splitlines()
    s = emodel_run.setup
    assert lines[0].startswith(f"Path_30: {len(s.points)} samples, load point tool0, pivot ")
    assert lines[0].endswith("circle R 155.000 mm; conf met at 3/3 targets")
    body = lines[1 + len(s.ik.notes):]
    assert body[0] == "E-model (linear_solver):"
    assert body[1] == "       0 N: max |bar| 0.0000 mm at     0.0 deg, max |normal| 0.0000 mm"
    p = emodel_run.runs[0].prediction
    assert f"max |bar| {np.abs(p.bar[2]).max() * 1e3:.4f} mm" in body[3]
    assert len(body) == 1 + len(LOADS)


def test_write_csv_and_plots(emodel_run, tmp_path):
    paths = emodel_run.write(tmp_path / "new")
    assert [p.name for p in paths] == ["circle_Path_30.csv", "circle_top.png",
                                       "circle_polar.png", "circle_z.png"]
    assert all(p.stat().st_size > 0 for p in paths)
    head = paths[0].read_text().splitlines()[0].split(",")
    assert head[:5] == ["step", "angle_deg", "x_mm", "y_mm", "z_mm"]
    assert head[5:8] == ["bar_mm_0N", "radial_mm_0N", "normal_mm_0N"]
    rows = np.loadtxt(paths[0], delimiter=",", skiprows=1)
    p = emodel_run.runs[0].prediction
    assert rows.shape == (len(emodel_run.setup.points), 5 + 3 * len(LOADS))
    np.testing.assert_allclose(rows[:, head.index("bar_mm_800N")], p.bar[2] * 1e3, rtol=1e-8,
                               atol=1e-12)


def test_effects_of_the_robot_and_extra_ones_become_laws(robot, arm, module):
    width = 2e-4
    r = replace(robot, effects=(Effect("backlash", 2, (("width", width),)),))
    res = run_circle(r, [parse_effect("backlash:j2=0.1mrad")], loads=[0.0, 800.0], step=10.0)
    (run,) = res.runs
    assert run.law_joints == (1, 2)
    assert res.text().splitlines()[-3] == "E-model (nonlinear_solver, laws on joints 2,3):"
    solve = nonlinear_solver({2: [Backlash(width)], 1: [Backlash(1e-4)]})
    setup = rapid_circle(robot, module, "Path_30", step_mm=10.0)
    ref = predict_circle(arm, setup, [0.0, 800.0], solver=solve)
    lin = predict_circle(arm, setup, [0.0, 800.0])
    np.testing.assert_allclose(run.prediction.deviation, ref.deviation, rtol=0, atol=1e-15)
    assert np.abs(ref.deviation - lin.deviation).max() > 0.5 * width  # the laws act


def test_flexible_model_is_the_flex_arm_fixture(robot, flex_arm, module):
    res = run_circle(robot, models=["emodel", "cb"], loads=[0.0, 800.0], step=10.0,
                     spec=ArmSpec(mesh_size=0.06, n_modes=10))
    assert [r.label for r in res.runs] == ["E-model", "CB"]
    setup = rapid_circle(robot, module, "Path_30", step_mm=10.0)
    ref = predict_circle(flex_arm, setup, [0.0, 800.0])
    np.testing.assert_allclose(res.runs[1].prediction.deviation, ref.deviation, rtol=0,
                               atol=1e-12 * np.abs(ref.deviation).max())
    assert np.all(res.runs[1].prediction.bar[1] >= res.runs[0].prediction.bar[1])


def test_static_schema_file_overlay(robot):
    res = run_circle(robot, loads=[0.0, 800.0], step=10.0, measured=EXAMPLE)
    ang, bar, nrm, force = res.measured
    ref = measured_deviation(res.setup, *static_circle_readings(
        res.setup, robot.chain, read_measurements(EXAMPLE)))
    for a, b in zip(res.measured, ref, strict=True):
        np.testing.assert_array_equal(a, b)
    assert np.unique(force).tolist() == [0.0, 400.0, 800.0] and len(force) == 73
    assert res.text().splitlines()[-1] == (
        f"measured: 73 readings at [0.0, 400.0, 800.0] N, max |bar| "
        f"{np.abs(bar).max() * 1e3:.4f} mm")


def test_path_data_on_the_nominal_circle_reads_zero(emodel_run, robot):
    s = emodel_run.setup
    data = PathData(steps=np.arange(len(s.points)), points=s.points,
                    force=np.full(len(s.points), 400.0))
    res = run_circle(robot, loads=[0.0], step=10.0, measured=data)
    ang, bar, nrm, force = res.measured
    assert np.abs(bar).max() < 1e-6 and np.abs(nrm).max() < 1e-6  # [m]
    np.testing.assert_allclose(np.sort(ang), np.sort(s.angles), atol=1e-12)


def test_rejects_unknown_model_procedure_and_measurement_kind(robot):
    with pytest.raises(ValueError, match="emodel"):
        run_circle(robot, models=["rigid"], step=20.0)
    with pytest.raises(ValueError, match="no procedure Path_99"):
        run_circle(robot, proc="Path_99")
    modal = ModalData(poses=["p1"], q=np.zeros((1, 6)), modes=[1], freq_hz=[12.5])
    with pytest.raises(ValueError, match="got ModalData"):
        run_circle(robot, loads=[0.0], step=20.0, measured=modal)
