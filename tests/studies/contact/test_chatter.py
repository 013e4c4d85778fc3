import numpy as np
import pytest

from flexarm.assembly.analyses import modes, tcp_compliance
from flexarm.studies.contact.chatter import (
    analyse,
    char_poly,
    cnc_model,
    growth_rate,
    is_stable,
    plane_model,
    process_vectors,
    simulate,
)
from flexarm.studies.contact.chatter_map import critical_kcb


def _random_system(rng):
    m = rng.uniform(20, 150, 2)
    a = rng.uniform(0, np.pi)
    Rm = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    M = Rm @ np.diag(m) @ Rm.T
    b = rng.uniform(0, np.pi)
    Rk = np.array([[np.cos(b), -np.sin(b)], [np.sin(b), np.cos(b)]])
    K = Rk @ np.diag(rng.uniform(1e5, 2e6, 2)) @ Rk.T
    w = np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K)).real)
    zeta = rng.uniform(0.002, 0.05)
    C = zeta * (M * w.mean() + K / w.mean())  # Rayleigh damping near zeta
    return M, C, K


def test_closed_form_agrees_with_time_simulation():
    rng = np.random.default_rng(7)
    n_stable = n_unstable = checked = 0
    while checked < 24:
        M, C, K = _random_system(rng)
        res_k = rng.uniform(1e4, 3e6)
        n, f = process_vectors(rng.uniform(0, 180), rng.uniform(-80, 80))
        Kt = K + res_k * np.outer(f, n)
        a = char_poly(M, C, Kt)
        sigma = float(growth_rate(M, C, Kt))
        w_min = np.sqrt(np.abs(np.linalg.eigvals(np.linalg.solve(M, Kt)))).min()
        t_end = 60 * 2 * np.pi / w_min
        if abs(sigma) * t_end < 3:  # too close to the boundary to see in this window
            continue
        t, x = simulate(M, C, Kt, [1e-5, 0.0], t_end, n_steps=3000)
        amp = np.linalg.norm(x, axis=1)
        q = len(t) // 4
        grows = amp[-q:].max() > amp[:q].max()
        assert bool(is_stable(a)) == (not grows)
        assert bool(is_stable(a)) == (sigma < 0)
        # envelope slope ~ growth rate
        slope = np.log(amp[-q:].max() / amp[:q].max()) / (t[-q] - t[0])
        assert slope == pytest.approx(sigma, rel=0.35, abs=0.05 / t_end)
        n_stable += bool(is_stable(a))
        n_unstable += not is_stable(a)
        checked += 1
    assert n_stable >= 5 and n_unstable >= 5


def test_undamped_flutter_is_the_complex_eigenvalue_condition():
    M = np.diag([50.0, 50.0])
    K = np.diag([1e5, 1.3e5])
    # the weak axis e1 lies between the normal (-20 deg) and the force (+10 deg)
    for kcb, flutter in ((1e3, False), (4e4, True), (1e5, False)):
        r = analyse(type("S", (), {"M": M, "C": np.zeros((2, 2)), "K": K})(), kcb, 30.0, -20.0)
        assert (r.discriminant < 0) == flutter
        assert (r.growth_rate > 1e-9) == flutter


def test_plane_model_from_the_arm(arm, robot):
    q = robot.pose("P1")
    pm = plane_model(arm, q)
    P = pm.axes
    C3 = tcp_compliance(arm, q)[:3, :3]
    assert np.allclose(np.linalg.inv(pm.K), P @ C3 @ P.T, rtol=1e-10)  # condensed, not diag
    assert abs(pm.K[0, 1]) > 0  # coupling kept
    assert np.all(np.linalg.eigvalsh(pm.M) > 0) and np.all(np.linalg.eigvalsh(pm.C) > 0)
    w2 = np.sort(np.sqrt(np.linalg.eigvals(np.linalg.solve(pm.M, pm.K)).real)) / (2 * np.pi)
    assert np.all(w2 <= np.sort(pm.freq_hz) * (1 + 1e-9))  # residual flexibility lowers them
    assert w2[0] > 0.9 * modes(arm, q).freq_hz[0]
    ks = np.linalg.eigvalsh(pm.K)
    assert ks[0] < 2e5 < ks[1]  # weak Y axis at P1 (thesis)


def test_cnc_stable_where_robot_chatters_at_p1(arm, robot):
    pm = plane_model(arm, robot.pose("P1"))
    n, f = process_vectors(165.0, 30.0)
    lim = float(critical_kcb(pm.M, pm.C, pm.K, n, f))
    kcb = 1.5 * lim
    robot_res = analyse(pm, kcb, 30.0, 165.0)
    cnc = cnc_model(5e7, float(np.trace(pm.M)) / 2, axes=pm.axes)
    cnc_res = analyse(cnc, kcb, 30.0, 165.0)
    assert not robot_res.is_stable and robot_res.growth_rate > 0
    assert cnc_res.is_stable and cnc_res.growth_rate < 0
    t, x = simulate(pm.M, pm.C, robot_res.K_total, 1e-5 * n, 2.0, 2000)
    amp = np.linalg.norm(x, axis=1)
    assert amp[-200:].max() > 10 * amp[:200].max()
    # the robot's orbit is an oval: principal extents differ
    s = np.linalg.svd(x[-500:] - x[-500:].mean(axis=0), compute_uv=False)
    assert 1.1 * s[1] < s[0] < 20 * s[1]  # an oval, neither a circle nor a line
    t, x = simulate(cnc.M, cnc.C, cnc_res.K_total, 1e-5 * n, 2.0, 2000)
    assert np.linalg.norm(x[-200:], axis=1).max() < 1e-3 * 1e-5
