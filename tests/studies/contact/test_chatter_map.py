import numpy as np
import pytest

from flexarm.studies.contact.chatter import analyse, cnc_model, plane_model, process_vectors
from flexarm.studies.contact.chatter_map import (
    chatter_limits_map,
    chatter_map,
    critical_kcb,
    recommendation,
    worst_normal,
)


def test_critical_kcb_matches_a_scan(arm, robot):
    pm = plane_model(arm, robot.pose("P1"))
    for nd in (0.0, 160.0):
        n, f = process_vectors(nd, 30.0)
        lim = float(critical_kcb(pm.M, pm.C, pm.K, n, f))
        assert 1e4 < lim < 1e7
        assert analyse(pm, lim * 0.999, 30.0, nd).is_stable
        assert not analyse(pm, lim * 1.001, 30.0, nd).is_stable


def test_critical_kcb_batched_equals_single():
    ms = [cnc_model([1e5, k], 50.0, 0.01) for k in (1.2e5, 1.5e5, 3e5)]
    n, f = process_vectors(-20.0, 30.0)  # weak axis e1 between normal and force
    M = np.array([m.M for m in ms])
    C = np.array([m.C for m in ms])
    K = np.array([m.K for m in ms])
    batch = critical_kcb(M, C, K, n, f)
    single = [float(critical_kcb(m.M, m.C, m.K, n, f)) for m in ms]
    assert np.allclose(batch, single)
    assert batch[0] < batch[1]  # closer stiffnesses couple more easily


def test_worst_normal_is_no_larger_than_any_given(arm, robot):
    pm = plane_model(arm, robot.pose("P1"))
    kw, ang = worst_normal(pm.M, pm.C, pm.K, 30.0)
    for nd in (0.0, 45.0, 90.0, 160.0):
        n, f = process_vectors(nd, 30.0)
        assert kw <= critical_kcb(pm.M, pm.C, pm.K, n, f) * (1 + 1e-9)


def test_map_and_recommendation(arm, robot):
    q2 = np.radians(np.linspace(-40, 100, 6))
    q3 = np.radians(np.linspace(-100, 60, 6))
    cm = chatter_map(arm, robot.pose("P1"), q2, q3, 30.0, lower=robot.lower, upper=robot.upper)
    assert cm.kcb.shape == (6, 6)
    fin = np.isfinite(cm.kcb)
    assert fin.sum() > 10 and np.all(cm.kcb[fin] > 0)
    assert cm.kcb[fin].max() > 2 * cm.kcb[fin].min()  # the pose matters
    best = cm.best(1)[0]
    assert best[2] >= np.nanmax(np.where(fin, cm.kcb, -np.inf))
    text = recommendation(cm)
    assert "weak Y" in text and "stiff configurations" in text


def test_batched_plane_matrices_equal_the_per_pose_model(robot, arm):
    from flexarm.studies.contact.chatter import plane_model
    from flexarm.studies.contact.plane_batch import plane_matrices

    rng = np.random.default_rng(3)
    Q = robot.lower + (robot.upper - robot.lower) * rng.random((12, 6))
    M, C, K, P = plane_matrices(arm, Q.reshape(3, 4, 6), chunk=5)
    assert M.shape == (3, 4, 2, 2) and P.shape == (3, 4, 2, 3)
    for i, q in enumerate(Q):
        pm = plane_model(arm, q)
        for A, B in ((pm.M, M.reshape(-1, 2, 2)[i]), (pm.C, C.reshape(-1, 2, 2)[i]),
                     (pm.K, K.reshape(-1, 2, 2)[i]), (pm.axes, P.reshape(-1, 2, 3)[i])):
            np.testing.assert_allclose(B, A, rtol=1e-9, atol=1e-12 * np.abs(A).max())


def test_cubic_roots_degenerate_leading_term():
    from flexarm.studies.contact.chatter_map import _cubic_roots

    c = np.array([[0.0, 1.0, -3.0, 2.0], [0.0, 0.0, 2.0, -4.0], [1.0, -6.0, 11.0, -6.0]])
    r = _cubic_roots(c)
    assert np.allclose(np.sort(r[0, :2].real), [1, 2]) and np.isnan(r[0, 2])
    assert np.isclose(r[1, 0].real, 2.0) and np.isnan(r[1, 1:]).all()
    assert np.allclose(np.sort(r[2].real), [1, 2, 3])


@pytest.fixture(scope="module")
def limits_map(arm, robot):
    return chatter_limits_map(arm, robot.pose("P1"), robot.lower, robot.upper, n=7)


def test_limits_map_spans_the_joint_limits(limits_map, arm, robot):
    cm = limits_map
    np.testing.assert_array_equal(cm.q2, np.linspace(robot.lower[1], robot.upper[1], 7))
    np.testing.assert_array_equal(cm.q3, np.linspace(robot.lower[2], robot.upper[2], 7))
    ref = chatter_map(arm, robot.pose("P1"), cm.q2, cm.q3, 30.0, lower=robot.lower,
                      upper=robot.upper)
    np.testing.assert_array_equal(cm.kcb, ref.kcb)
    assert np.isinf(cm.kcb).any() and np.isfinite(cm.kcb).sum() > 20
    with pytest.raises(ValueError, match="at least 2"):
        chatter_limits_map(arm, robot.pose("P1"), robot.lower, robot.upper, n=1)


def test_text_is_the_best_poses_and_the_recommendation(limits_map):
    lines = limits_map.text().splitlines()
    assert len(lines) == 4 and lines[3] == recommendation(limits_map)
    for line, (b2, b3, k) in zip(lines[:3], limits_map.best(3), strict=True):
        assert line == f"best: q2={b2:7.1f} deg q3={b3:7.1f} deg limit K_c b={k:.3g} N/m"


def test_best_poses_keep_off_the_joint_limits(limits_map, robot):
    from flexarm.studies.contact.chatter_map import LIMIT_MARGIN

    assert limits_map.is_excluded[[0, -1], :].all() and limits_map.is_excluded[:, [0, -1]].all()
    best = limits_map.best(3)
    assert best
    for b2, b3, _k in best:
        q = np.radians([b2, b3])
        assert np.all(q - robot.lower[1:3] >= LIMIT_MARGIN - 1e-12)
        assert np.all(robot.upper[1:3] - q >= LIMIT_MARGIN - 1e-12)
    assert "joint limit" in recommendation(limits_map)


def test_write_csv_round_trip(limits_map, tmp_path):
    cm = limits_map
    path = cm.write_csv(tmp_path / "sub" / "chatter_map.csv")
    assert path.read_text().splitlines()[0] == (
        "q2_deg,q3_deg,kcb_limit_N_per_m,normal_deg,k_weak_N_per_m,excluded")
    rows = np.loadtxt(path, delimiter=",", skiprows=1)
    G2, G3 = np.meshgrid(np.degrees(cm.q2), np.degrees(cm.q3), indexing="ij")
    assert rows.shape == (49, 6)
    for col, ref in zip(rows.T, (G2, G3, cm.kcb, cm.normal_deg, cm.k_weak,
                                 cm.is_excluded), strict=True):
        np.testing.assert_allclose(col, ref.ravel(), rtol=1e-8, atol=1e-12)
    assert np.isinf(rows[:, 2]).sum() == np.isinf(cm.kcb).sum() > 0
    # the exact bytes of numpy's "%.9g" writer
    ref = tmp_path / "ref.csv"
    np.savetxt(ref, np.column_stack([G2.ravel(), G3.ravel(), cm.kcb.ravel(),
                                     cm.normal_deg.ravel(), cm.k_weak.ravel(),
                                     cm.is_excluded.ravel()]),
               delimiter=",", comments="", fmt="%.9g",
               header="q2_deg,q3_deg,kcb_limit_N_per_m,normal_deg,k_weak_N_per_m,excluded")
    assert path.read_bytes() == ref.read_bytes()
