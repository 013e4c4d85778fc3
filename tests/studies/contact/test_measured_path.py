"""A measured circle run is overlaid only when its readings lie on the programmed
circle: a 10x typo or a run of another circle is refused with the reading, its distance
and the circle."""

from __future__ import annotations

from importlib.resources import files

import numpy as np
import pytest

from flexarm.robot.formats.rapid import read_rapid
from flexarm.studies.contact.ball_bar import circle_offsets, rapid_circle
from flexarm.studies.contact.loaded_circle import THESIS_RAPID, _measured
from flexarm.validation import PathData, read_measurements
from flexarm.validation.tolerances import tol


@pytest.fixture(scope="module")
def setup(robot):
    return rapid_circle(robot, read_rapid(THESIS_RAPID), "Path_30", None, "tool0", 10.0)


def test_offsets_from_a_circle_analytically():
    from types import SimpleNamespace

    n = np.array([0.0, 0.6, 0.8])
    c = SimpleNamespace(centre=np.array([1.0, 2.0, 3.0]), normal=n, radius=0.2)
    u = np.array([1.0, 0.0, 0.0])  # in the plane
    v = np.cross(n, u)
    a = np.linspace(0, 2 * np.pi, 7)[:, None]
    on = c.centre + 0.2 * (np.cos(a) * u + np.sin(a) * v)
    assert circle_offsets(c, on).max() < 1e-15
    off = on + 0.03 * n + 0.04 * (np.cos(a) * u + np.sin(a) * v)  # 3 up, 4 out: 5
    assert np.allclose(circle_offsets(c, off), 0.05, rtol=0, atol=1e-15)
    assert circle_offsets(c, c.centre[None])[0] == pytest.approx(0.2)


def test_the_shipped_circle_run_lies_on_its_circle(setup, robot):
    example = files("flexarm") / "data" / "examples" / "circle_static_example.csv"
    ang, bar, nrm, f = _measured(setup, robot.chain, example)
    assert len(f) == 73 and np.abs(bar).max() < tol.path_max_offset


def _run(setup, radius=None, typo=None):
    a = np.linspace(0, 2 * np.pi, 13)[:-1]
    R = setup.radius if radius is None else radius
    u = setup.plane_axes
    P = setup.centre + R * (np.cos(a)[:, None] * u[0] + np.sin(a)[:, None] * u[1])
    if typo is not None:
        P[typo, 0] *= 10
    return PathData(steps=np.arange(12), points=P, force=np.full(12, 400.0))


def test_on_the_circle_is_overlaid(setup, robot):
    _, bar, _, _ = _measured(setup, robot.chain, _run(setup))
    assert np.abs(bar).max() < 1e-6  # the fitted circle on the bar's sphere: 13 nm apart


@pytest.mark.parametrize("radius, typo, step", [
    (None, 4, "4"),        # x typed ten times too large: that reading
    (0.1, None, r"\d+"),   # another circle, 100 mm instead of 155 mm: every reading
])
def test_off_the_circle_is_refused(setup, robot, radius, typo, step):
    data = _run(setup, radius, typo)
    d = circle_offsets(setup, data.points).max() * 1e3
    if radius is not None:
        assert d == pytest.approx(55.0, abs=0.05)
    with pytest.raises(ValueError, match=rf"^measured circle, step {step}: the reading .* mm "
                                         rf"lies {d:.1f} mm from the programmed circle "
                                         r"Path_30 .*radius 155\.0 mm; at most 10 mm\)"):
        _measured(setup, robot.chain, data)


def test_a_static_schema_reading_off_the_circle_names_series_and_step(setup, robot, tmp_path):
    example = files("flexarm") / "data" / "examples" / "circle_static_example.csv"
    data = read_measurements(example)
    disp = np.array(data.disp)
    k = int(np.flatnonzero((data.series == "F800N") & (data.steps == 7))[0])
    disp[k, 2] += 0.5
    from dataclasses import replace

    with pytest.raises(ValueError, match=r"series 'F800N', step 7: the reading .* lies 50\d\.\d "
                                         r"mm from the programmed circle"):
        _measured(setup, robot.chain, replace(data, disp=disp))
