"""The loop's error history: the figures in its CSV are an independent RMS of the readings.

The readings are made on the thesis's Path_30 circle (its circumcircle from three
robtargets, computed here) with a known radial error ``a + b cos 3θ`` at evenly spread
angles, so the RMS is also known in closed form, ``sqrt(a² + b²/2)``; the file is read
back with numpy, not with flexarm's reader.  A straight milling pass checks the
distance measure the same way.
"""

import csv

import numpy as np
import pytest

from flexarm.robot.formats.rapid import read_rapid
from flexarm.studies.compensation.lab.history import HISTORY_COLUMNS, path_history
from flexarm.validation.data.formats import write_path
from flexarm.validation.data.measurements import PathData

from ..conftest import MILLING, THESIS

#: (step, constant radial error a [mm], cos 3θ amplitude b [mm], out-of-plane offset [mm])
STEPS = [("nominal program", 0.1, 1.2, 0.05), ("compensated, nominal model", 0.02, 0.3, 0.01),
         ("compensated, identified model", -0.002, 0.011, 0.0)]


def circumcircle(p1, p2, p3):
    """(centre, unit normal, radius) of the circle through three points."""
    a, b = p1 - p3, p2 - p3
    n = np.cross(a, b)
    c = p3 + np.cross(a @ a * b - b @ b * a, n) / (2 * n @ n)
    return c, n / np.linalg.norm(n), np.linalg.norm(p1 - c)


def read_points(path):
    """Readings [mm] of a path CSV, by numpy (comments, a header, then step,x,y,z,f)."""
    lines = [x for x in open(path).read().splitlines() if x and not x.startswith("#")]
    return np.loadtxt(lines[1:], delimiter=",", ndmin=2)[:, 1:4]


def read_figures(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    assert tuple(rows[0]) == HISTORY_COLUMNS
    return [dict(zip(rows[0], r, strict=True)) for r in rows[1:]]


@pytest.fixture(scope="module")
def circle_steps(tmp_path_factory):
    """(folder, files, circle) of three measured Path_30 circles."""
    targets = read_rapid(THESIS).targets
    c, n, r = circumcircle(*(targets[t].pos_mm for t in ("Target_70", "Target_80",
                                                          "Target_90")))
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    theta = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    folder = tmp_path_factory.mktemp("history")
    files = []
    for k, (_step, a, b, off) in enumerate(STEPS):
        rad = r + a + b * np.cos(3 * theta)
        pts = c + rad[:, None] * (np.outer(np.cos(theta), u) + np.outer(np.sin(theta), v)) \
            + off * n
        files.append(write_path(folder / f"step{k}.csv", PathData(
            steps=np.arange(len(theta)), points=pts * 1e-3, force=np.full(len(theta), 800.0))))
    return folder, files, (c, n, r)


def test_circle_figures_are_an_independent_rms_of_the_readings(circle_steps):
    folder, files, (c, n, r) = circle_steps
    history = path_history(files, THESIS, [s[0] for s in STEPS])
    written = history.write(folder / "history.png")
    assert [p.name for p in written] == ["history.png", "history.csv"]
    assert written[0].stat().st_size > 20_000
    figures = read_figures(folder / "history.csv")
    assert [f["step"] for f in figures] == [s[0] for s in STEPS]
    first = None
    for f, path, (_step, a, b, _off) in zip(figures, files, STEPS, strict=True):
        p = read_points(path)
        d = p - c
        radial = np.linalg.norm(d - np.outer(d @ n, n), axis=1) - r
        rms = np.sqrt(np.mean(radial**2))
        assert f["procedure"] == "Path_30" and f["measure"] == "radial"
        assert int(f["readings"]) == len(p)
        assert abs(float(f["rms_mm"]) - rms) < 1e-9  # mm
        assert abs(float(f["rms_mm"]) - np.sqrt(a**2 + b**2 / 2)) < 1e-9
        assert abs(float(f["peak_mm"]) - np.abs(radial).max()) < 1e-9
        assert abs(float(f["peak_mm"]) - (abs(a) + abs(b))) < 1e-9  # θ = 0 is a reading
        first = rms if first is None else first
        assert float(f["gain"]) == pytest.approx(first / rms, rel=1e-9)
    print(history.text())  # noqa: T201


def test_a_straight_pass_is_measured_by_its_distance(tmp_path):
    x = np.linspace(1110.0, 1390.0, 281)
    dy, dz = 0.05 * np.sin(x / 7.0), np.full(len(x), 0.03)
    pts = np.c_[x, -150.0 + dy, 500.0 + dz]
    path = write_path(tmp_path / "line.csv", PathData(steps=np.arange(len(x)),
                                                      points=pts * 1e-3, force=np.zeros(len(x))))
    history = path_history([path], MILLING, ["before"], proc="Line")
    history.write_csv(tmp_path / "h.csv")
    (f,) = read_figures(tmp_path / "h.csv")
    p = read_points(path)
    dist = np.hypot(p[:, 1] + 150.0, p[:, 2] - 500.0)  # from the line y = -150, z = 500
    assert f["measure"] == "distance" and f["procedure"] == "Line"
    assert abs(float(f["rms_mm"]) - np.sqrt(np.mean(dist**2))) < 1e-9
    assert abs(float(f["peak_mm"]) - dist.max()) < 1e-9


def test_one_line_errors(circle_steps):
    _folder, files, _ = circle_steps
    with pytest.raises(ValueError, match="--label: 1 labels for 3 measured paths"):
        path_history(files, THESIS, ["only one"])
    with pytest.raises(ValueError, match="a second measured path of Path_30 in step 'same'"):
        path_history(files[:2], THESIS, ["same", "same"])
    with pytest.raises(ValueError, match="at least one step"):
        path_history([], THESIS)


def test_a_file_naming_its_procedure_is_set_against_that_one(tmp_path):
    """The thesis's ``main`` runs Path_50's circle: the lab's ``# procedure:`` comment
    decides, not the order of the procedures."""
    from flexarm.robot.paths import sample_procedure

    p = sample_procedure(read_rapid(THESIS).procedure("Path_50")).points_m
    data = PathData(steps=np.arange(len(p)), points=p * 1.0001, force=np.zeros(len(p)))
    named = write_path(tmp_path / "named.csv", data, ["procedure: Path_50"])
    plain = write_path(tmp_path / "plain.csv", data)
    history = path_history([named, plain], THESIS, ["named", "plain"])
    assert [m.run.name for m in history.measured] == ["Path_50", "main"]
    assert history.measured[0].named and history.measured[1].chosen
    assert history.figures()[0]["rms"] == history.figures()[1]["rms"]  # the same circle
