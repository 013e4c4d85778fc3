"""A TCP impulse on the Exudyn model read as a hammer test: the log decrement and the
peak finder recover known values from synthetic ring-downs; on the arm, the response's
peaks lie within 1 % of our first three frequencies and the log decrement gives our
modal damping within 10 %; the receptance U/F follows our FRF around the first modes."""

import numpy as np
import pytest

from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.studies.exudyn.impulse import log_decrement, spectrum_peak


@pytest.mark.parametrize("zeta", [0.005, 0.02, 0.05])
def test_log_decrement_of_a_known_ring_down(zeta):
    t = np.arange(0.0, 6.0, 1e-3)
    w1, w2 = 2 * np.pi * 7.0, 2 * np.pi * 17.0
    y = (np.exp(-zeta * w1 * t) * np.sin(w1 * np.sqrt(1 - zeta**2) * t)
         + 0.5 * np.exp(-0.03 * w2 * t) * np.sin(w2 * t))  # a second mode nearby
    assert log_decrement(t, y, 7.0) == pytest.approx(zeta, rel=0.03)
    freq = np.fft.rfftfreq(16 * t.size, 1e-3)
    mag = np.abs(np.fft.rfft(y, 16 * t.size))
    # a decaying sine's spectrum peaks at omega sqrt(1 - 2 zeta^2)
    assert spectrum_peak(freq, mag, 7.2) == pytest.approx(7.0 * np.sqrt(1 - 2 * zeta**2),
                                                          rel=2e-3)


exudyn = pytest.importorskip("exudyn", reason="Exudyn (pip install flexarm[mbs]) runs the "
                                              "flexible-multibody model")

from flexarm.studies.exudyn.impulse import impulse_test  # noqa: E402 - after the skip


def _check(res, tmp_path):
    assert np.abs(res.peaks_hz / res.freq_ours - 1).max() < 0.01  # acceptance: 1 %
    assert np.abs(res.zeta / res.zeta_ours - 1).max() < 0.10  # acceptance: 10 %
    near = (res.freq_hz > 0.5 * res.freq_ours[0]) & (res.freq_hz < 1.5 * res.freq_ours[1])
    err = np.abs(res.H[near] - res.H_ours[near]).max() / np.abs(res.H_ours[near]).max()
    assert err < 0.05  # the measured receptance is our FRF around the first two modes
    assert [p.name for p in res.write(tmp_path)] == ["impulse.png"]


def test_emodel_impulse_at_p1(demo_robot, tmp_path):
    res = impulse_test(build_arm(demo_robot), demo_robot.pose("P1"), duration=3.0)
    _check(res, tmp_path)


@pytest.mark.slow
def test_cb_impulse_at_p1(demo_robot, tmp_path):
    arm = build_arm(demo_robot, ArmSpec("cb", mesh_size=0.06, n_modes=10))
    res = impulse_test(arm, demo_robot.pose("P1"), duration=3.0)
    _check(res, tmp_path)
