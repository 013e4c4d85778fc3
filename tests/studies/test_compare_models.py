"""Model comparison table, CSV and Bode PNG on the box arm."""

import csv

import numpy as np
import pytest

from flexarm.studies.compare_models import compare_models

from ..box_arm import box_mesher


def test_compare_models_box_arm(box_robot, tmp_path, figures):
    msgs = []
    rep = compare_models(box_robot, ["P1", "P2"], n_modes=6, n_freq=4, mass_method="surface",
                         out_dir=tmp_path, mesher=box_mesher, progress=msgs.append,
                         bode_freq_hz=np.geomspace(1, 500, 50))
    models = {r.model for r in rep.results}
    assert models == {"E-model", "Guyan", "CB(6)", "full-FE"}  # 2 joints: no wrist column
    rows = {(d["pose"], d["model"]): d for d in rep.rows()}
    assert rows["P1", "CB(6)"]["max_f_err_pct"] < 0.1
    assert rows["P1", "CB(6)"]["max_C_err_pct"] < 1e-6
    assert rows["P1", "E-model"]["max_C_err_pct"] > 5  # the links' own compliance
    assert rows["P1", "full-FE"]["max_f_err_pct"] == 0
    csv_path, bode_csv, png = rep.files
    with csv_path.open() as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == 8 and float(table[0]["f1_Hz"]) > 0
    assert png.stat().st_size > 10_000
    # the Bode CSV (m/N) is every plotted curve (mm/kN): one per model with a Bode, per pose
    with bode_csv.open() as fh:
        bode = list(csv.DictReader(fh))
    axes = figures["model_comparison_bode.png"].axes
    for ax, pose in zip(axes, ["P1", "P2"], strict=True):
        assert ax.get_ylabel() == "|H_yy| [mm/kN]"
        for line in ax.get_lines():
            rows = [b for b in bode if b["pose"] == pose and b["model"] == line.get_label()]
            assert len(rows) == 50
            np.testing.assert_allclose(line.get_xdata(), [float(b["freq_Hz"]) for b in rows])
            np.testing.assert_allclose(
                line.get_ydata(), [float(b["abs_Hyy_m_per_N"]) * 1e6 for b in rows], rtol=1e-9)
        # the low end is the static Y compliance of the table, in the plot's unit
        cyy = {d["model"]: float(d["Cyy_mm_per_kN"]) for d in table if d["pose"] == pose}
        for line in ax.get_lines():
            assert line.get_ydata()[0] == pytest.approx(cyy[line.get_label()], rel=0.05)
    assert len(bode) == 2 * 3 * 50  # full FE has no Bode
    assert "P2: full FE" in msgs
    assert "CB(6)" in rep.text()


def test_a_wrist_row_only_for_a_robot_with_a_wrist(monkeypatch):
    """CB+wrist differs from CB only through ``[wrist]``: without it there is no row."""
    import dataclasses

    from flexarm.assembly.emodel import emodel
    from flexarm.robot import load_robot
    from flexarm.studies import compare_models as cm

    # the flexible arms stand in as E-models: which rows exist is the question here
    monkeypatch.setattr(cm, "build_robot", lambda *a, **k: None)
    monkeypatch.setattr(cm, "flexible_arm", lambda robot, *a, **k: emodel(robot))
    demo = load_robot()
    with_wrist = cm.compare_models(demo, ["P1"], full_fe=False, mass_method="surface")
    plain = dataclasses.replace(demo, wrist_coupling=None, wrist_stiffness=None)
    without = cm.compare_models(plain, ["P1"], full_fe=False, mass_method="surface")
    assert "CB(10)+wrist" in {r.model for r in with_wrist.results}
    assert {r.model for r in without.results} == {"E-model", "E-model (bearing)", "Guyan",
                                                 "CB(10)"}


def test_modes_are_paired_by_shape_not_rank():
    """A rigid-link model lacks the reference's link-bending modes: its wrist mode is
    compared with the reference's wrist mode, not with the bending mode of the same rank."""
    from flexarm.studies.compare_models import ComparisonReport, ModelResult

    X, Y, Z = np.eye(6)[:3]
    ref = ModelResult("full-FE", "P1", np.array([10.0, 40.0, 95.0]), np.ones(6), 900,
                      tcp_shapes=np.stack([X, Z + 0.1 * Y, Y]).T)
    em = ModelResult("E-model", "P1", np.array([10.2, 100.0]), np.ones(6), 6,
                     tcp_shapes=np.stack([X, Y]).T)
    rows = {d["model"]: d for d in ComparisonReport((em, ref), "full-FE", np.ones(1)).rows()}
    # by rank the second pair would be 100 / 40 Hz: +150 %
    assert rows["E-model"]["max_f_err_pct"] == pytest.approx(100 * (100 / 95 - 1))
    lonely = ModelResult("E-model", "P1", np.array([300.0]), np.ones(6), 6,
                         tcp_shapes=Z[:, None])
    rows = ComparisonReport((lonely, ref), "full-FE", np.ones(1)).rows()
    assert np.isnan(rows[0]["max_f_err_pct"])  # nothing to compare with
