"""The workflows behind the commands: models, run_lab, the compare dispatcher,
run_diagnosis and the texts they print."""

from __future__ import annotations

import json

import numpy as np
import pytest

from flexarm.robot.effects import Effect, parse_effect
from flexarm.validation import example_path, read_measurements, write_frf
from flexarm.validation.data.load_plan import LabPlan, parse_dirs, parse_loads
from flexarm.validation.diagnosis.history import robot_with_effects
from flexarm.validation.dynamic.compare import (
    FrfComparison,
    ModalComparison,
    compare_frf,
    compare_modal,
)
from flexarm.validation.lab.modal_lab import virtual_modal
from flexarm.validation.lab.virtual_lab import run_lab, virtual_lab
from flexarm.validation.models import ValidationModels, ValidationOptions, validation_models
from flexarm.validation.static.compare import Comparison, compare_static
from flexarm.validation.workflow import compare, run_diagnosis

from .helpers import frf_data


def test_models_without_flexible_are_the_emodel(demo, lab):
    robot, arm = demo
    models = validation_models(robot)
    assert models.flexible is None and models.flex_mesh is None
    d = lab(seed=2, perturb=(1,) * 6, poses=("P1",))
    assert compare_static(models.arm, d).chi2_red == compare_static(arm, d).chi2_red
    with pytest.raises(ValueError, match="mass must be one of"):
        ValidationOptions(mass="cad")


def test_flexible_model_adds_link_flexibility_once(demo):
    robot, arm = demo
    links = Effect("links", None, (("compliance", 1.0),))
    assert ValidationModels(robot, arm, flexible=arm).effects_with_links() == [links]
    own = robot_with_effects(robot, arm, [parse_effect("backlash:j2=0.1mrad")])
    eff = ValidationModels(own, arm, flexible=arm).effects_with_links()
    assert [e.kind for e in eff] == ["backlash", "links"]
    assert ValidationModels(own, arm).effects_with_links() == list(own.effects)


def test_run_lab_is_the_virtual_lab_and_its_truth_round_trips(tmp_path, demo):
    robot, arm = demo
    lab = run_lab(effects=["backlash:j2=0.1mrad", parse_effect("stiffness:j1=1.3")],
                  poses="P1, P2", loads="0:400:200", dirs="x,-z", seed=4, noise="15um",
                  ref_noise="45um", modal=True, n_modes=3, freq_noise_pct=1.0)
    eff = [parse_effect("backlash:j2=0.1mrad"), parse_effect("stiffness:j1=1.3")]
    plan = LabPlan({p: robot.pose(p) for p in ("P1", "P2")}, parse_loads("0:400:200"),
                   parse_dirs("x,-z"))
    ref = virtual_lab(arm, plan, eff, 1.5e-5, 4, None, 4.5e-5)
    assert np.array_equal(lab.data.disp, ref.disp) and np.array_equal(lab.data.sigma, ref.sigma)
    modal = virtual_modal(arm, plan.poses, eff, 3, 0.01, 4)
    assert np.array_equal(lab.modal.freq_hz, modal.freq_hz)
    files = lab.write(tmp_path / "s.csv", tmp_path / "m.csv")
    truth = json.loads(files.truth.read_text())
    assert truth == lab.truth and files.truth == tmp_path / "s.truth.json"
    assert (truth["noise_m"], truth["ref_noise_m"], truth["freq_noise"], truth["seed"]) == (
        1.5e-5, 4.5e-5, 0.01, 4)
    assert [Effect.from_dict(e) for e in truth["effects"]] == eff
    back = read_measurements(files.static)
    assert np.array_equal(back.disp, lab.data.disp) and back.n_series == 4
    assert np.array_equal(read_measurements(files.modal).freq_hz, lab.modal.freq_hz)
    assert lab.text(files).splitlines() == [
        f"wrote {files.modal} (6 frequencies)",
        f"wrote {files.static} (12 readings, 4 series) and {files.truth}"]


def test_run_lab_without_modal_data_writes_no_modal_file(tmp_path):
    lab = run_lab(poses="P1", loads="0:100:100", dirs="z", noise=0.0)
    assert lab.modal is None and "freq_noise" not in lab.truth
    assert lab.data.sigma is None and lab.truth["noise_m"] == 0.0
    with pytest.raises(ValueError, match="no modal data"):
        lab.write(tmp_path / "s.csv", tmp_path / "m.csv")
    files = lab.write(tmp_path / "s.csv")
    assert files.modal is None and len(lab.text(files).splitlines()) == 1


def test_compare_dispatches_static_like_compare_static(tmp_path, demo, lab):
    d = lab(seed=2, perturb=(1,) * 6)
    cmp = compare(d)
    ref = compare_static(demo[1], d)
    assert isinstance(cmp, Comparison)
    assert cmp.chi2_red == ref.chi2_red and cmp.rms == ref.rms and cmp.table == ref.table
    text = cmp.text().splitlines()
    assert len(text) == 2 + 18 + 1
    assert text[-1] == (f"chi2_red = {ref.chi2_red:.3f} (band {ref.band[0]:.3f}-"
                        f"{ref.band[1]:.3f} for the stated noise), RMS = {ref.rms * 1e6:.1f} µm")
    assert text[2].split() == ["P1_+x"] + [f"{v:.4f}" for v in (
        ref.table[0].mean_abs_mm, ref.table[0].max_abs_mm, ref.table[0].relative,
        ref.table[0].max_meas_mm)]
    assert [p.name for p in cmp.write(tmp_path)] == [
        "errors.csv", "deflection_vs_force.png", "residuals.csv", "residual_vs_torque.png",
        "residual_by_pose.png"]


def test_compare_dispatches_modal_and_frf(tmp_path, demo):
    robot, arm = demo
    poses = {p: robot.pose(p) for p in ("P1", "P2")}
    soft = virtual_modal(arm, poses, [parse_effect("stiffness:j2=0.5")], 3, 0.0)
    cmp = compare(soft, freq_noise_pct=2.0)
    ref = compare_modal(arm, soft, freq_noise=0.02)
    assert isinstance(cmp, ModalComparison) and cmp.chi2_red == ref.chi2_red > 0
    assert cmp.text().splitlines()[-1] == (
        f"chi2_red = {ref.chi2_red:.3f} (band {ref.band[0]:.3f}-{ref.band[1]:.3f} for 2.0% "
        f"frequency noise), RMS error {ref.rms_pct:.2f}%")
    assert "for 0.5% frequency noise" in compare(soft).text()
    path = write_frf(tmp_path / "f.csv", frf_data(arm, robot))
    cmp = compare(path)
    assert isinstance(cmp, FrfComparison) and len(cmp.text().splitlines()) == 2 + 2
    assert cmp.table == compare_frf(arm, read_measurements(path)).table
    assert all(r.rms_log10_mag < 1e-9 for r in cmp.table)
    with pytest.raises(ValueError, match="cannot compare a model with PathData"):
        compare(example_path("path"))


def test_run_diagnosis_refuses_a_nonlinear_robot(demo, lab):
    robot, arm = demo
    nonlinear = robot_with_effects(robot, arm, [parse_effect("backlash:j2=0.1mrad")])
    with pytest.raises(ValueError, match="starts from a linear model"):
        run_diagnosis(lab(poses=("P1",)), nonlinear)


def test_run_diagnosis_text_and_updated_robot(tmp_path, demo, lab):
    robot, arm = demo
    d = lab(["base:k=1e7"], poses=("P1", "P2"), dirs="x,y,z", loads="0:800:200", seed=3,
            perturb=(1,) * 6)
    run = run_diagnosis(d)
    dg = run.diagnosis
    text = run.text()
    assert text == dg.text() and text.count("\nv") == len(dg.steps)
    assert text.splitlines()[0].startswith(f"identifiability: condition "
                                           f"{dg.identifiability.condition:.3g}, singular")
    assert " ".join(text.split()).endswith(" ".join(f"note: {dg.notes[-1]}".split()))
    new, ref = run.updated_robot(), robot_with_effects(robot, arm, dg.final_effects)
    assert new.joints == ref.joints and new.base == ref.base and new.base.kind == "spring"
    path = run.write_robot(tmp_path / "new.toml")
    assert path == tmp_path / "new.toml" and path.is_file()
    assert [p.name for p in run.write_history(tmp_path / "h")] == [
        "history.csv", "history.json", "history.png"]


def test_history_csv_holds_every_plotted_bar_from_the_nominal_model(tmp_path, demo, lab,
                                                                    figures):
    import csv

    from flexarm.validation.diagnosis.history import write_history

    run = run_diagnosis(lab(["base:k=1e7"], poses=("P1", "P2"), dirs="x,y,z",
                            loads="0:800:200", seed=3, perturb=(1,) * 6))
    write_history(tmp_path, run.diagnosis, nominal_rms=161e-6, sigma=run.sigma)
    with open(tmp_path / "history.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert rows[0]["version"] == "nominal" and rows[0]["rms_heldout_um"] == ""
    assert len(rows) == len(run.diagnosis.steps) + 1
    bars = figures["history.png"].axes[0].containers[0]
    np.testing.assert_allclose([b.get_height() for b in bars],
                               [float(r["rms_fit_um"]) for r in rows], rtol=1e-12)
    assert float(rows[0]["rms_fit_um"]) == pytest.approx(161.0)


def test_angles_outside_the_robots_limits_name_file_line_and_column(tmp_path, demo):
    """A reading at q2 = 160 deg (the demo arm's joint 2 stops at 150 deg) is refused by
    compare and diagnose with the file, line and column, before any model is used."""
    from flexarm.fe.errors import ReadError

    text = example_path("static").read_text().splitlines()
    header = next(i for i, line in enumerate(text) if line.startswith("series,"))
    cols = [c.strip() for c in text[header].split(",")]
    first = next(i for i in range(header + 1, len(text)) if not text[i].startswith("#"))
    series = text[first].split(",")[0]
    for i in range(first, len(text)):  # the whole series: a series holds one pose
        row = text[i].split(",")
        if row[0] == series:
            row[cols.index("q2_deg")] = " 160"
            text[i] = ",".join(row)
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(text) + "\n")
    read_measurements(bad)  # plausible angles: readable without a robot
    for run in (compare, run_diagnosis):
        with pytest.raises(ReadError, match=r"bad\.csv.*line.*q2.*outside the limits") as exc:
            run(bad, demo[0])
        assert "\n" not in str(exc.value)


@pytest.mark.parametrize("kind", ["static", "modal"])
def test_api_data_outside_the_joint_limits_name_the_reading_and_joint(kind):
    """Data given as objects are checked as files are (the reader names file and line)."""
    import dataclasses

    data = read_measurements(example_path(kind))
    q = np.array(data.q)
    q[3, 1] = np.radians(-95.0)
    label = (data.series if kind == "static" else data.poses)[3]
    with pytest.raises(ValueError, match=f"{type(data).__name__} reading 4 of '{label}': "
                                         r"joint_2 = -95 deg is outside its limits \[-90, 150\]"):
        compare(dataclasses.replace(data, q=q))
