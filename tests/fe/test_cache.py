"""The package cache: keys, verified reads, healing of damaged entries."""

from __future__ import annotations

import os
import time

import numpy as np
import pytest

from flexarm.fe import cache
from flexarm.fe.cache import JSON, cache_key, cache_root, cached, lookup


@pytest.fixture()
def root(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "c"))
    return tmp_path / "c"


def _calls():
    count = []

    def compute():
        count.append(1)
        return {"value": 42, "calls": len(count)}

    return compute, count


def test_root_follows_the_environment(root):
    assert cache_root() == root and root.is_dir()


def test_key_covers_parts_kind_and_library_versions(monkeypatch):
    a = np.arange(4.0)
    base = cache_key("k", a, 1.0)
    assert base == cache_key("k", a.copy(), 1.0)
    assert len({base, cache_key("k", a + 1e-15, 1.0), cache_key("k", a, 1.0 + 1e-12),
                cache_key("other", a, 1.0), cache_key("k", a, 1.0, libraries=("gmsh",))}) == 5
    real = cache.library_versions
    monkeypatch.setattr(cache, "library_versions", lambda libs=(): tuple(
        (n, "0.0") if n == "scipy" else (n, v) for n, v in real(libs)))
    assert cache_key("k", a, 1.0) != base


def test_key_covers_the_flexarm_version(monkeypatch):
    a = np.arange(4.0)
    base = cache_key("k", a, 1.0)
    monkeypatch.setattr(cache, "package_version", lambda: "99.0")
    upgraded = cache_key("k", a, 1.0)
    monkeypatch.setattr(cache, "package_version", lambda: "99.0.post1")
    assert len({base, upgraded, cache_key("k", a, 1.0)}) == 3
    monkeypatch.undo()
    assert cache_key("k", a, 1.0) == base


def test_an_entry_of_another_flexarm_is_not_read(root, monkeypatch, caplog):
    """An entry stored by another version (here of another schema, which the running code
    could not read) is not found: computed again, with one info line and no warning."""
    monkeypatch.setattr(cache, "_VERSIONS_SEEN", set())
    monkeypatch.setattr(cache, "package_version", lambda: "0.0.9")
    old = cached("mass-properties", cache_key("mass-properties", "link"),
                 lambda: {"masse": 1.0})
    assert (root / "flexarm-version").read_text() == "0.0.9\n"
    monkeypatch.setattr(cache, "package_version", lambda: "1.0")
    compute, count = _calls()
    with caplog.at_level("INFO", logger="flexarm.fe.cache"):
        new = cached("mass-properties", cache_key("mass-properties", "link"), compute)
        cached("mass-properties", cache_key("mass-properties", "other link"), compute)
        again = cached("mass-properties", cache_key("mass-properties", "link"), compute)
    assert not new.is_hit and new.value == {"value": 42, "calls": 1} and new.path != old.path
    assert again.is_hit and again.value == new.value and len(count) == 2
    said = [r for r in caplog.records if "flexarm 0.0.9" in r.getMessage()]
    assert len(said) == 1 and "\n" not in said[0].getMessage()
    assert str(root) in said[0].getMessage() and "flexarm 1.0" in said[0].getMessage()
    assert not [r for r in caplog.records if r.levelname == "WARNING"]
    assert (root / "flexarm-version").read_text() == "1.0\n" and old.path.is_file()
    monkeypatch.setattr(cache, "package_version", lambda: "0.0.9")  # the older one still
    assert cached("mass-properties", old.path.stem, compute).value == {"masse": 1.0}


def test_pinned_volume_meshes_are_read_under_any_version(root, monkeypatch):
    """The demo arm's shipped tetrahedra are files of the robot, not cache entries."""
    from flexarm.assembly.link_meshes import meshed_link
    from flexarm.robot import load_robot

    monkeypatch.setattr(cache, "package_version", lambda: "99.0")
    made = meshed_link(load_robot().links[2], 0.03)
    assert made.mesher == "file" and made.mesh.n_tets > 1000


def test_computed_once_then_read(root):
    compute, count = _calls()
    first = cached("kind", "abc", compute)
    second = cached("kind", "abc", compute)
    assert (first.is_hit, second.is_hit) == (False, True)
    assert second.value == first.value and len(count) == 1
    assert first.path == root / "kind" / "abc.json"


@pytest.mark.parametrize("damage", ["truncate", "flip", "no_checksum", "garbage_checksum"])
def test_damaged_entry_is_rebuilt_never_trusted(root, damage):
    compute, count = _calls()
    path = cached("kind", "abc", compute).path
    check = path.with_name(path.name + ".sha256")
    data = path.read_bytes()
    if damage == "truncate":
        path.write_bytes(data[: len(data) // 2])
    elif damage == "flip":  # still valid JSON, different number: only the checksum sees it
        path.write_bytes(data.replace(b"42", b"43"))
    elif damage == "no_checksum":
        check.unlink()
    else:
        check.write_text("0" * 64)
    assert lookup("kind", "abc") is None and not path.exists()
    again = cached("kind", "abc", compute)
    assert not again.is_hit and again.value["value"] == 42 and len(count) == 2
    assert cached("kind", "abc", compute).is_hit


def test_unreadable_entry_with_valid_checksum_is_rebuilt(root):
    compute, count = _calls()
    broken = cache.Codec(".json", JSON.save, lambda p: 1 / 0)
    cached("kind", "abc", compute, broken)
    assert not cached("kind", "abc", compute, broken).is_hit and len(count) == 2


def test_stale_part_files_are_swept(root):
    compute, _ = _calls()
    folder = root / "kind"
    folder.mkdir(parents=True)
    stale, fresh = folder / ".abc.x1.part.json", folder / ".abc.x2.part.json"
    stale.write_text("{")
    fresh.write_text("{")
    old = time.time() - 7200
    os.utime(stale, (old, old))
    cached("kind", "abc", compute)
    assert not stale.exists() and fresh.exists()


def test_disabled_cache_neither_reads_nor_writes(root):
    compute, count = _calls()
    entry = cached("kind", "abc", compute, enabled=False)
    assert entry.path is None and not (root / "kind").exists() and len(count) == 1


def _rewrite_with_checksum(path, data: bytes) -> None:
    """Replace an entry by ``data`` with a matching checksum (a foreign or buggy writer)."""
    from flexarm.fe.files import file_digest

    path.write_bytes(data)
    path.with_name(path.name + ".sha256").write_text(file_digest(path) + "\n")


def test_broken_json_with_valid_checksum_is_reported_and_rebuilt(root, caplog):
    compute, count = _calls()
    first = cached("mass-properties", "abc", compute)
    _rewrite_with_checksum(first.path, b'{"value": 42 "calls": 1}')
    with caplog.at_level("WARNING", logger="flexarm.fe.cache"):
        again = cached("mass-properties", "abc", compute)
    assert not again.is_hit and again.value == {"value": 42, "calls": 2} and len(count) == 2
    (record,) = caplog.records
    assert str(first.path) in record.getMessage() and "\n" not in record.getMessage()
    assert cached("mass-properties", "abc", compute).value == again.value


def test_unwritable_cache_root_computes_without_caching(tmp_path, monkeypatch, caplog):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("FLEXARM_CACHE", str(blocker / "cache"))
    compute, count = _calls()
    with caplog.at_level("WARNING", logger="flexarm.fe.cache"):
        entry = cached("kind", "abc", compute)
    assert entry.value["value"] == 42 and entry.path is None and not entry.is_hit
    assert "without caching" in caplog.text and len(count) == 1


def test_read_only_cache_on_a_miss_keeps_the_computed_value(root, monkeypatch, caplog):
    import tempfile

    def refuse(*args, dir=None, **kwargs):  # what a read-only folder does (root ignores modes)
        raise PermissionError(13, "Permission denied", str(dir))

    compute, count = _calls()
    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with caplog.at_level("WARNING", logger="flexarm.fe.cache"):
        entry = cached("kind", "abc", compute)
    assert entry.value == {"value": 42, "calls": 1} and entry.path is None
    assert "Permission denied" in caplog.text and "without caching" in caplog.text
    assert not (root / "kind" / "abc.json").exists()
    monkeypatch.undo()
    monkeypatch.setenv("FLEXARM_CACHE", str(root))
    assert not cached("kind", "abc", compute).is_hit and len(count) == 2


def test_concurrent_builds_of_one_key_give_one_value(root):
    import threading

    results, started = [], []

    def compute():  # a non-deterministic builder: each call gives a new value
        started.append(1)
        time.sleep(0.2)
        return {"build": len(started)}

    threads = [threading.Thread(target=lambda: results.append(cached("kind", "abc", compute)))
               for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(started) == 1 and [r.value for r in results] == [{"build": 1}] * 3
    assert sorted(r.is_hit for r in results) == [False, True, True]


def _matrix_codec(kind: str):
    """A stiffness matrix stored as HDF5 or .npy, as the superelement cache stores its K."""
    if kind == "h5":
        h5py = pytest.importorskip("h5py")

        def save(path, K):
            with h5py.File(path, "w") as f:
                f["K"] = K

        def load(path):
            with h5py.File(path, "r") as f:
                return f["K"][()]

        return cache.Codec(".h5", save, load)
    return cache.Codec(".npy", lambda path, K: np.save(path, K), np.load)


@pytest.mark.parametrize("kind", ["h5", "npy"])
@pytest.mark.parametrize("damage", ["truncate", "truncate-foreign", "mantissa-bit"])
def test_damaged_matrix_heals_to_exactly_a_clean_build(root, kind, damage):
    from flexarm.fe.files import file_digest

    K = np.random.default_rng(3).normal(size=(40, 40))
    K = K @ K.T
    codec, calls = _matrix_codec(kind), []

    def build():
        calls.append(1)
        return K.copy()

    path = cached("superelements", "k", build, codec).path
    data = bytearray(path.read_bytes())
    if damage == "mantissa-bit":  # the lowest mantissa bit of K[0, 0], found by its bytes
        at = bytes(data).index(K[0, 0].tobytes())
        data[at] ^= 1
        path.write_bytes(bytes(data))
    else:
        path.write_bytes(bytes(data[: len(data) // 3]))
        if damage == "truncate-foreign":  # a writer that vouches for its broken file
            path.with_name(path.name + ".sha256").write_text(file_digest(path))
    healed = cached("superelements", "k", build, codec)
    assert not healed.is_hit and len(calls) == 2
    assert healed.value.tobytes() == K.tobytes()
    assert cached("superelements", "k", build, codec).is_hit


def test_a_result_object_round_trips_through_the_pickle_codec(root):
    """A frozen result (here a diagnosis step record) read back equals the one stored,
    arrays and all; the second call reads it."""
    from flexarm.validation.diagnosis.results import Step

    step = Step("baseline", (), 1.02, (0.8, 1.2), 100.0, 15e-6, 16e-6, freq_rms=0.01,
                dropped=(("tilt_j1", "joint 1 tilt dropped"),))
    first = cached("result", cache_key("result", 1), lambda: step, cache.PICKLE)
    again = cached("result", cache_key("result", 1), lambda: None, cache.PICKLE)
    assert not first.is_hit and again.is_hit and again.value == step

