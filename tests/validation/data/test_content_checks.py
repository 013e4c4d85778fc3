"""What a lab gets wrong in a measurement file, refused with the file, the line and the
figure: a pose that moves inside a load series, FRFs too short to have a peak, a data
row where the header belongs, a points table that does not fit the arm."""

from __future__ import annotations

import re

import numpy as np
import pytest

from flexarm.fe.errors import ReadError
from flexarm.validation import FrfData, example_path, read_measurements, read_static
from flexarm.validation.data.formats.csv_frf import check_lines
from flexarm.validation.data.formats.csv_points import read_points
from flexarm.validation.tolerances import tol

HEADER = "series, step, q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, q6_deg, fx_N, fy_N, fz_N, " \
         "dx_mm, dy_mm, dz_mm"


def _static(tmp_path, q2_of_step, n=5, name="s.csv"):
    """One series of ``n`` steps with joint 2 at ``q2_of_step(k)`` [deg]."""
    rows = [f"a, {k}, 0, {q2_of_step(k):g}, -19, 12, -15, -11, 0, {100 * k}, 0, 0, "
            f"{0.04 * k:g}, 0" for k in range(n)]
    path = tmp_path / name
    path.write_text("\n".join([HEADER, *rows]) + "\n")
    return path


@pytest.mark.parametrize("moved, line, value", [
    ({2: 53}, 4, "53"),             # one reading at another angle
    ({3: 60, 4: 60}, 5, "60"),      # moved for good after step 2
    ({1: 52.001}, 3, "52.001"),     # a thousandth of a degree is another pose too
])
def test_a_load_series_holds_one_pose(tmp_path, moved, line, value):
    path = _static(tmp_path, lambda k: moved.get(k, 52))
    message = (f"{path}, line {line}, column 'q2_deg': series 'a' has other joint angles here "
               f"than on line 2 ({value} instead of 52: a load series holds one pose; was the "
               "robot moved?)")
    with pytest.raises(ReadError, match="^" + re.escape(message) + "$"):
        read_static(path)


def test_a_path_series_moves_at_most_of_its_steps(tmp_path):
    """Changing at more than half of the steps is a path under load (the loaded circle in
    the static schema); a repeated first point, as the shipped circle run has, is fine."""
    n = 9
    allowed = int(tol.moving_series_share * (n - 1)) + 1  # changes a path needs at least
    path = _static(tmp_path, lambda k: 52 + max(k - (n - 1 - allowed), 0), n)
    assert np.ptp(read_static(path).q[:, 1]) > 0
    fewer = _static(tmp_path, lambda k: 52 + max(k - (n - allowed), 0), n, "f.csv")
    with pytest.raises(ReadError, match="a load series holds one pose"):
        read_static(fewer)
    from importlib.resources import files

    circle = read_measurements(files("flexarm") / "data" / "examples" /
                               "circle_static_example.csv")
    assert len(np.unique(circle.q[circle.series == "F0N"], axis=0)) == 24  # 25 readings


def _frf(lines: dict) -> FrfData:
    rows = [(p, i, o, f) for (p, i, o), n in lines.items() for f in np.arange(1.0, n + 1)]
    return FrfData(poses=[r[0] for r in rows], q=np.zeros((len(rows), 6)),
                   inputs=[r[1] for r in rows], outputs=[r[2] for r in rows],
                   freq_hz=[r[3] for r in rows], receptance=np.ones(len(rows)) * 1e-6 + 0j)


def test_frf_lines_for_a_peak():
    check_lines(_frf({("c1", "y", "y"): 3, ("c1", "y", "x"): 40}))
    with pytest.raises(ReadError, match=r"^FRF data: the FRF of pose 'c2', input y, output x "
                                        r"has 2 frequency lines; comparing FRFs needs at "
                                        r"least 3"):
        check_lines(_frf({("c1", "y", "y"): 5, ("c2", "y", "x"): 2}))


def test_frf_lines_name_the_csv_line(tmp_path):
    text = example_path("frf").read_text().splitlines()
    keep = [ln for ln in text if ", y, x, 10," not in ln and ", y, x, 12," not in ln
            and ", y, x, 15," not in ln]
    path = tmp_path / "frf.csv"
    path.write_text("\n".join(keep) + "\n")
    data = read_measurements(path)  # reading does not ask it
    first = next(k for k, ln in enumerate(keep, 1) if ", y, x, " in ln)
    with pytest.raises(ReadError, match=rf"^{re.escape(str(path))}, line {first}, column "
                                        r"'freq_Hz': the FRF of pose 'c1', input y, output x "
                                        r"has 2 frequency lines"):
        check_lines(data, path)


@pytest.mark.parametrize("kind", ["static", "modal", "frf", "path"])
def test_a_data_row_where_the_header_belongs(tmp_path, kind):
    lines = example_path(kind).read_text().splitlines()
    header = next(k for k, ln in enumerate(lines) if ln and not ln.startswith("#"))
    rest = lines[:header] + lines[header + 1:]
    first = next(k for k, ln in enumerate(rest, 1) if ln.strip() and not ln.startswith("#"))
    path = tmp_path / f"{kind}.csv"
    path.write_text("\n".join(rest) + "\n")
    with pytest.raises(ReadError, match=rf"line {first}: no header row: the first row "
                                        r"that is not a comment holds numbers \("):
        read_measurements(path)


def test_points_table_links_of_the_arm(tmp_path):
    path = tmp_path / "p.points.csv"
    path.write_text("node,link,x_mm,y_mm,z_mm\n1,2,0,0,450\n2,7,100,0,0\n")
    assert read_points(path).links.tolist() == [2, 7]  # without the arm: any link >= 0
    assert read_points(path, 8).n_points == 2
    with pytest.raises(ReadError, match=rf"^{re.escape(str(path))}, line 3, column 'link': "
                                        r"link 7 does not exist \(the arm has bodies 0\.\.6, "
                                        r"0 = base\)$"):
        read_points(path, 7)


def test_points_table_must_hold_every_node_of_the_file(tmp_path):
    from flexarm.robot import load_robot
    from flexarm.validation.dynamic.compare_shapes import measurement_points

    data = tmp_path / "shapes.uff"
    (tmp_path / "shapes.points.csv").write_text("node,link,x_mm,y_mm,z_mm\n100,1,87.5,0,0\n")
    robot = load_robot()
    assert measurement_points(data, robot, [100, 100]).nodes.tolist() == [100]
    with pytest.raises(ReadError, match=r"shapes\.points\.csv: node 101 of shapes\.uff is not "
                                        r"in it \(it has 100\)"):
        measurement_points(data, robot, [100, 101])
