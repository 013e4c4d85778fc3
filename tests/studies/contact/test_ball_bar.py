import numpy as np
import pytest

from flexarm.studies.contact.ball_bar import (
    load_point_compliance,
    measured_deviation,
    predict_circle,
    rapid_circle,
    weak_directions,
)


@pytest.fixture(scope="module")
def setup30(robot, module):
    return rapid_circle(robot, module, "Path_30", step_mm=5.0)


def test_geometry_of_the_thesis_circles(robot, module, setup30):
    assert np.allclose(setup30.pivot * 1e3, [1333.34, 47.78, 588.13], atol=0.01)
    assert abs(setup30.radius * 1e3 - 155.0) < 0.01
    for name, r in (("Path_40", 118.427), ("Path_50", 142.916)):
        s = rapid_circle(robot, module, name, step_mm=10.0)
        assert np.allclose(s.pivot * 1e3, [1333.34, 47.78, 588.13], atol=0.01)
        assert abs(s.radius * 1e3 - r) < 0.01
        assert abs(s.bar_length.mean() * 1e3 - 155.0) < 0.01


def test_zero_load_zero_and_linear_scaling(arm, setup30):
    p = predict_circle(arm, setup30, [0.0, 200.0, 800.0])
    assert np.all(p.deviation[0] == 0.0)
    assert np.abs(p.deviation[2] - 4 * p.deviation[1]).max() <= 1e-12
    assert np.abs(p.deviation[2]).max() > 1e-3  # millimetres at 800 N: a real effect
    pull = predict_circle(arm, setup30, [800.0], pull=True)
    assert np.allclose(pull.deviation[0], -p.deviation[2], atol=1e-15)


def test_bar_reading_is_the_compliance_along_the_bar(arm, setup30):
    p = predict_circle(arm, setup30, [800.0])
    C = load_point_compliance(arm, setup30)
    u = setup30.bar_dirs
    assert np.allclose(p.bar[0], 800.0 * np.einsum("ni,nij,nj->n", u, C, u), rtol=1e-12)
    assert np.all(p.bar[0] > 0)  # pushing lengthens the bar
    assert np.allclose(p.bar, p.radial)  # pivot at the centre: bar == in-plane radial


def test_largest_deviation_where_load_is_along_the_weak_direction(arm, setup30):
    p = predict_circle(arm, setup30, [800.0])
    k = np.argmax(np.abs(p.bar[0]))
    lam, v = weak_directions(arm, setup30)
    align = np.abs(np.sum(v * setup30.bar_dirs, axis=1))
    a_dev = np.degrees(setup30.angles[k])
    a_weak = np.degrees(setup30.angles[np.argmax(align)])
    diff = (a_dev - a_weak + 90) % 180 - 90  # +-u give the same projection
    assert abs(diff) < 10.0
    assert abs(abs(v[k, 1]) - 1) < 0.01  # the weak direction is base Y (thesis)
    assert abs(abs(a_dev) - 90) < 5.0


def test_tilted_circle_force_not_horizontal(robot, module, arm):
    s = rapid_circle(robot, module, "Path_40", step_mm=10.0)
    assert np.abs(s.bar_dirs[:, 2]).min() > 0.5  # 100 mm above the pivot on a 155 mm bar
    p = predict_circle(arm, s, [800.0])
    assert np.abs(p.z).max() > 2 * np.abs(predict_circle(
        arm, rapid_circle(robot, module, "Path_30", step_mm=10.0), [800.0]).z).max()


def test_measured_overlay_relative_to_zero_load(setup30):
    P = setup30.points
    ang, bar, nrm, f = measured_deviation(
        setup30, np.r_[P + 1e-4, P + 1e-4 + 3e-4 * setup30.bar_dirs],
        np.r_[np.zeros(len(P)), np.full(len(P), 400.0)])
    assert np.allclose(bar[len(P):], 3e-4, atol=1e-7)
    assert np.allclose(bar[:len(P)], 0.0, atol=1e-12)


def test_along_bar_is_the_dot_product_with_each_bar_direction(setup30):
    rng = np.random.default_rng(3)
    n = len(setup30.points)
    v = rng.normal(size=(2, n, 3))
    u = setup30.points - setup30.pivot
    u /= np.linalg.norm(u, axis=1)[:, None]
    dots = [[float(v[k, i] @ u[i]) for i in range(n)] for k in range(2)]
    # unit directions and O(1) vectors: the sums of three products agree to round-off
    assert np.allclose(setup30.along_bar(v), dots, rtol=0, atol=1e-14)
    assert np.allclose(setup30.along_bar(v[1]), dots[1], rtol=0, atol=1e-14)  # one vector each
    assert np.allclose(setup30.along_bar(-3.0 * setup30.bar_dirs), -3.0, rtol=0, atol=1e-14)
