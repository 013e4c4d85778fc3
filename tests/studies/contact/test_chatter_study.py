import numpy as np
import pytest

from flexarm.studies.contact.chatter import plane_model, process_vectors
from flexarm.studies.contact.chatter_map import chatter_limits_map, critical_kcb, worst_normal
from flexarm.studies.contact.chatter_study import run_chatter, write_chatter_map


@pytest.fixture(scope="module")
def study(arm, robot):
    return run_chatter(arm, robot.pose("P1"), 5e5, 30.0, duration=0.5)


def test_limit_is_the_closed_form_of_the_plane_model(study, arm, robot):
    pm = plane_model(arm, robot.pose("P1"))
    _kc, worst = worst_normal(pm.M, pm.C, pm.K, 30.0)
    assert study.normal_deg == float(worst)
    n, f = process_vectors(study.normal_deg, 30.0)
    assert study.limit == float(critical_kcb(pm.M, pm.C, pm.K, n, f))
    assert 1e5 < study.limit < 5e5  # 2.54e5 N/m: the robot chatters at 5e5
    robot_, cnc = study.results
    np.testing.assert_array_equal(robot_.structure.K, pm.K)
    assert np.allclose(np.diag(cnc.structure.M), np.trace(pm.M) / 2)
    assert not robot_.is_stable and cnc.is_stable and np.isinf(study.limits[1])


def test_verdict_flips_at_the_limit(study, arm, robot):
    q = robot.pose("P1")
    below = run_chatter(arm, q, 0.99 * study.limit, 30.0, study.normal_deg, duration=0.01)
    above = run_chatter(arm, q, 1.01 * study.limit, 30.0, study.normal_deg, duration=0.01)
    assert below.results[0].is_stable and below.results[0].growth_rate < 0
    assert not above.results[0].is_stable and above.results[0].growth_rate > 0


def test_simulation_grows_for_the_robot_and_decays_for_the_cnc(study):
    assert study.x.shape == (2, len(study.t), 2) and study.t[-1] == 0.5
    amp = np.linalg.norm(study.x, axis=-1)
    n, _f = process_vectors(study.normal_deg, 30.0)
    np.testing.assert_allclose(study.x[:, 0], [1e-5 * n, 1e-5 * n])
    g = study.results[0].growth_rate
    tail = amp[0, -400:].max() / amp[0, :400].max()  # last vs first 0.05 s
    assert tail > 0.5 * np.exp(g * 0.45)
    assert amp[1, -400:].max() < 1e-3 * amp[1, 0]


def test_text_and_plots(study, tmp_path):
    lines = study.text().splitlines()
    assert len(lines) == 4
    assert lines[0].endswith("normal 165.0 deg, force 30.0 deg from it, K_c b 5e+05 N/m")
    assert lines[1].startswith("robot: K principal ") and lines[1].endswith("-> UNSTABLE")
    assert f"limit K_c b {study.limit:.3g} N/m" in lines[1]
    assert lines[2].startswith("CNC  : ") and "limit K_c b inf N/m -> stable" in lines[2]
    assert lines[3] == "verdict: robot CHATTERS (mode coupling); CNC stable"
    paths = study.write(tmp_path / "new")
    assert [p.name for p in paths] == ["chatter_time.csv", "chatter_time.png",
                                       "chatter_orbit.png"]
    assert all(p.stat().st_size > 0 for p in paths)


def test_write_chatter_map(arm, robot, tmp_path):
    cm = chatter_limits_map(arm, robot.pose("P1"), robot.lower, robot.upper, n=4)
    paths = write_chatter_map(tmp_path / "new", cm)
    assert [p.name for p in paths] == ["chatter_map.csv", "chatter_map.png"]
    rows = np.loadtxt(paths[0], delimiter=",", skiprows=1)
    np.testing.assert_allclose(rows[:, 2], cm.kcb.ravel(), rtol=1e-8)
    assert paths[1].stat().st_size > 0
