"""Model comparison table, CSV and Bode PNG on the box arm."""

import csv

import numpy as np

from flexarm.studies.compare_models import compare_models

from ..box_arm import box_mesher


def test_compare_models_box_arm(box_robot, tmp_path):
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
    csv_path, png = rep.files
    with csv_path.open() as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == 8 and float(table[0]["f1_Hz"]) > 0
    assert png.stat().st_size > 10_000
    assert "P2: full FE" in msgs
    assert "CB(6)" in rep.text()
