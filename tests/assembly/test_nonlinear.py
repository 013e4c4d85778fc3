"""Nonlinear joint laws against their closed forms: backlash (b/2) sign(tau) or (b/2) tanh(tau/s),
hardening (1/K1 - 1/K2) clip(tau, -t, t), and the Prandtl play operator of hysteresis traced by
hand along a triangle wave; batched histories and validation."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.nonlinear import Backlash, Hardening, Hysteresis, JointLaw, play_operator

TAU = np.array([-300.0, -20.0, -1e-9, 0.0, 1e-9, 5.0, 250.0])


def test_backlash_closed_forms():
    np.testing.assert_array_equal(Backlash(2e-4).deflection(TAU),
                                  1e-4 * np.array([-1, -1, -1, 0, 1, 1, 1]))
    smooth = Backlash(2e-4, smoothing=10.0)
    np.testing.assert_allclose(smooth.deflection(TAU), 1e-4 * np.tanh(TAU / 10.0), rtol=1e-15)
    np.testing.assert_allclose(smooth.shape(TAU), 0.5 * np.tanh(TAU / 10.0), rtol=1e-15)
    assert not Backlash(0.0).deflection(TAU).any()  # no play, no extra deflection
    batch = Backlash(1e-3).deflection(np.stack([TAU, -TAU]))
    np.testing.assert_array_equal(batch[1], -batch[0])


@pytest.mark.parametrize("width, smoothing", [(-1e-4, 0.0), (1e-4, -1.0)])
def test_backlash_validation(width, smoothing):
    with pytest.raises(ValueError, match="backlash width and smoothing must be >= 0"):
        Backlash(width, smoothing)


def test_hardening_closed_form_and_total_stiffness():
    k1, k2, t = 1e5, 4e5, 150.0
    h = Hardening.from_stiffness(k1, k2, t)
    assert h.extra_compliance == pytest.approx(1 / k1 - 1 / k2, rel=1e-15)
    np.testing.assert_allclose(h.deflection(TAU), (1 / k1 - 1 / k2) * np.clip(TAU, -t, t),
                               rtol=1e-15)
    np.testing.assert_array_equal(h.shape(TAU), np.clip(TAU, -t, t))
    # total joint rotation tau / k2 + extra: slope 1/k1 below the threshold, 1/k2 above
    total = TAU / k2 + h.deflection(TAU)
    assert total[5] == pytest.approx(5.0 / k1, rel=1e-12)
    assert total[6] == pytest.approx(t / k1 + (250.0 - t) / k2, rel=1e-12)
    assert total[0] == pytest.approx(-t / k1 - (300.0 - t) / k2, rel=1e-12)
    with pytest.raises(ValueError, match="hardening threshold must be > 0 N m, got 0.0"):
        Hardening(0.0, 1e-6)


def test_play_operator_along_a_triangle_wave():
    """Up 0 -> 100, down to -100, up to 40 with r = 10: z - tau = -r on loading, +r after a
    full 2r reversal, linear in between."""
    r = 10.0
    tau = np.r_[np.linspace(0, 100, 11), np.linspace(95, -100, 40), np.linspace(-95, 40, 28)]
    p = play_operator(tau, r)
    assert p.shape == tau.shape and np.all(np.abs(p) <= r + 1e-12)
    expected = np.empty_like(tau)
    z = tau[0] - r
    for k, t in enumerate(tau):  # the textbook recursion z_k = clip(z_{k-1}, t - r, t + r)
        z = min(max(z, t - r), t + r)
        expected[k] = z - t
    np.testing.assert_allclose(p, expected, atol=1e-12)
    np.testing.assert_allclose(p[:11], -r)  # first loading
    # unloading in 5 N m steps: -r + 5, 0, r - 5, then r once the 2 r reversal is past
    np.testing.assert_allclose(p[11:14], [-r + 5, 0.0, r - 5])
    np.testing.assert_allclose(p[14:51], r)
    np.testing.assert_allclose(p[51:54], [r - 5, 0.0, -r + 5])  # reloading
    np.testing.assert_allclose(p[54:], -r)


def test_play_operator_start_and_batches():
    # the state starts on the branch of the first load change
    assert play_operator([50.0, 40.0], 10.0).tolist() == [10.0, 10.0]
    assert play_operator([50.0, 60.0], 10.0).tolist() == [-10.0, -10.0]
    assert play_operator([7.0], 3.0).tolist() == [-3.0]
    assert play_operator(np.zeros((2, 0)), 1.0).shape == (2, 0)
    hist = np.array([[0.0, 30.0, 10.0, 0.0], [5.0, -20.0, 0.0, 40.0]])
    both = play_operator(hist, 4.0)
    for row, h in zip(both, hist, strict=True):
        np.testing.assert_array_equal(row, play_operator(h, 4.0))


def test_hysteresis_loop_width_and_shape():
    h = Hysteresis(3e-4, radius=25.0)
    cycle = np.r_[np.linspace(-200, 200, 9), np.linspace(150, -200, 8)]
    d = h.deflection(cycle)
    np.testing.assert_allclose(d, 3e-4 * play_operator(cycle, 25.0) / 50.0, rtol=1e-15)
    assert np.ptp(d) == pytest.approx(3e-4, rel=1e-12)  # the loop is lost_motion wide
    assert np.all(np.abs(h.shape(cycle)) <= 0.5)
    np.testing.assert_allclose(Hysteresis(6e-4, radius=25.0).deflection(cycle), 2 * d)
    with pytest.raises(ValueError, match="hysteresis radius must be > 0 N m, got 0"):
        Hysteresis(1e-4, radius=0)


def test_joint_law_union():
    for law in (Backlash(1e-4), Hardening(10.0, 1e-6), Hysteresis(1e-4, 5.0)):
        assert isinstance(law, JointLaw)
