"""EMA over a wide band: twelve modes over 5-800 Hz (an analytic modal sum) split into
sub-bands, identified and merged, each mode once and within 0.1 % in frequency and 5 %
in damping."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.validation.dynamic.ema import identify_modes
from flexarm.validation.dynamic.ema_bands import SubBand, merge_poles, parse_split, sub_bands

from .modal_sum import FREQ, LINES, ZETA, errors, many_modes, modal_sum


@pytest.mark.parametrize("seed", [0, 1, *(pytest.param(s, marks=pytest.mark.slow)
                                         for s in range(2, 10))])
def test_twelve_modes_over_5_to_800_hz_each_once_with_splitting(seed):
    """3 % noise on every line: the band is split (3200 lines, 12 expected modes) and
    every mode comes out once, within 0.1 % / 5 %."""
    pm = identify_modes(modal_sum(noise=0.03, seed=seed))
    assert len(pm.bands) == 3
    n, hit, df, dz = errors(pm.freq_hz, pm.damping)
    assert (n, hit) == (12, 12)
    assert df < 1e-3 and dz < 0.05, (df, dz)


@pytest.mark.parametrize("seed", [0, pytest.param(1, marks=pytest.mark.slow),
                                  pytest.param(2, marks=pytest.mark.slow)])
def test_many_modes_need_the_split(seed):
    """Some 25 modes over 5-800 Hz (1 % noise, 12 outputs): one fit at the default order
    finds 7-10 of them; split, every one once, within 0.1 % / 5 %."""
    freq, zeta = many_modes(seed)
    frf = modal_sum(noise=0.01, seed=seed, n_out=12, freq_hz=freq, zeta=zeta)
    pm = identify_modes(frf)
    assert len(pm.bands) >= 5
    n, hit, df, dz = errors(pm.freq_hz, pm.damping, freq, zeta)
    assert n == hit == len(freq) and df < 1e-3 and dz < 0.05, (n, hit, len(freq), df, dz)
    whole = identify_modes(frf, split="none")
    assert len(whole.freq_hz) < 0.5 * len(freq), whole.freq_hz


@pytest.mark.parametrize("n", [2, 5, 8, 12])
def test_the_merge_never_keeps_a_mode_twice(n):
    """However many sub-bands are asked for, their overlaps see modes twice and the merge
    keeps each once."""
    pm = identify_modes(modal_sum(noise=0.02, seed=0), split=n)
    assert len(pm.bands) == n
    got = errors(pm.freq_hz, pm.damping)
    assert got[:2] == (12, 12) and got[2] < 1e-3 and got[3] < 0.05, got


def test_noise_free_modal_sum_is_exact():
    """Split, merged and refined, the poles of a noise-free modal sum are the truth (2e-11
    in frequency, 1e-9 in damping measured)."""
    pm = identify_modes(modal_sum())
    assert np.allclose(pm.freq_hz, FREQ, rtol=1e-8, atol=0)
    assert np.allclose(pm.damping, ZETA, rtol=1e-6, atol=0)


def test_how_many_sub_bands():
    """auto: from the expected modes (12 peaks, 4 per fit) and from the lines (4000 per
    fit); a number; none."""
    frf = modal_sum()
    cut = [b.core_lo for b in sub_bands(LINES, frf.H, 5.0, 800.0, 40)[1:]]
    assert len(cut) == 2
    # cut between modes 4 and 5, and 8 and 9, never on a mode
    assert FREQ[3] < cut[0] < FREQ[4] and FREQ[7] < cut[1] < FREQ[8]
    assert len(sub_bands(LINES, frf.H, 5.0, 800.0, 40, split="none")) == 1
    assert len(sub_bands(LINES, frf.H, 5.0, 800.0, 40, split=5)) == 5
    flat = np.ones((2, 9001)) * (1 + 0j)  # no peak: the lines decide
    f = np.linspace(1.0, 1000.0, 9001)
    assert len(sub_bands(f, flat, 1.0, 1000.0, 40)) == 3


def test_sub_band_orders_follow_their_modes():
    frf = modal_sum()
    for b in sub_bands(LINES, frf.H, 5.0, 800.0, 40):
        inside = np.sum((FREQ >= b.lo) & (FREQ <= b.hi))
        assert b.order == min(40, 4 * inside + 8)
        assert b.lo <= b.core_lo < b.core_hi <= b.hi


def test_merge_keeps_distinct_modes_and_drops_repeats():
    """Two poles 0.1 % apart seen by neighbouring fits with the same residues: one mode
    (the more central kept); the same closeness with orthogonal residues, or inside one
    fit: two modes."""
    bands = [SubBand(0, 60, 0, 50, 8), SubBand(40, 100, 50, 100, 8)]
    f, z = [49.95, 50.0], [0.01, 0.01]
    assert merge_poles(f, z, [[1, 1], [1, 1]], [0, 1], bands).tolist() == [0]
    assert merge_poles(f, z, [[1, 1], [1, -1]], [0, 1], bands).tolist() == [0, 1]
    assert merge_poles(f, z, [[1, 1], [1, 1]], [1, 1], bands).tolist() == [0, 1]
    # damping ratios twice apart are two modes too
    assert merge_poles(f, [0.01, 0.02], [[1, 1], [1, 1]], [0, 1], bands).tolist() == [0, 1]


@pytest.mark.parametrize("text", ["0", "-2", "two", "1.5"])
def test_split_option_refuses_what_it_cannot_read(text):
    with pytest.raises(ValueError, match=f"--split {text}"):
        parse_split(text)
