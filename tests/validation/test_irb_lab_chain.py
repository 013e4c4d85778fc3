"""The vibration-lab chain of the guide on the IRB 4600 imported from its URDF:
``lab -> ema -> check-damping -> diagnose --modal`` with a 20 kg mass hidden on link 3
(``docs/irb_lab_pictures.py`` runs the same steps for the guide's pictures)."""

from __future__ import annotations

import contextlib
import csv
import io
import os
from pathlib import Path

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.validation.data.formats import read_modal
from flexarm.validation.data.formats.uff import read_uff

from ..irb4600 import import_irb

POSES = "0,52,-19,12,-15,-11;0,0,66,0,-66,0;0,32,20,101,-98,-35"


def _run(*argv: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main([*argv, "-q"]) == 0, argv
    return out.getvalue()


@pytest.mark.slow
def test_the_chain_names_the_hidden_mass_on_the_imported_robot(tmp_path):
    toml, _, _ = import_irb(tmp_path)
    here = Path.cwd()
    os.chdir(tmp_path)
    try:
        _run("lab", "--robot", str(toml), "--poses", POSES, "--modal", "lab.uff",
             "--n-modes", "4", "--effect", "mass:l3=20kg", "-o", "static.csv")
        _run("ema", "lab.uff", "-o", "modal.csv")
        damping = _run("check-damping", "modal.csv", "--robot", str(toml), "--plot", "d.png")
        text = _run("diagnose", "static.csv", "--robot", str(toml), "--modal", "modal.csv",
                    "--report", "diag")
    finally:
        os.chdir(here)
    # ema: every mode the lab wrote, within 1 % (two standard deviations of the 0.5 %
    # noise on the frequencies written with the shapes; the FRFs come from the true model)
    truth = read_uff(tmp_path / "lab.uff").shapes
    got = read_modal(tmp_path / "modal.csv")
    for pose in ("Q1", "Q2", "Q3"):
        f = np.sort(np.asarray(got.freq_hz)[np.asarray(got.poses) == pose])
        t = np.sort(np.asarray(truth.freq_hz)[np.asarray(truth.poses) == pose])
        assert len(f) == len(t) == 4, (pose, f, t)
        np.testing.assert_allclose(f, t, rtol=1e-2)
    assert "no joint misses damping" in damping
    assert "link 3 added mass    accepted" in text
    with open(tmp_path / "diag" / "history.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows[-1]["model"] == "baseline + link 3 added mass"
    assert float(rows[-1]["freq_rms_pct"]) < 0.2 * float(rows[0]["freq_rms_pct"])
