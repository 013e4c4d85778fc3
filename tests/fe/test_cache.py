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
