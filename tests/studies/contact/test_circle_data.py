from importlib.resources import files

import numpy as np
import pytest

from flexarm.studies.contact.ball_bar import measured_deviation, predict_circle, rapid_circle
from flexarm.studies.contact.circle_data import static_circle_readings, synthetic_static_circle
from flexarm.validation import read_measurements
from flexarm.validation.data.formats import write_static
from flexarm.validation.data.measurements import StaticData

EXAMPLE = files("flexarm") / "data" / "examples" / "circle_static_example.csv"


@pytest.fixture(scope="module")
def setup30(robot, module):
    return rapid_circle(robot, module, "Path_30", step_mm=5.0)


def _at(setup, pred, ang):
    """Predicted bar reading (k, m) interpolated at the measured angles."""
    o = np.argsort(setup.angles)
    return np.array([np.interp(ang, setup.angles[o], b[o], period=2 * np.pi) for b in pred.bar])


def test_static_schema_round_trip_gives_the_relative_deviation(arm, setup30, tmp_path):
    sigma = 2e-6
    d = synthetic_static_circle(arm, setup30, [0.0, 400.0, 800.0], sigma=sigma, n_points=18)
    path = write_static(tmp_path / "c.csv", StaticData(**d))
    data = read_measurements(path)
    assert isinstance(data, StaticData) and data.n_series == 3
    P, F = static_circle_readings(setup30, arm.chain, data)
    assert len(P) == 18 * 3 + 1  # the reference rows of loaded series are dropped
    assert sorted(set(F.tolist())) == [0.0, 400.0, 800.0]
    ang, bar, nrm, f = measured_deviation(setup30, P, F)
    pred = _at(setup30, predict_circle(arm, setup30, [0.0, 400.0, 800.0]), ang)
    level = np.searchsorted([0.0, 400.0, 800.0], f)
    model = pred[level, np.arange(len(f))]
    # sag and the reference offset cancel; what is left is noise and the bar's
    # second-order length change |d_perp|^2 / (2 L) (<= 20 um at 3 mm off-axis on 155 mm)
    assert np.abs(bar - model).max() < 0.01 * np.abs(model).max() + 5 * sigma
    assert np.abs(bar[f == 800.0]).max() > 2e-3


def test_shipped_example_is_a_circle_run_in_the_static_schema(arm, setup30):
    head = EXAMPLE.read_text().splitlines()[:4]
    assert any("SYNTHETIC" in line for line in head)
    data = read_measurements(EXAMPLE)
    assert isinstance(data, StaticData) and data.n_series == 3
    ang, bar, nrm, f = measured_deviation(setup30, *static_circle_readings(setup30, arm.chain,
                                                                             data))
    assert np.abs(bar[f == 0]).max() < 5e-5  # 0 N: relative to itself, noise only
    k = np.argmax(np.abs(np.where(f == 800, bar, 0)))
    assert abs(abs(np.degrees(ang[k])) - 90) < 20  # largest along the weak Y direction
    model = np.abs(predict_circle(arm, setup30, [800.0]).bar).max()
    assert 0.75 < np.abs(bar[k]) / model < 1.25  # the example tracks the demo arm
