"""flexarm's LSCF against an independent implementation: sdypy-ema (the maintained LSCF
of pyEMA/OpenModal) on the same noisy modal sum, one fit over a band from 0 Hz, the only
case its estimator handles.  Both must find the same poles; ours must not be worse."""

from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest

from flexarm.validation.dynamic.ema import identify_modes

from .modal_sum import LINES, errors, modal_sum

EMA = pytest.importorskip("sdypy.EMA", exc_type=ImportError)

#: Four modes under 200 Hz (a band one LSCF fit resolves), damping 1-2 %.
FREQ = np.array([23.0, 58.0, 104.0, 161.0])
ZETA = np.array([0.012, 0.018, 0.010, 0.015])


def _sdypy_poles(frf, hi: float) -> tuple[np.ndarray, np.ndarray]:
    model = EMA.Model(frf=frf.H, freq=frf.freq_hz, lower=LINES[0], upper=hi,
                      pol_order_high=40, frf_form="receptance")
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        model.get_poles(method="lscf", show_progress=False)
        # its stable pole nearest each true frequency, within +-5 Hz
        model.select_closest_poles(FREQ, f_window=5)
    return np.asarray(model.nat_freq), np.asarray(model.nat_xi)


@pytest.mark.parametrize("seed", [0, 1])
def test_our_lscf_finds_the_poles_sdypy_ema_finds(seed):
    frf = modal_sum(noise=0.01, seed=seed, n_out=6, freq_hz=FREQ, zeta=ZETA)
    hi = 200.0
    ours = identify_modes(frf, f_hi=hi, split="none", weighted=False)
    f_ref, z_ref = _sdypy_poles(frf, hi)
    n, hit, df, dz = errors(ours.freq_hz, ours.damping, FREQ, ZETA)
    assert (n, hit) == (4, 4)
    _, hit_ref, df_ref, dz_ref = errors(f_ref, z_ref, FREQ, ZETA)
    assert hit_ref == 4  # the reference itself resolves the four modes
    # the same poles, to the scatter the 1 % noise leaves in either estimator
    k = np.argmin(np.abs(f_ref[None, :] / ours.freq_hz[:, None] - 1), axis=1)
    np.testing.assert_allclose(ours.freq_hz, f_ref[k], rtol=1e-3)
    np.testing.assert_allclose(ours.damping, z_ref[k], rtol=0.1)
    assert df <= max(2 * df_ref, 2e-4) and dz <= max(2 * dz_ref, 0.02), (df, df_ref, dz, dz_ref)
