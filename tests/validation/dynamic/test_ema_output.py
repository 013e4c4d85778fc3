"""``ema``'s files appear whole or not at all: Ctrl-C or a full disk while the pictures
are drawn leaves no modal file, no picture and no temporary folder (one line, exit 130 or
2), and an older complete run in the same folder is kept as it was."""

from __future__ import annotations

import errno
from pathlib import Path

import pytest

from flexarm.cli import main
from flexarm.validation.data.formats.uff_write import write_uff

from .modal_sum import modal_sum


def _half_then(exc):
    """A picture writer that leaves half a PNG, then fails with ``exc``."""
    def write(path, *args, **kwargs):
        Path(path).write_bytes(b"\x89PNG half")
        raise exc
    return write


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def frf_file(tmp_path_factory):
    frf = modal_sum(noise=0.01)
    return write_uff(tmp_path_factory.mktemp("lab") / "frf.uff", frfs=[frf])


@pytest.mark.parametrize("fault, code, last", [
    (_half_then(KeyboardInterrupt), 130, "flexarm ema: interrupted"),
    (_half_then(OSError(errno.ENOSPC, "No space left on device")), 2,
     "flexarm ema: error: {out}: No space left on device"),
], ids=["ctrl-c", "full-disk"])
def test_ema_output_is_whole_or_absent(tmp_path, capsys, monkeypatch, frf_file, fault, code,
                                       last):
    from flexarm.validation.dynamic import ema_plots

    monkeypatch.setattr(ema_plots, "plot_synthesis", fault)  # modal.csv is written by then
    out = tmp_path / "new" / "ema"
    assert main(["ema", str(frf_file), "-o", str(out / "modal.csv")]) == code
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert err == [last.format(out=out)], err
    assert list(tmp_path.iterdir()) == []  # no modal file, no parent made for it, no .part


@pytest.mark.parametrize("suffix", ["csv", "uff"])
def test_ema_keeps_the_older_complete_run(tmp_path, capsys, monkeypatch, frf_file, suffix):
    from flexarm.validation.dynamic import ema_plots

    out = tmp_path / f"modal.{suffix}"
    assert main(["ema", str(frf_file), "-o", str(out)]) == 0
    (tmp_path / "notes.txt").write_text("the user's own file")
    before = _tree(tmp_path)
    assert sorted(before) == sorted([f"modal.{suffix}", "modal.frf_P1.png",
                                     "modal.stabilisation_P1.png", "notes.txt"])
    monkeypatch.setattr(ema_plots, "plot_stabilisation",
                        _half_then(OSError(errno.ENOSPC, "No space left on device")))
    capsys.readouterr()
    assert main(["ema", str(frf_file), "-o", str(out), "--split", "none"]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert err == [f"flexarm ema: error: {tmp_path}: No space left on device"], err
    assert _tree(tmp_path) == before and not list(tmp_path.glob(".*"))


def test_a_bad_split_is_one_line_before_any_work(tmp_path, capsys, frf_file):
    assert main(["ema", str(frf_file), "--split", "0", "-o", str(tmp_path / "m.csv")]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert err == ["flexarm ema: error: --split 0: auto, none or a number of sub-bands "
                   "(1, 2, ...)"], err
    assert list(tmp_path.iterdir()) == []
