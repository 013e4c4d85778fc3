"""A universal file cut short, or holding values pyuff cannot parse, is refused naming
the dataset, its pose and the line (pyuff alone drops the cut dataset in silence)."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe.errors import ReadError
from flexarm.validation.data.formats.uff import read_uff
from flexarm.validation.data.formats.uff_scan import bad_number, delimiters, truncation

pyuff = pytest.importorskip("pyuff")

MARKS = ("flexarm pose=P1 q_deg=0,52,-19,12,-15,-11", "flexarm pose=P2 q_deg=0,0,66,0,-66,0")


def _two_poses(path, lines=30):
    f = np.linspace(1.0, 30.0, lines)
    sets = [pyuff.prepare_58(func_type=4, rsp_node=1, rsp_dir=d, ref_node=1, ref_dir=2,
                             data=(1e-6 / (1 - (f / 12) ** 2 + 0.05j * f / 12)) * d, x=f,
                             abscissa_spacing=1, id1="receptance", id4=mark,
                             abscissa_spec_data_type=18, ordinate_spec_data_type=8,
                             orddenom_spec_data_type=13)
            for mark in MARKS for d in (1, 2)]
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    return path


def test_pyuff_drops_a_cut_dataset_and_we_do_not(tmp_path):
    path = _two_poses(tmp_path / "lab.uff")
    raw = path.read_bytes()
    tags = delimiters(raw)
    assert len(tags) == 8 and truncation(raw) is None
    cut = tmp_path / "cut.uff"
    cut.write_bytes(raw[: tags[6] + 400])  # inside the 4th set (pose P2)
    assert len(pyuff.UFF(str(cut)).get_set_types()) == 3  # the silent loss
    with pytest.raises(ReadError, match=r"cut\.uff: the file ends inside dataset 4 \(type 58, "
                                        r"pose 'P2', from line \d+\): no closing '    -1' line"):
        read_uff(cut)


@pytest.mark.parametrize("keep, found", [
    (lambda tags: tags[4] + 5, "text after the last dataset's closing '    -1'"),
    (lambda tags: tags[4] + 7, "the file ends inside dataset 3 (type ?"),
    (lambda tags: tags[4] + 14, "the file ends inside dataset 3 (type 58, from line"),
])
def test_where_the_cut_falls(tmp_path, keep, found):
    raw = _two_poses(tmp_path / "lab.uff").read_bytes()
    assert found in truncation(raw[: keep(delimiters(raw))])


def test_a_delimiter_padded_to_80_columns_counts(tmp_path):
    raw = _two_poses(tmp_path / "lab.uff").read_bytes()
    padded = raw.replace(b"    -1\n", b"    -1" + b" " * 74 + b"\n")
    assert delimiters(padded) and truncation(padded) is None


@pytest.mark.parametrize("token", ["1.#QNAN", "nan(ind)", "-1.#IND", "*************"])
def test_a_value_pyuff_cannot_parse_is_named_with_its_line(tmp_path, token):
    path = _two_poses(tmp_path / "lab.uff")
    lines = path.read_text().splitlines(keepends=True)
    k = [i for i, ln in enumerate(lines) if ln.rstrip() == "    58"][2] + 12
    value = lines[k].split()[1]
    lines[k] = lines[k].replace(value, token.rjust(len(value)), 1)
    path.write_text("".join(lines))
    assert bad_number(path.read_bytes(), 2) == f"line {k + 1}: {token!r} is not a number"
    with pytest.raises(ReadError, match=rf"lab\.uff, dataset 3 \(type 58\): line {k + 1}: "):
        read_uff(path)


def test_nan_that_pyuff_reads_is_named_by_record_and_line(tmp_path):
    path = _two_poses(tmp_path / "lab.uff")
    lines = path.read_text().splitlines(keepends=True)
    k = [i for i, ln in enumerate(lines) if ln.rstrip() == "    58"][1] + 12
    value = lines[k].split()[2]  # the real part of the second line
    lines[k] = lines[k].replace(value, "NaN".rjust(len(value)), 1)
    path.write_text("".join(lines))
    with pytest.raises(ReadError, match=r"lab\.uff, dataset 2 \(type 58\), field 'data': 1 "
                                        r"value not finite, the first at frequency line 2 "
                                        r"\(2 Hz\)"):
        read_uff(path)


def test_an_frf_needs_three_lines(tmp_path):
    with pytest.raises(ReadError, match=r"dataset 1 \(type 58\), field 'x': 2 frequency "
                                        r"lines; an FRF needs at least 3"):
        read_uff(_two_poses(tmp_path / "short.uff", lines=2))
    assert read_uff(_two_poses(tmp_path / "ok.uff", lines=3)).frfs[1].pose == "P2"
