"""Atomic output: a folder written whole or not at all, errors that name the user's file,
writers wrapped to write through a temporary folder, and npz archives that are the same
bytes for the same arrays and never leave a half-closed archive behind."""

from __future__ import annotations

import errno
import gc
import os
import zipfile

import numpy as np
import pytest

from flexarm.fe.files import atomic_folder, atomic_path, write_npz, writes_folder


def test_a_full_disk_names_the_file_at_its_final_place(tmp_path):
    out = tmp_path / "report"
    with pytest.raises(OSError) as caught, atomic_folder(out) as tmp:
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp / "sub" / "a.png"))
    assert caught.value.errno == errno.ENOSPC
    assert caught.value.filename == str(out / "sub" / "a.png")
    with pytest.raises(OSError) as caught, atomic_folder(out):
        raise OSError(errno.ENOSPC, "No space left on device")  # write() names no file
    assert caught.value.filename == str(out)
    with pytest.raises(OSError) as caught, atomic_path(tmp_path / "a.csv") as tmp:
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp))
    assert caught.value.filename == str(tmp_path / "a.csv")
    assert list(tmp_path.iterdir()) == []


def test_parents_made_for_a_failed_folder_are_removed(tmp_path):
    with pytest.raises(KeyboardInterrupt), atomic_folder(tmp_path / "a" / "b" / "out") as tmp:
        (tmp / "x.csv").write_text("half")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_the_current_folder_is_written_from_inside(tmp_path, monkeypatch):
    """``-o .``: the temporary folder goes inside the output folder (its parent may be
    read-only), and is gone afterwards."""
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    with atomic_folder(".") as tmp:
        assert tmp.parent.resolve() == work.resolve() and tmp.name.startswith(".work.part-")
        (tmp / "a.csv").write_text("a")
    assert sorted(os.listdir(work)) == ["a.csv"] and os.listdir(tmp_path) == ["work"]


def test_writes_folder_returns_final_paths_and_leaves_nothing_on_failure(tmp_path):
    @writes_folder("out")
    def write(label, out, fail=False):
        paths = [out / "a.txt", out / "b" / "c.txt"]
        paths[1].parent.mkdir()
        for p in paths:
            p.write_text(label)
            if fail:
                raise KeyboardInterrupt
        return tuple(paths)

    final = tmp_path / "r"
    assert write("x", final) == (final / "a.txt", final / "b" / "c.txt")
    assert (final / "b" / "c.txt").read_text() == "x"
    with pytest.raises(KeyboardInterrupt):
        write("y", out=final, fail=True)
    assert (final / "a.txt").read_text() == "x" and os.listdir(tmp_path) == ["r"]


def test_npz_is_numpy_readable_and_the_same_bytes_every_time(tmp_path):
    arrays = {"K": np.arange(6.0).reshape(2, 3), "names": np.array(["a", "bc"])}
    write_npz(tmp_path / "a.npz", arrays, b"checksum 1")
    os.utime(tmp_path / "a.npz", (0, 0))
    write_npz(tmp_path / "b.npz", arrays, b"checksum 1")
    assert (tmp_path / "a.npz").read_bytes() == (tmp_path / "b.npz").read_bytes()
    with np.load(tmp_path / "a.npz", allow_pickle=False) as z:
        assert z["K"].tolist() == arrays["K"].tolist() and z["names"].tolist() == ["a", "bc"]
    assert zipfile.ZipFile(tmp_path / "a.npz").comment == b"checksum 1"
    with pytest.raises(ValueError):  # no pickles
        write_npz(tmp_path / "c.npz", {"o": np.array([{}], dtype=object)})


def test_npz_on_a_full_disk_is_one_error(tmp_path, monkeypatch, capfd):
    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np.lib.format, "write_array", full)
    with pytest.raises(OSError, match="No space left"):
        write_npz(tmp_path / "a.npz", {"K": np.eye(3)})
    gc.collect()
    assert capfd.readouterr().err == ""  # no "Exception ignored in ZipFile.__del__"
