"""FRFs of analytic modal sums over 5-800 Hz, the truth the EMA tests identify: twelve
well-separated modes (:data:`FREQ`, :data:`ZETA`), or some thirty drawn at random."""

from __future__ import annotations

import numpy as np

from flexarm.validation.data.formats.uff_frf import UffFrf

#: Natural frequencies [Hz] and damping ratios [-] of the twelve modes.
FREQ = np.array([18.0, 37, 61, 92, 130, 176, 231, 297, 374, 463, 566, 684])
ZETA = np.array([0.010, 0.015, 0.008, 0.012, 0.020, 0.010, 0.015, 0.009, 0.012, 0.018,
                 0.010, 0.014])
#: 0.25 Hz lines over 5-800 Hz, as an analyzer's 3200-line zoom.
LINES = np.arange(5.0, 800.001, 0.25)


def modal_sum(noise: float = 0.0, seed: int = 0, n_out: int = 8, freq_hz=FREQ,
              zeta=ZETA) -> UffFrf:
    """Receptances ``sum_r phi_o phi_1 / (w_r^2 - w^2 + 2 i zeta_r w_r w)`` [m/N] at
    ``n_out`` outputs (z) from a hammer at output 1 (z, a unit-mass modal model with
    random shapes, every mode well excited at the reference), with complex Gaussian
    noise of ``noise`` times each line's magnitude."""
    rng = np.random.default_rng(seed)
    phi = rng.normal(size=(len(freq_hz), n_out))
    phi[:, 0] = np.sign(phi[:, 0]) * (0.7 + 0.6 * rng.random(len(freq_hz)))
    w, wr = 2 * np.pi * LINES, 2 * np.pi * np.asarray(freq_hz)[:, None]
    H = np.einsum("ro,rf->of", phi * phi[:, :1],
                  1 / (wr**2 - w**2 + 2j * np.asarray(zeta)[:, None] * wr * w))
    H = H + noise * np.abs(H) * (rng.normal(size=H.shape) + 1j * rng.normal(size=H.shape)) \
        / np.sqrt(2)
    nodes = np.arange(1, n_out + 1)
    z = np.full(n_out, "z")
    return UffFrf("P1", np.zeros(6), LINES, nodes, z, np.ones(n_out, int), z, H)


def many_modes(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies [Hz] (log-uniform over 10-760 Hz, at least 3 % apart; 24-28 of them
    for seeds 0-2) and damping ratios [-] (0.8-2 %) of a modal sum with many modes."""
    rng = np.random.default_rng(seed)
    drawn = np.sort(np.exp(rng.uniform(np.log(10.0), np.log(760.0), 30)))
    kept = [drawn[0]]
    for f in drawn[1:]:
        if f > 1.03 * kept[-1]:
            kept.append(f)
    return np.array(kept), rng.uniform(0.008, 0.02, len(kept))


def errors(freq_hz, damping, truth=FREQ, zeta=ZETA) -> tuple[int, int, float, float]:
    """(poles found, true modes they hit, worst relative frequency error, worst relative
    damping error) of identified modes, each true mode against its nearest pole."""
    freq_hz, damping = np.asarray(freq_hz), np.asarray(damping)
    k = np.argmin(np.abs(freq_hz[None, :] / truth[:, None] - 1), axis=1)
    return (len(freq_hz), len(set(k.tolist())), float(np.max(np.abs(freq_hz[k] / truth - 1))),
            float(np.max(np.abs(damping[k] / zeta - 1))))
