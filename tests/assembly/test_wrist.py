"""The demo arm's coupled wrist: coupling from the gear trains, K_w = C^T diag(k) C, and
its effect on the TCP compliance and the modes checked against independent formulas."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flexarm.assembly.analyses import modes, natural_frequencies, tcp_compliance
from flexarm.assembly.emodel import emodel
from flexarm.assembly.flexible import coupled_wrist_stiffness
from flexarm.assembly.system import system_matrices
from flexarm.robot.demo_arm import WRIST_TRAINS, wrist_coupling
from flexarm.robot.kinematics import jacobian

POSES = ("P1", "P2", "P3")


@pytest.fixture(scope="module")
def wrist_k(demo_robot):
    """(3,) joint-referred torsion stiffness of the wrist trains [N m/rad]."""
    return np.array([j.model.torsion for j in demo_robot.joints[-3:]])


@pytest.fixture(scope="module")
def e_pair(demo_robot):
    """E-model (surface mass properties) without and with the coupled wrist."""
    e = emodel(demo_robot, method="surface")
    return e, dataclasses.replace(e, wrist_stiffness=coupled_wrist_stiffness(demo_robot))


def _delta_tcp(robot, q, k):
    """ΔC_TCP = J_w (K_w^-1 - diag(1/k)) J_w^T: the wrist joints are in series with the
    rest of the (statically determinate) chain, so only their compliance block changes."""
    C = np.asarray(robot.wrist_coupling)
    Ci = np.linalg.inv(C)
    dCq = Ci @ np.diag(1 / k) @ Ci.T - np.diag(1 / k)
    J = jacobian(robot.chain, q)[:, -3:]
    return J @ dCq @ J.T


def test_demo_coupling_from_gear_trains(demo_robot):
    C = np.asarray(demo_robot.wrist_coupling)
    assert np.array_equal(C, wrist_coupling())
    # unit lower triangular: joint 4 drives nothing else; c54 = 1/40, c64 = 1/25, c65 = 1/20
    assert np.array_equal(C, [[1, 0, 0], [0.025, 1, 0], [0.04, 0.05, 1]])
    # the trains multiply to the joints' gear ratios
    ratios = {j.name: j.gear_ratio for j in demo_robot.joints}
    for name, stages in WRIST_TRAINS.items():
        assert np.prod(list(stages.values())) == pytest.approx(ratios[name], rel=1e-15)


def test_coupled_stiffness_values(demo_robot, wrist_k):
    K = coupled_wrist_stiffness(demo_robot)
    k4, k5, k6 = wrist_k
    c54, c64, c65 = 0.025, 0.04, 0.05
    hand = np.array([
        [k4 + c54**2 * k5 + c64**2 * k6, c54 * k5 + c64 * c65 * k6, c64 * k6],
        [c54 * k5 + c64 * c65 * k6, k5 + c65**2 * k6, c65 * k6],
        [c64 * k6, c65 * k6, k6],
    ])
    assert np.allclose(K, hand, rtol=1e-14, atol=0)
    assert np.allclose(K[0, 1:], [6550.0, 6000.0]) and K[1, 2] == pytest.approx(7500.0)
    assert np.array_equal(K, K.T) and np.linalg.eigvalsh(K).min() > 0.9 * k6
    # the diagonal stays within 0.2 % of the uncoupled joint stiffnesses (k6 exactly)
    assert np.abs(np.diag(K) / wrist_k - 1).max() < 2e-3 and K[2, 2] == k6
    # compliance: joint 4 under its own torque keeps 1/k4; the cross term is -c54/k4
    Ci = np.linalg.inv(K)
    assert Ci[0, 0] == pytest.approx(1 / k4, rel=1e-12)
    assert Ci[0, 1] == pytest.approx(-c54 / k4, rel=1e-10)


def test_identity_coupling_gives_uncoupled_springs(demo_robot, wrist_k, e_pair):
    for C in (None, np.eye(3)):
        r = dataclasses.replace(demo_robot, wrist_coupling=None if C is None
                                else tuple(map(tuple, C.tolist())))
        assert np.array_equal(coupled_wrist_stiffness(r), np.diag(wrist_k))
    e, _ = e_pair
    q = demo_robot.pose("P1")
    ei = dataclasses.replace(e, wrist_stiffness=np.diag(wrist_k))
    assert np.allclose(tcp_compliance(ei, q), tcp_compliance(e, q), rtol=1e-12, atol=0)
    assert np.allclose(natural_frequencies(ei, q), natural_frequencies(e, q), rtol=1e-12)


def test_singular_coupling_rejected(demo_robot):
    with pytest.raises(ValueError, match="invertible"):
        dataclasses.replace(demo_robot, wrist_coupling=((1, 0, 0), (1, 0, 0), (0, 0, 1)))


def test_emodel_and_default_flexible_ignore_the_coupling(demo_robot, e_pair):
    """Only ``coupled_wrist=True`` uses the coupling: the E-model is unchanged."""
    e, _ = e_pair
    assert demo_robot.wrist_stiffness is None and e.wrist_stiffness is None
    plain = emodel(dataclasses.replace(demo_robot, wrist_coupling=None), method="surface")
    for p in POSES:
        q = demo_robot.pose(p)
        assert np.array_equal(tcp_compliance(e, q), tcp_compliance(plain, q))


def test_emodel_wrist_tcp_compliance_matches_series_formula(demo_robot, wrist_k, e_pair):
    e, ew = e_pair
    rel = {}
    for p in POSES:
        q = demo_robot.pose(p)
        dC = tcp_compliance(ew, q) - tcp_compliance(e, q)
        ref = _delta_tcp(demo_robot, q, wrist_k)
        assert np.abs(dC - ref).max() < 1e-10 * np.abs(ref).max(), p
        rel[p] = np.diag(dC) / np.diag(tcp_compliance(e, q))
    # visible at the TCP: P3 Cxx +1.15 %, P1 rotation about x -2.8 %
    assert rel["P3"][0] == pytest.approx(0.0115, abs=5e-4)
    assert rel["P1"][3] == pytest.approx(-0.0277, abs=1e-3)
    assert np.abs(rel["P1"][:3]).max() < 2e-3  # P1 translations barely move (joints 1-3)


def test_emodel_wrist_modes(demo_robot, e_pair):
    """Exact: eigenvalues of K + ΔK (ΔK inserted by hand at the torsion coordinates)
    and the trace identity sum(Δλ) = tr(M^-1 ΔK); magnitude of the wrist-mode shift."""
    e, ew = e_pair
    k = np.array([j.model.torsion for j in demo_robot.joints[-3:]])
    C = np.asarray(demo_robot.wrist_coupling)
    dKw = C.T @ np.diag(k) @ C - np.diag(k)
    names = e.coordinate_names
    tors = [names.index(f"joint_{j}.torsion") for j in (4, 5, 6)]
    for p in POSES:
        q = demo_robot.pose(p)
        sm = system_matrices(e, q)
        dK = np.zeros_like(sm.K)
        dK[np.ix_(tors, tors)] = dKw
        lam_hand = np.sort(np.linalg.eigvals(np.linalg.solve(sm.M, sm.K + dK)).real)
        lam0 = (2 * np.pi * natural_frequencies(e, q)) ** 2
        lam1 = (2 * np.pi * natural_frequencies(ew, q)) ** 2
        assert np.allclose(lam1, lam_hand, rtol=1e-9), p
        assert (lam1 - lam0).sum() == pytest.approx(np.trace(np.linalg.solve(sm.M, dK)),
                                                    rel=1e-8)
    # P1: mode 6 (139.6 Hz) stores 88 % of its strain energy in the wrist joints and is
    # raised by 0.21 %; the first-order estimate phi^T ΔK phi gives the right sign and
    # size (0.58 % vs exact 0.42 % in λ: the neighbouring wrist modes mix)
    q = demo_robot.pose("P1")
    m = modes(e, q)
    f1 = natural_frequencies(ew, q)
    assert m.energy[3:, 5].sum() > 0.85
    assert f1[5] / m.freq_hz[5] - 1 == pytest.approx(0.0021, abs=2e-4)
    sm = system_matrices(e, q)
    dK = np.zeros_like(sm.K)
    dK[np.ix_(tors, tors)] = dKw
    first = m.shapes[:, 5] @ dK @ m.shapes[:, 5] / m.omega[5] ** 2
    assert 0.003 < first < 0.007 and (f1[5] / m.freq_hz[5]) ** 2 - 1 > 0.5 * first
    # joints 1-3 modes do not move (< 0.01 %)
    assert np.abs(f1[:3] / m.freq_hz[:3] - 1).max() < 1e-4


@pytest.mark.slow
def test_cb_wrist_column_differs_by_the_series_formula(demo_robot, wrist_k):
    """compare_models' CB(10)+wrist vs CB(10) at P1-P3 (demo defaults, no full FE)."""
    from flexarm.assembly.flexible import flexible_arm
    from flexarm.studies.compare_models import compare_models

    rep = compare_models(demo_robot, POSES, full_fe=False, bode_freq_hz=np.geomspace(1, 1e3, 20))
    for p in POSES:
        cb, cw = rep.get("CB(10)", p), rep.get("CB(10)+wrist", p)
        ref = np.diag(_delta_tcp(demo_robot, demo_robot.pose(p), wrist_k))
        assert np.allclose(cw.C_diag - cb.C_diag, ref, rtol=1e-8, atol=1e-12 * cb.C_diag.max())
        df = cw.freq_hz / cb.freq_hz - 1
        assert np.abs(df[:3]).max() < 1e-4  # main-axis modes unchanged
        assert 1e-3 < np.abs(df).max() < 1e-2, p  # wrist modes move by 0.1-1 %
    # the full 6x6 difference, not only the diagonal
    from flexarm.assembly.build import BuildOptions, build_robot

    cb = BuildOptions("cb").resolved(demo_robot)
    b = build_robot(demo_robot, cb)
    a0, a1 = flexible_arm(demo_robot, cb, b), flexible_arm(demo_robot, cb, b, coupled_wrist=True)
    q = demo_robot.pose("P3")
    dC = tcp_compliance(a1, q) - tcp_compliance(a0, q)
    ref = _delta_tcp(demo_robot, q, wrist_k)
    assert np.abs(dC - ref).max() < 1e-10 * np.abs(ref).max()
