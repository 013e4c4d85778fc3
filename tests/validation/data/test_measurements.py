"""Measurement data sets and their CSV files (flexarm/validation/measurements.py, formats/).

Every malformed-file case is checked with its exact message: file, line, column.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from flexarm.fe.errors import ReadError
from flexarm.validation import (
    FrfData,
    MeasurementFileError,
    ModalData,
    PathData,
    StaticData,
    example_path,
    read_frf,
    read_measurements,
    read_modal,
    read_path,
    read_static,
    write_frf,
    write_measurements,
    write_modal,
    write_path,
    write_static,
)

STATIC_HEADER = ["series", "step", "q1_deg", "q2_deg", "q3_deg", "q4_deg", "q5_deg", "q6_deg",
                 "fx_N", "fy_N", "fz_N", "dx_mm", "dy_mm", "dz_mm"]
C1, C2 = ["0", "52", "-19", "12", "-15", "-11"], ["0", "0", "66", "0", "-66", "0"]
STATIC_ROWS = [  # file lines 3..8 (line 1 is a comment, line 2 the header)
    ["a", "0", *C1, "0", "0", "0", "0", "0", "0"],
    ["a", "1", *C1, "0", "400", "0", "0.009", "0.172", "-0.003"],
    ["a", "2", *C1, "0", "800", "0", "0.017", "0.344", "-0.007"],
    ["b", "0", *C2, "0", "0", "0", "0", "0", "0"],
    ["b", "1", *C2, "400", "0", "0", "0.101", "-0.002", "-0.02"],
    ["b", "2", *C2, "800", "0", "0", "0.198", "0", "-0.041"],
]
MODAL_HEADER = ["pose", "q1_deg", "q2_deg", "q3_deg", "q4_deg", "q5_deg", "q6_deg", "mode",
                "freq_Hz"]
MODAL_ROWS = [["c1", *C1, "1", "9.8"], ["c1", *C1, "2", "12.4"], ["c2", *C2, "1", "11.2"]]
FRF_HEADER = ["pose", "q1_deg", "q2_deg", "q3_deg", "q4_deg", "q5_deg", "q6_deg", "input",
              "output", "freq_Hz", "re_m_per_N", "im_m_per_N"]
FRF_ROWS = [["c1", *C1, "y", "y", "5", "6.3e-07", "-1.2e-08"],
            ["c1", *C1, "y", "y", "10", "1.6e-06", "-1.5e-07"],
            ["c1", *C1, "y", "x", "10", "-1.9e-07", "1.8e-08"]]
PATH_HEADER = ["step", "x_mm", "y_mm", "z_mm", "f_N"]
PATH_ROWS = [["0", "1433.34", "47.78", "588.13", "400"],
             ["1", "1404.05", "118.44", "588.127", "400"]]
LIMITS = np.deg2rad([[-170, 170], [-65, 85], [-180, 70], [-300, 300], [-130, 130],
                     [-300, 300]])


def render(header, rows) -> str:
    lines = ["# a comment line", ", ".join(header)] + [", ".join(r) for r in rows]
    return "\n".join(lines) + "\n"


def edit(header, rows, row, column, value):
    rows = [list(r) for r in rows]
    rows[row][header.index(column)] = value
    return rows


@pytest.fixture
def csv(tmp_path):
    """Write text to ``data.csv`` in a fresh folder; return its path."""
    def write(text: str, name: str = "data.csv"):
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path
    return write


def raises(path, message: str):
    return pytest.raises(ReadError, match="^" + re.escape(f"{path}, {message}") + "$")


# ---------------------------------------------------------------- well-formed files

@pytest.mark.parametrize(("kind", "cls", "n"), [
    ("static", StaticData, 10), ("modal", ModalData, 6), ("frf", FrfData, 10),
    ("path", PathData, 8),
])
def test_shipped_examples_parse(kind, cls, n):
    path = example_path(kind)
    assert path.read_text().startswith("# flexarm example")
    data = read_measurements(path)
    assert type(data) is cls and data.n_rows == n
    assert read_measurements(path, limits=LIMITS) == data


def test_static_example_content():
    d = read_static(example_path("static"))
    assert list(d.series_slices()) == ["c1_y", "c2_x"] and d.n_series == 2
    assert d.reference_rows().tolist() == [0, 5]
    assert np.all(d.disp[d.reference_rows()] == 0)
    assert d.steps.tolist() == [0, 1, 2, 3, 4] * 2
    assert d.force[4].tolist() == [0.0, 800.0, 0.0]
    assert d.disp[4, 1] == 0.344e-3 and d.sigma[0] == 15e-6
    assert d.q[0, 1] == np.deg2rad(52.0)
    assert d.moment is None and d.rot is None


@pytest.mark.parametrize(("header", "rows", "cls"), [
    (STATIC_HEADER, STATIC_ROWS, StaticData), (MODAL_HEADER, MODAL_ROWS, ModalData),
    (FRF_HEADER, FRF_ROWS, FrfData), (PATH_HEADER, PATH_ROWS, PathData),
])
def test_kind_is_recognised_from_the_columns_in_any_order(csv, header, rows, cls):
    order = list(reversed(range(len(header))))
    text = render([header[k] for k in order], [[r[k] for k in order] for r in rows])
    assert type(read_measurements(csv(text))) is cls


def test_comments_blank_lines_spaces_bom_and_case(csv):
    text = ("\ufeff# title\n\n   # indented comment\n"
            + "SERIES,Step," + ",".join(h.upper() for h in STATIC_HEADER[2:]) + "\n"
            + "\n".join(",  ".join(r) for r in STATIC_ROWS[:3]) + "\n\n# between series\n"
            + "\r\n".join(" ,".join(r) for r in STATIC_ROWS[3:]) + "\r\n# end\n")
    assert read_static(csv(text)) == read_static(csv(render(STATIC_HEADER, STATIC_ROWS), "b.csv"))


def test_quoted_labels_with_commas_round_trip(csv, tmp_path):
    rows = [[f'"{r[0]}, x"', *r[1:]] for r in STATIC_ROWS]
    d = read_static(csv(render(STATIC_HEADER, rows)))
    assert list(d.series_slices()) == ["a, x", "b, x"]
    assert read_static(write_static(tmp_path / "out.csv", d)) == d


def test_optional_columns(csv):
    header = MODAL_HEADER + ["damping_ratio"]
    d = read_modal(csv(render(header, [r + ["0.02"] for r in MODAL_ROWS])))
    assert d.damping_ratio.tolist() == [0.02] * 3
    assert d.pose_labels() == ["c1", "c2"] and d.n_poses == 2
    assert read_modal(csv(render(MODAL_HEADER, MODAL_ROWS), "b.csv")).damping_ratio is None


def test_load_unload_order_is_kept(csv):
    rows = [r for r in STATIC_ROWS[:3]] + [["a", "3", *C1, "0", "400", "0", "0.011", "0.18",
                                            "-0.003"]]
    d = read_static(csv(render(STATIC_HEADER, rows)))
    assert d.force[:, 1].tolist() == [0.0, 400.0, 800.0, 400.0]
    assert d.steps.tolist() == [0, 1, 2, 3]


def test_frf_values(csv):
    d = read_frf(csv(render(FRF_HEADER, FRF_ROWS)))
    assert d.receptance[0] == complex(6.3e-07, -1.2e-08)
    assert d.inputs.tolist() == ["y"] * 3 and d.outputs.tolist() == ["y", "y", "x"]
    assert d.input_axes.tolist() == [1, 1, 1] and d.output_axes.tolist() == [1, 1, 0]


def test_path_values(csv):
    d = read_path(csv(render(PATH_HEADER, PATH_ROWS)))
    assert d.points[1].tolist() == [1.40405, 0.11844, 0.588127]
    assert d.force.tolist() == [400.0, 400.0]


# ---------------------------------------------------------------- round trips

def _random_static(rng, n=12):
    series = np.repeat(["s1", "s 2", "s,3"], n // 3)
    steps = np.tile(np.arange(n // 3) * 2, 3)
    disp = rng.normal(size=(n, 3)) * 1e-4
    disp[steps == 0] = 0.0
    rot = rng.normal(size=(n, 3)) * 1e-5
    rot[steps == 0] = 0.0
    return StaticData(series=series, steps=steps, q=rng.uniform(-1, 1, size=(n, 6)),
                      force=rng.normal(size=(n, 3)) * 300, disp=disp,
                      moment=rng.normal(size=(n, 3)) * 20, rot=rot,
                      sigma=rng.uniform(1e-6, 3e-5, size=n))


def _random_modal(rng):
    q = np.repeat(rng.uniform(-1, 1, size=(2, 6)), 3, axis=0)
    return ModalData(poses=np.repeat(["p1", "p2"], 3), q=q, modes=[1, 2, 3] * 2,
                     freq_hz=rng.uniform(5, 60, 6), damping_ratio=rng.uniform(0, 0.1, 6))


def _random_frf(rng):
    q = np.repeat(rng.uniform(-1, 1, size=(1, 6)), 4, axis=0)
    return FrfData(poses=["p"] * 4, q=q, inputs=list("xxyz"), outputs=list("xyzz"),
                   freq_hz=rng.uniform(0, 100, 4),
                   receptance=rng.normal(size=4) * 1e-6 + 1j * rng.normal(size=4) * 1e-7)


def _random_path(rng):
    return PathData(steps=np.arange(5), points=rng.normal(size=(5, 3)),
                    force=rng.uniform(0, 800, 5))


@pytest.mark.parametrize(("make", "write", "read"), [
    (_random_static, write_static, read_static), (_random_modal, write_modal, read_modal),
    (_random_frf, write_frf, read_frf), (_random_path, write_path, read_path),
])
def test_write_then_read_is_exact(tmp_path, make, write, read):
    data = make(np.random.default_rng(3))
    path = write(tmp_path / "x.csv", data, comments=["seed 3", "two\nlines"])
    back = read(path)
    assert back == data and read_measurements(path) == data
    lines = path.read_text().splitlines()
    assert lines[0].startswith("# flexarm ") and lines[1:3] == ["# seed 3", "# two"]
    # deterministic bytes, nothing left behind
    first = path.read_bytes()
    write_measurements(path, back)
    assert path.read_bytes().splitlines()[2:] == first.splitlines()[5:]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.csv"]


@pytest.mark.parametrize("kind", ["static", "modal", "frf", "path"])
def test_examples_round_trip_in_canonical_units(tmp_path, kind):
    data = read_measurements(example_path(kind))
    path = write_measurements(tmp_path / "x.csv", data)
    assert read_measurements(path) == data


def test_written_static_file_uses_canonical_units(tmp_path):
    d = read_static(example_path("static"))
    text = write_static(tmp_path / "s.csv", d).read_text()
    header = text.splitlines()[1]
    assert header == ("series,step,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,fx_N,fy_N,fz_N,"
                      "dx_mm,dy_mm,dz_mm,sigma_mm")
    assert text.splitlines()[6] == "c1_y,4,0.0,52.0,-19.0,12.0,-15.0,-11.0,0.0,800.0,0.0," \
                                   "0.017,0.344,-0.007,0.015"


def test_writer_checks_the_type(tmp_path):
    modal = read_modal(example_path("modal"))
    with pytest.raises(ValueError, match="write_static needs a StaticData, got ModalData"):
        write_static(tmp_path / "x.csv", modal)
    with pytest.raises(ValueError, match="cannot write a dict as measurements"):
        write_measurements(tmp_path / "x.csv", {})


# ---------------------------------------------------------------- malformed files

def test_missing_required_column(csv):
    header = [h for h in STATIC_HEADER if h != "fz_N"]
    rows = [r[:10] + r[11:] for r in STATIC_ROWS]
    path = csv(render(header, rows))
    with raises(path, "line 2: missing required column 'fz_N' for a static file "
                      "(kind guessed from the other columns)") as info:
        read_measurements(path)
    assert isinstance(info.value, MeasurementFileError) and info.value.line == 2
    with raises(path, "line 2: missing required column 'fz_N' for a static file"):
        read_static(path)


def test_missing_several_columns_with_forced_kind(csv):
    path = csv(render(MODAL_HEADER, MODAL_ROWS))
    with raises(path, "line 2: missing required columns 'input', 'output', 're_m_per_N', "
                      "'im_m_per_N' for an FRF file"):
        read_frf(path)


def test_unknown_unit(csv):
    header = [h if h != "dy_mm" else "dy_mmm" for h in STATIC_HEADER]
    path = csv(render(header, STATIC_ROWS))
    with raises(path, "line 2, column 'dy_mmm': unknown unit 'mmm' for a length "
                      "(accepted: m, mm, um, cm, in)") as info:
        read_measurements(path)
    assert info.value.column == "dy_mmm"


def test_missing_unit_suffix(csv):
    header = [h if h != "fy_N" else "fy" for h in STATIC_HEADER]
    path = csv(render(header, STATIC_ROWS))
    with raises(path, "line 2, column 'fy': missing unit suffix (a force: N, kN, "
                      "e.g. 'fy_N')"):
        read_measurements(path)


def test_unknown_column(csv):
    path = csv(render(STATIC_HEADER + ["temperature_C"], [r + ["21"] for r in STATIC_ROWS]))
    with raises(path, "line 2, column 'temperature_C': unknown column for a static file "
                      "(known: series, step, q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, q6_deg, "
                      "fx_N, fy_N, fz_N, dx_mm, dy_mm, dz_mm, mx_Nm, my_Nm, mz_Nm, rx_mrad, "
                      "ry_mrad, rz_mrad, sigma_mm)"):
        read_measurements(path)


def test_column_of_another_kind_is_unknown(csv):
    path = csv(render(MODAL_HEADER + ["input"], [r + ["x"] for r in MODAL_ROWS]))
    with raises(path, "line 2, column 'input': unknown column for a modal file (known: pose, "
                      "q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, q6_deg, mode, freq_Hz, "
                      "damping_ratio)"):
        read_measurements(path)


def test_unknown_kind(csv):
    path = csv("time_s, value\n0, 1\n")
    with raises(path, "line 1: cannot tell the kind of measurement file from its columns "
                      "(expected the columns of one of: static, modal, frf, path; see "
                      "flexarm.validation)"):
        read_measurements(path)


def test_ambiguous_kind(csv):
    header = FRF_HEADER + ["mode"]
    path = csv(render(header, [r + ["1"] for r in FRF_ROWS]))
    with raises(path, "line 2: the columns fit both a modal file and an FRF file; cannot "
                      "tell the kind of file"):
        read_measurements(path)


def test_guess_tie_is_ambiguous(csv):
    # modal: 6 present, 3 missing; path: 4 present, 1 missing; both all distinctive
    path = csv("mode, q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, x_mm, y_mm, z_mm, f_N\n"
               "1, 0, 0, 0, 0, 0, 1, 2, 3, 4\n")
    with raises(path, "line 1: the columns fit a modal file and a path file equally well; "
                      "cannot tell the kind of file"):
        read_measurements(path)


@pytest.mark.parametrize(("header", "message"), [
    ("series, q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, q6_deg",
     "'step', 'fx_N', 'fy_N', 'fz_N', 'dx_mm', 'dy_mm', 'dz_mm' for a static file"),
    ("pose, q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, q6_deg, freq_Hz", "'mode' for a modal file"),
    ("step, x_mm, y_mm, z_mm", "'f_N' for a path file"),
])
def test_kind_guess_from_distinctive_columns(csv, header, message):
    path = csv(header + "\n" + ", ".join(["1"] * (header.count(",") + 1)) + "\n")
    plural = "s" if "," in message.split(" for ")[0] else ""
    with raises(path, f"line 1: missing required column{plural} {message} "
                      "(kind guessed from the other columns)"):
        read_measurements(path)


def test_complete_kind_wins_over_a_partial_one(csv):
    path = csv("pose, q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, q6_deg, freq_Hz, mode, input\n"
               "p, 0, 0, 0, 0, 0, 0, 1, 1, x\n")
    with raises(path, "line 1, column 'input': unknown column for a modal file (known: pose, "
                      "q1_deg, q2_deg, q3_deg, q4_deg, q5_deg, q6_deg, mode, freq_Hz, "
                      "damping_ratio)"):
        read_measurements(path)


@pytest.mark.parametrize(("value", "message"), [
    ("nan", "'nan' is not a finite number"), ("NaN", "'NaN' is not a finite number"),
    ("inf", "'inf' is not a finite number"), ("", "empty value"),
    ("abc", "'abc' is not a number"), ("1,5", None), ("0x10", "'0x10' is not a number"),
])
def test_bad_numbers(csv, value, message):
    rows = edit(STATIC_HEADER, STATIC_ROWS, 4, "dy_mm", value)
    path = csv(render(STATIC_HEADER, rows))
    if message is None:  # a decimal comma makes one field too many
        message = ("15 fields, expected 14 as in the header (line 2); decimal commas? write 1.5, "
                   "not 1,5 (and quote a label holding a comma)")
        with raises(path, f"line 7: {message}"):
            read_measurements(path)
        return
    with raises(path, f"line 7, column 'dy_mm': {message}") as info:
        read_measurements(path)
    assert (info.value.line, info.value.column) == (7, "dy_mm")


def test_first_bad_cell_in_file_order_is_reported(csv):
    rows = edit(STATIC_HEADER, STATIC_ROWS, 4, "q2_deg", "x")
    rows = edit(STATIC_HEADER, rows, 2, "dz_mm", "")
    path = csv(render(STATIC_HEADER, rows))
    with raises(path, "line 5, column 'dz_mm': empty value"):
        read_measurements(path)


def test_bad_integer_and_empty_label(csv):
    path = csv(render(STATIC_HEADER, edit(STATIC_HEADER, STATIC_ROWS, 1, "step", "1.5")))
    with raises(path, "line 4, column 'step': '1.5' is not an integer"):
        read_static(path)
    path = csv(render(STATIC_HEADER, edit(STATIC_HEADER, STATIC_ROWS, 1, "series", '""')),
               "b.csv")
    with raises(path, "line 4, column 'series': empty value"):
        read_static(path)


def test_duplicate_column(csv):
    header = STATIC_HEADER + ["dx_mm"]
    path = csv(render(header, [r + ["0"] for r in STATIC_ROWS]))
    with raises(path, "line 2, column 'dx_mm': duplicate column (already given as 'dx_mm')"):
        read_measurements(path)
    header = STATIC_HEADER + ["dx_um"]
    path = csv(render(header, [r + ["0"] for r in STATIC_ROWS]), "b.csv")
    with raises(path, "line 2, column 'dx_um': duplicate column (already given as 'dx_mm')"):
        read_measurements(path)


def test_unnamed_column(csv):
    path = csv("series, , step\n")
    with raises(path, "line 1: column 2 has no name"):
        read_measurements(path)


def test_series_without_reference_row(csv):
    rows = edit(STATIC_HEADER, STATIC_ROWS, 3, "dy_mm", "0.012")
    path = csv(render(STATIC_HEADER, rows))
    with raises(path, "line 6, column 'dy_mm': the first row of series 'b' (step 0) is its "
                      "reference reading, so its displacement must be 0, got 0.012"):
        read_measurements(path)


def test_series_whose_first_step_is_not_zero_still_needs_zero_displacement(csv):
    rows = [r for r in STATIC_ROWS[1:3]]  # series 'a' starts at step 1 with a deflection
    path = csv(render(STATIC_HEADER, rows))
    with raises(path, "line 3, column 'dx_mm': the first row of series 'a' (step 1) is its "
                      "reference reading, so its displacement must be 0, got 0.009"):
        read_measurements(path)


def test_reference_rotation_must_be_zero(csv):
    header = STATIC_HEADER + ["rx_mrad", "ry_mrad", "rz_mrad"]
    rows = [r + ["0", "0", "0"] for r in STATIC_ROWS]
    rows = edit(header, rows, 0, "rz_mrad", "0.1")
    path = csv(render(header, rows))
    with raises(path, "line 3, column 'rz_mrad': the first row of series 'a' (step 0) is its "
                      "reference reading, so its rotation must be 0, got 0.1"):
        read_measurements(path)


def test_steps_not_increasing(csv):
    rows = [STATIC_ROWS[0], STATIC_ROWS[2], STATIC_ROWS[1]]
    path = csv(render(STATIC_HEADER, rows))
    with raises(path, "line 5, column 'step': step 1 does not follow step 2 of series 'a' "
                      "(steps must increase, in measurement order)"):
        read_measurements(path)
    path = csv(render(STATIC_HEADER, [STATIC_ROWS[0], STATIC_ROWS[0]]), "b.csv")
    with raises(path, "line 4, column 'step': step 0 does not follow step 0 of series 'a' "
                      "(steps must increase, in measurement order)"):
        read_measurements(path)


def test_series_split_in_two_blocks(csv):
    extra = ["a", "3", *C1, "0", "0", "0", "0.001", "0.002", "0"]
    path = csv(render(STATIC_HEADER, STATIC_ROWS + [extra]))
    with raises(path, "line 9, column 'series': series 'a' continues here after other series "
                      "(it started on line 3); keep the rows of a series together"):
        read_measurements(path)


def test_wrong_number_of_fields(csv):
    rows = [list(r) for r in STATIC_ROWS]
    rows[2] = rows[2][:-1]
    text = render(STATIC_HEADER, rows).replace("\na, 1", "\n\n# note\na, 1")
    path = csv(text)
    with raises(path, "line 7: 13 fields, expected 14 as in the header (line 2)") as info:
        read_measurements(path)
    assert info.value.line == 7 and info.value.column is None


def test_unknown_frf_direction(csv):
    path = csv(render(FRF_HEADER, edit(FRF_HEADER, FRF_ROWS, 2, "output", "w")))
    with raises(path, "line 5, column 'output': 'w' is not a direction (x, y or z)"):
        read_measurements(path)


def test_frf_directions_are_case_insensitive(csv):
    path = csv(render(FRF_HEADER, edit(FRF_HEADER, FRF_ROWS, 2, "output", "X")))
    assert read_frf(path).outputs.tolist() == ["y", "y", "x"]


@pytest.mark.parametrize("reader", [read_measurements, read_static])
def test_pose_outside_joint_limits(csv, reader):
    rows = edit(STATIC_HEADER, STATIC_ROWS, 4, "q2_deg", "95")
    path = csv(render(STATIC_HEADER, rows))
    with raises(path, "line 7, column 'q2_deg': 95 is outside the limits [-65, 85] deg "
                      "of joint 2"):
        reader(path, limits=LIMITS)
    assert reader(path).q[4, 1] == np.deg2rad(95.0)  # no limits, no check


def test_limits_are_inclusive_and_in_the_file_unit(csv):
    header = [h.replace("_deg", "_rad") for h in MODAL_HEADER]
    rows = edit(header, MODAL_ROWS, 0, "q1_rad", "-3")
    rows = [r[:1] + ["0"] * 6 + r[7:] for r in rows[:1]] + rows[1:2]
    rows[0][header.index("q1_rad")] = repr(float(np.deg2rad(170.0)))
    rows[1] = ["c1", *rows[0][1:7], "2", "12.4"]
    assert read_modal(csv(render(header, rows)), limits=LIMITS).n_rows == 2
    rows[1][header.index("q1_rad")] = rows[0][header.index("q1_rad")] = "3"
    path = csv(render(header, rows), "b.csv")
    with raises(path, "line 3, column 'q1_rad': 3 is outside the limits [-2.96706, 2.96706] "
                      "rad of joint 1"):
        read_modal(path, limits=LIMITS)


def test_limits_shape_is_checked(csv):
    path = csv(render(STATIC_HEADER, STATIC_ROWS))
    with pytest.raises(ValueError, match=re.escape("limits must have shape (6, 2) [rad], "
                                                   "got (2, 6)")):
        read_static(path, limits=np.ones((2, 6)))


def test_negative_frequency(csv):
    path = csv(render(FRF_HEADER, edit(FRF_HEADER, FRF_ROWS, 1, "freq_Hz", "-10")))
    with raises(path, "line 4, column 'freq_Hz': frequency must be zero or positive, got -10"):
        read_measurements(path)
    rows = edit(MODAL_HEADER, MODAL_ROWS, 2, "freq_Hz", "0")
    path = csv(render(MODAL_HEADER, rows), "b.csv")
    with raises(path, "line 5, column 'freq_Hz': natural frequency must be positive, got 0"):
        read_measurements(path)


def test_zero_frequency_is_a_valid_frf_line(csv):
    path = csv(render(FRF_HEADER, edit(FRF_HEADER, FRF_ROWS, 0, "freq_Hz", "0")))
    assert read_frf(path).freq_hz[0] == 0.0


@pytest.mark.parametrize("sigma", ["0", "-0.015"])
def test_sigma_not_positive(csv, sigma):
    header = STATIC_HEADER + ["sigma_mm"]
    rows = [r + ["0.015"] for r in STATIC_ROWS]
    rows[5][-1] = sigma
    path = csv(render(header, rows))
    with raises(path, f"line 8, column 'sigma_mm': sigma must be positive, got {sigma}"):
        read_measurements(path)


def test_modal_rules(csv):
    rows = edit(MODAL_HEADER, MODAL_ROWS, 1, "mode", "1")
    path = csv(render(MODAL_HEADER, rows))
    with raises(path, "line 4, column 'mode': mode 1 of pose 'c1' is already given on line 3"):
        read_measurements(path)
    rows = edit(MODAL_HEADER, MODAL_ROWS, 1, "q3_deg", "-18")
    path = csv(render(MODAL_HEADER, rows), "b.csv")
    with raises(path, "line 4, column 'q3_deg': pose 'c1' has other joint angles here than on "
                      "line 3 (one pose, one set of angles)"):
        read_measurements(path)
    rows = edit(MODAL_HEADER, MODAL_ROWS, 0, "mode", "0")
    path = csv(render(MODAL_HEADER, rows), "c.csv")
    with raises(path, "line 3, column 'mode': mode number must be positive, got 0"):
        read_measurements(path)
    header = MODAL_HEADER + ["damping_ratio"]
    rows = [r + ["0.02"] for r in MODAL_ROWS]
    rows[2][-1] = "1.2"
    path = csv(render(header, rows), "d.csv")
    with raises(path, "line 5, column 'damping_ratio': damping ratio must be below 1 (a "
                      "fraction of critical damping), got 1.2"):
        read_measurements(path)


def test_frf_duplicate_line(csv):
    rows = FRF_ROWS + [FRF_ROWS[1]]
    path = csv(render(FRF_HEADER, rows))
    with raises(path, "line 6, column 'freq_Hz': frequency 10 of pose 'c1', input y, output y "
                      "is already given on line 4"):
        read_measurements(path)


def test_path_steps_increase(csv):
    path = csv(render(PATH_HEADER, PATH_ROWS[::-1]))
    with raises(path, "line 4, column 'step': step 0 does not follow step 1 "
                      "(steps must increase, in measurement order)"):
        read_measurements(path)


@pytest.mark.parametrize(("text", "message"), [
    ("", "no header row (the file is empty or only holds comments)"),
    ("# only\n\n# comments\n", "no header row (the file is empty or only holds comments)"),
])
def test_empty_files(csv, text, message):
    path = csv(text)
    with pytest.raises(ReadError, match="^" + re.escape(f"{path}: {message}") + "$"):
        read_measurements(path)


def test_header_without_rows(csv):
    path = csv("# c\n" + ", ".join(PATH_HEADER) + "\n# no data yet\n")
    with raises(path, "line 2: no data rows after the header"):
        read_measurements(path)


def test_not_utf8_and_bad_quotes(csv, tmp_path):
    path = tmp_path / "latin.csv"
    path.write_bytes(", ".join(PATH_HEADER).encode() + b"\n0, 1, 2, 3, 4 \xb5\n")
    with pytest.raises(ReadError, match=re.escape(f"{path}: not a UTF-8 text file")):
        read_measurements(path)
    path = csv(", ".join(PATH_HEADER) + '\n0, "1, 2, 3, 4\n')
    with pytest.raises(ReadError, match=re.escape(f"{path}, line 2: malformed CSV")):
        read_measurements(path)


def test_label_starting_with_hash_inside_a_row(csv):
    header = STATIC_HEADER[1:] + ["series"]
    rows = [r[1:] + [r[0]] for r in STATIC_ROWS]
    rows[0][-1] = "#a"
    path = csv(render(header, rows))
    with raises(path, "line 3, column 'series': label '#a' must not start with '#' or hold a "
                      "line break"):
        read_measurements(path)


def test_missing_file_is_a_file_not_found_error(tmp_path):
    with pytest.raises(FileNotFoundError):
        read_measurements(tmp_path / "nope.csv")


# ---------------------------------------------------------------- dataclasses

def test_dataclass_shapes_are_checked():
    with pytest.raises(ValueError, match=re.escape("StaticData.q must have shape (2, 6), "
                                                   "got (2, 5)")):
        StaticData(series=["a", "a"], steps=[0, 1], q=np.zeros((2, 5)), force=np.zeros((2, 3)),
                   disp=np.zeros((2, 3)))
    with pytest.raises(ValueError, match=re.escape("PathData.force must have shape (3,), "
                                                   "got (2,)")):
        PathData(steps=[0, 1, 2], points=np.zeros((3, 3)), force=[1.0, 2.0])
    with pytest.raises(ValueError, match="FrfData.inputs must be among x, y, z, got 'w'"):
        FrfData(poses=["p"], q=np.zeros((1, 6)), inputs=["w"], outputs=["x"], freq_hz=[1.0],
                receptance=[1e-6])
    with pytest.raises(ValueError, match="ModalData.freq_hz must be finite"):
        ModalData(poses=["p"], q=np.zeros((1, 6)), modes=[1], freq_hz=[np.nan])
    with pytest.raises(ValueError, match="label ' p' must be non-empty"):
        ModalData(poses=[" p"], q=np.zeros((1, 6)), modes=[1], freq_hz=[1.0])


def test_dataclasses_are_frozen_read_only_and_compare_by_content():
    d = read_static(example_path("static"))
    with pytest.raises(dataclasses.FrozenInstanceError):
        d.disp = None
    with pytest.raises(ValueError, match="read-only"):
        d.disp[0, 0] = 1.0
    e = dataclasses.replace(d, sigma=None)
    assert e != d and e == dataclasses.replace(d, sigma=None)
    assert dataclasses.replace(d, disp=d.disp * 2) != d
    assert d != read_modal(example_path("modal"))
    with pytest.raises(TypeError):
        hash(d)


def test_series_helpers():
    d = StaticData(series=["x", "x", "x", "y"], steps=[0, 1, 2, 5], q=np.zeros((4, 6)),
                   force=np.zeros((4, 3)), disp=np.zeros((4, 3)))
    assert d.series_slices() == {"x": slice(0, 3), "y": slice(3, 4)}
    assert d.reference_rows().tolist() == [0, 3] and d.n_series == 2 and d.n_rows == 4
    assert d.series.dtype.kind == "U" and d.steps.dtype == np.int64


# ---------------------------------------------------------------- notebook use

@pytest.mark.parametrize(("make", "write"), [
    (_random_static, write_static), (_random_modal, write_modal), (_random_frf, write_frf),
    (_random_path, write_path),
])
def test_dataframe_equals_the_written_file(tmp_path, make, write):
    pd = pytest.importorskip("pandas")
    data = make(np.random.default_rng(5))
    frame = data.to_dataframe()
    assert len(frame) == data.n_rows
    path = write(tmp_path / "x.csv", data)
    file = pd.read_csv(path, comment="#", keep_default_na=False,
                       float_precision="round_trip")
    assert frame.columns.tolist() == file.columns.tolist()
    for name in frame.columns:
        a, b = frame[name].to_numpy(), file[name].to_numpy()
        if a.dtype.kind == "f":
            assert np.allclose(a, b, rtol=1e-13, atol=0), name
        else:
            assert a.astype(str).tolist() == b.astype(str).tolist(), name


def test_static_dataframe_units():
    pytest.importorskip("pandas")
    d = _random_static(np.random.default_rng(8))
    f = d.to_dataframe()
    assert f.columns.tolist()[:14] == STATIC_HEADER
    assert f["series"].tolist() == d.series.tolist() and f["step"].tolist() == d.steps.tolist()
    for k, c in enumerate("xyz"):
        assert np.allclose(f[f"d{c}_mm"], 1e3 * d.disp[:, k], rtol=1e-15, atol=0)
        assert np.allclose(f[f"r{c}_mrad"], 1e3 * d.rot[:, k], rtol=1e-15, atol=0)
        assert np.array_equal(f[f"f{c}_N"], d.force[:, k])
        assert np.array_equal(f[f"m{c}_Nm"], d.moment[:, k])
    assert np.allclose(f[[f"q{j}_deg" for j in range(1, 7)]], np.degrees(d.q), rtol=1e-14)
    assert np.allclose(f["sigma_mm"], 1e3 * d.sigma, rtol=1e-15)


def test_frf_dataframe_units():
    pytest.importorskip("pandas")
    d = _random_frf(np.random.default_rng(9))
    f = d.to_dataframe()
    assert f.columns.tolist() == FRF_HEADER
    assert np.array_equal(f["re_m_per_N"] + 1j * f["im_m_per_N"], d.receptance)  # m/N as is
    assert np.array_equal(f["freq_Hz"], d.freq_hz)
    assert f["input"].tolist() == d.inputs.tolist() and f["output"].tolist() == list("xyzz")


def _figure(text: str, before: str, after: str) -> str:
    return text.split(before, 1)[1].split(after, 1)[0]


def test_static_repr_is_short_for_a_large_set():
    rng = np.random.default_rng(4)
    n_series, per = 400, 15
    steps = np.tile(np.arange(per), n_series)
    disp = rng.normal(size=(n_series * per, 3)) * 1e-3
    disp[steps == 0] = 0.0
    force = np.zeros((n_series * per, 3))
    force[:, 1] = np.tile(np.linspace(0, 800, per), n_series)
    q = np.repeat(rng.uniform(-1, 1, size=(n_series // 4, 6)), 4 * per, axis=0)
    d = StaticData(series=np.repeat([f"series {k}" for k in range(n_series)], per),
                   steps=steps, q=q, force=force, disp=disp,
                   sigma=np.full(n_series * per, 1e-5))
    text = repr(d)
    assert len(text) < 300 and "\n" not in text
    assert text.startswith(f"StaticData({n_series * per} readings, {n_series} series ")
    assert f"… (+{n_series - 4}), {n_series // 4} poses, load 0–800 N" in text
    top = float(_figure(text, "displacement up to ", " mm"))
    assert top == pytest.approx(1e3 * np.linalg.norm(disp, axis=1).max(), rel=1e-3)
    assert text.endswith("with sigma)")


@pytest.mark.parametrize("kind", ["static", "modal", "frf", "path"])
def test_reprs_of_the_shipped_examples(kind):
    d = read_measurements(example_path(kind))
    text = repr(d)
    assert len(text) < 300 and "\n" not in text and "array" not in text
    assert text.startswith(f"{type(d).__name__}({d.n_rows} ")
    if kind == "modal":
        lo, hi = _figure(text, "modes 1–3, ", " Hz").split("–")
        assert (float(lo), float(hi)) == pytest.approx((d.freq_hz.min(), d.freq_hz.max()),
                                                       rel=1e-3)
        assert f"at {d.n_poses} poses {', '.join(d.pose_labels())}," in text
    if kind == "frf":
        assert "paths y->y, y->x," in text
        h = float(_figure(text, "|H| up to ", " m/N"))
        assert h == pytest.approx(np.abs(d.receptance).max(), rel=1e-3)


def test_repr_of_the_shipped_lab_campaign_is_short():
    from importlib.resources import files

    text = repr(read_measurements(files("flexarm") / "data" / "lab" / "lab_hidden_effect.csv"))
    assert len(text) < 300 and text.startswith("StaticData(162 readings, 18 series")


def test_reprs_count_the_poses_in_order_of_appearance():
    z = np.zeros(6)
    one = ModalData(poses=["P1"], q=[z], modes=[1], freq_hz=[8.0])
    assert repr(one) == "ModalData(1 modes at 1 pose P1, modes 1, 8 Hz)"
    frf = FrfData(poses=["P2", "P1"], q=[z, z], inputs=["x", "x"], outputs=["x", "y"],
                  freq_hz=[1.0, 2.0], receptance=[1e-6, 2e-7j])
    assert repr(frf) == ("FrfData(2 frequency lines at 2 poses P2, P1, paths x->x, x->y, "
                         "1–2 Hz, |H| up to 1e-06 m/N)")
