"""The byte scan of measurement files against the line-by-line reader: the same arrays,
the same errors, whichever reads a file; which files the scan leaves to the reader."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.validation.data.formats import MeasurementFileError, _cells, read_measurements

HEADER = "series, step, q1_deg, q2_rad, q3_deg, q4_deg, q5_deg, q6_deg, fx_kN, fy_N, fz_N, " \
         "dx_um, dy_mm, dz_m, sigma_mm"


def _rows(n: int = 60, seed: int = 3) -> list[str]:
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3)) * [40.0, 0.05, 5e-5]
    d[::6] = 0.0  # each series' reference reading
    rows = []
    for i, (a, b, c) in enumerate(d):
        q2 = "0.9" if i // 6 % 2 else "9.0e-1"
        rows.append(f"s{i // 6},{i % 6} , 0,{q2},-19 ,\t12,-15.0,-11, 0.2E-1 ,{200 * (i % 6)}, "
                    f"0,{a:.3f},{b:.6g},{c:.4e},0.015")
    return rows


def _write(path, rows, comments=("# static rows", "# Messung: µm und mm"), eol="\n"):
    lines = [*comments, HEADER]
    for k, r in enumerate(rows):
        lines.append(r)
        if k % 7 == 3:
            lines += ["", "   # a comment between rows, with, commas"]
    path.write_bytes((eol.join(lines) + eol).encode())
    return path


def _both(path, monkeypatch):
    fast = read_measurements(path)
    monkeypatch.setattr(_cells, "_fast_lines", lambda raw, source: None)
    return fast, read_measurements(path)


@pytest.mark.parametrize("eol", ["\n", "\r\n"])
def test_scan_and_line_reader_give_the_same_arrays(tmp_path, monkeypatch, eol):
    fast, slow = _both(_write(tmp_path / "s.csv", _rows(), eol=eol), monkeypatch)
    assert fast == slow and fast.n_rows == 60
    assert fast.q[7, 1] == 0.9 and fast.force[1, 0] == 20.0
    assert fast.disp[1].tolist() == slow.disp[1].tolist()


def test_scan_reads_clean_files_and_leaves_the_rest_to_the_line_reader(tmp_path):
    def scanned(text: str) -> bool:
        return _cells._fast_lines(text.encode(), "f") is not None

    rows = "\n".join(_rows(6))
    assert scanned(f"# µm\n{HEADER.replace('dx_um', 'dx_µm')}\n{rows}\n")  # header, comments
    assert scanned(f"\ufeff{HEADER}\n{rows}\n")  # a byte-order mark before the header
    assert not scanned(f"{HEADER}\n{rows}\ns0,1,\"ü\"\n")  # quotes
    assert not scanned(f"{HEADER}\n{rows.replace('s0', 'sü')}\n")  # a data row not ASCII
    assert not scanned(f"{HEADER}\r{rows}\n")  # an old Mac line break
    assert not scanned(f"{HEADER}\n{rows}\x0c\n")  # a form feed: a blank to Python


@pytest.mark.parametrize("edit, message", [
    (lambda r: r[:4] + [r[4] + ", 1"] + r[5:], r"line 9: 16 fields, expected 15 as in the header"
                                               r" \(line 2\); decimal commas"),
    (lambda r: r[:2] + [r[2].replace("-19 ", "-1,9")] + r[3:],
     r"line 5: 16 fields, expected 15"),
    (lambda r: r[:1] + [r[1].replace("0.015", "0.0x5")] + r[2:],
     r"line 4, column 'sigma_mm': '0.0x5' is not a number"),
    (lambda r: r[:3] + [r[3].replace("s0", "#s0", 1)] + r[4:], None),  # a comment line now
], ids=["extra-field", "decimal-comma", "bad-number", "commented-row"])
def test_errors_are_the_same_from_either_reader(tmp_path, monkeypatch, edit, message):
    path = _write(tmp_path / "s.csv", edit(_rows(12)), comments=("# x",))
    outcomes = []
    for scan in (True, False):
        if not scan:
            monkeypatch.setattr(_cells, "_fast_lines", lambda raw, source: None)
        try:
            outcomes.append(read_measurements(path).n_rows)
        except MeasurementFileError as exc:
            outcomes.append(str(exc))
    assert outcomes[0] == outcomes[1]
    if message is not None:
        assert isinstance(outcomes[0], str), outcomes
        assert __import__("re").search(message, outcomes[0]), outcomes[0]
