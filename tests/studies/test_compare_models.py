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
