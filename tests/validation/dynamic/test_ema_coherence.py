"""Coherence as the weight of EMA's least squares: one channel with half its lines
ruined by noise and flagged by a low coherence, through a universal file (58 FRFs with
their 58 coherence sets) and ``ema``."""

from __future__ import annotations

import contextlib
import io
from dataclasses import replace

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.validation.data.formats.uff import read_uff
from flexarm.validation.data.formats.uff_write import write_uff
from flexarm.validation.dynamic.ema import line_weights, run_ema

from .modal_sum import LINES, errors, modal_sum


def _ruined(seed: int, level: float = 1.0):
    """0.5 % noise everywhere, and on the driving point half the lines (drawn at random)
    with noise ``level`` times their magnitude: coherence 0.1 there, 0.99 elsewhere."""
    frf = modal_sum(noise=0.005, seed=seed)
    rng = np.random.default_rng(100 + seed)
    bad = rng.permutation(len(LINES))[: len(LINES) // 2]
    H, g2 = frf.H.copy(), np.full(frf.H.shape, 0.99)
    H[0, bad] += level * np.abs(H[0, bad]) * (rng.normal(size=bad.size)
                                              + 1j * rng.normal(size=bad.size))
    g2[0, bad] = 0.1
    return replace(frf, H=H, coherence=g2)


@pytest.mark.parametrize("seed", [0, pytest.param(1, marks=pytest.mark.slow),
                                  pytest.param(2, marks=pytest.mark.slow)])
def test_coherence_weighting_recovers_the_modes_the_plain_fit_loses(tmp_path, seed):
    """Weighted: the twelve modes once each, within 0.1 % / 5 % (worst frequency error
    0.002 %, worst damping error 0.1-0.3 % over seeds 0-2).  Unweighted, from the same
    file: poles made up (17 and 30 of them at seeds 1 and 2), or every mode once but a
    worst frequency and damping error 20 times the weighted fit's (seed 0: 0.07 %, 4.7 %;
    with each FRF scaled to its RMS the ruined driving point no longer sets the fit
    alone)."""
    path = write_uff(tmp_path / "frf.uff", frfs=[_ruined(seed)])
    assert read_uff(path).frfs[0].coherence is not None  # the reader keeps it
    weighted, = run_ema(path).poses
    plain, = run_ema(path, weighted=False).poses
    assert weighted.weighted and not plain.weighted
    n, hit, df, dz = errors(weighted.freq_hz, weighted.damping)
    assert (n, hit) == (12, 12) and df < 1e-3 and dz < 0.05, (n, hit, df, dz)
    n, hit, df_plain, dz_plain = errors(plain.freq_hz, plain.damping)
    assert n > 12 or (df_plain > 10 * df and dz_plain > 10 * dz), (n, df_plain, dz_plain)


def test_ema_command_weights_unless_told_not_to(tmp_path):
    path = write_uff(tmp_path / "frf.uff", frfs=[_ruined(0)])
    found = {}
    for option in ("weight", "ignore"):
        with contextlib.redirect_stdout(io.StringIO()) as out:
            assert main(["ema", str(path), "--coherence", option,
                         "-o", str(tmp_path / option / "modal.csv")]) == 0
        found[option] = [float(line.split()[2]) for line in out.getvalue().splitlines()
                         if line.strip().startswith("P1")]
    assert len(found["weight"]) == 12 and found["ignore"] != found["weight"]


def test_line_weights_are_the_h1_inverse_variance_with_a_floor():
    """gamma^2 / (1 - gamma^2), capped at gamma^2 = 1 - 1e-4 and floored at 1e-6 of the
    largest weight."""
    W = line_weights(np.array([[0.0, 0.5, 0.9, 1.0]]))
    top = (1 - 1e-4) / 1e-4
    assert np.allclose(W, [[1e-6 * top, 1.0, 9.0, top]], rtol=1e-12)
    assert line_weights(None) is None
