"""One content-addressed on-disk cache for every expensive result of the package.

An entry is one file ``<root>/<kind>/<key><suffix>`` plus a checksum file
``<key><suffix>.sha256``.  ``key`` is a SHA-256 digest of every input that changes the
result, the cache layout version, the installed flexarm version and the versions of the
libraries that compute it (NumPy and SciPy always, the mesher where one is used), so an
upgrade never reuses an entry made by other code: the entries of another flexarm are
simply not found (one info line per cache folder says so).  Volume meshes a robot file
pins (the demo arm's ``tets/*.vtu``) are files of the robot, not cache entries, and are
read whatever the version.  Both files are written atomically, the checksum last: an
entry whose checksum is missing or differs from the file's bytes (a killed write, a
truncated or edited file) is not trusted, it is removed and computed again.

The root is ``$FLEXARM_CACHE`` if set, else ``~/.cache/flexarm``; deleting it is always
safe.  Temporary ``.part`` files that a killed process left behind are swept away the
next time an entry of the same kind is stored.

Faults never stop a run: a damaged entry is reported in one warning line and rebuilt; a
cache that cannot be written (read-only, full disk) gives one warning and the value is
computed without caching.  Processes building the same key take turns (a lock file
``<entry>.lock``): the second one reads what the first stored, so one key only ever has
one value, even from a mesher that is not deterministic.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any

from .files import atomic_path, digest, file_digest

__all__ = ["LAYOUT_VERSION", "Codec", "JSON", "BYTES", "PICKLE", "Cached", "cache_root",
           "cache_key", "cached", "lookup", "library_versions", "package_version",
           "package_digest"]

log = logging.getLogger(__name__)

#: Version of the cache layout and of its key recipe; part of every key.
LAYOUT_VERSION = 3
#: Libraries whose versions enter every key.
_BASE_LIBRARIES = ("numpy", "scipy")
#: A ``.part`` file older than this [s] belongs to a process that died while writing.
_STALE_PART_SECONDS = 3600.0
#: File in the cache root naming the flexarm version that stored entries there last.
_VERSION_FILE = "flexarm-version"
#: (root, version) pairs whose version file this process has checked.
_VERSIONS_SEEN: set = set()


@dataclass(frozen=True)
class Codec:
    """How a value is stored: file ``suffix`` (with the dot), ``save(path, value)`` and
    ``load(path) -> value``.  ``load`` may raise anything on a bad file."""

    suffix: str
    save: Callable[[Path, Any], None]
    load: Callable[[Path], Any]


def _save_json(path: Path, value) -> None:
    path.write_text(json.dumps(value))


def _load_json(path: Path):
    return json.loads(path.read_text())


#: Plain JSON values (dicts, lists, numbers, strings).
JSON = Codec(".json", _save_json, _load_json)


def _save_bytes(path: Path, value: bytes) -> None:
    path.write_bytes(value)


def _load_bytes(path: Path) -> bytes:
    return path.read_bytes()


#: Raw file contents (a picture), stored as they are: ``bytes``.
BYTES = Codec(".bin", _save_bytes, _load_bytes)


def _save_pickle(path: Path, value) -> None:
    import pickle

    path.write_bytes(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))


def _load_pickle(path: Path):
    import pickle

    return pickle.loads(path.read_bytes())  # noqa: S301 - our own checksummed entry


#: A result object of the package (a frozen dataclass of arrays and numbers), pickled.
#: Only for keys that include :func:`package_digest`: a pickle is read back by the
#: code that wrote it.
PICKLE = Codec(".pkl", _save_pickle, _load_pickle)


@dataclass(frozen=True, eq=False)
class Cached:
    """A cached value, the entry's file (None when caching was off) and whether it was
    read from the cache (``is_hit``) rather than computed."""

    value: Any
    path: Path | None
    is_hit: bool


def cache_root() -> Path:
    """The cache folder (created): ``$FLEXARM_CACHE`` or ``~/.cache/flexarm``.

    Examples
    --------
    >>> cache_root().is_dir()
    True
    """
    env = os.environ.get("FLEXARM_CACHE")
    path = Path(env) if env else Path.home() / ".cache" / "flexarm"
    path.mkdir(parents=True, exist_ok=True)
    return path


@cache
def library_versions(libraries: tuple[str, ...] = ()) -> tuple[tuple[str, str], ...]:
    """``(name, version)`` of NumPy, SciPy and ``libraries`` ("absent" when not installed)."""
    out = []
    for name in _BASE_LIBRARIES + tuple(libraries):
        try:
            out.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            out.append((name, "absent"))
    return tuple(out)


@cache
def package_version() -> str:
    """The installed flexarm's version (its package metadata; ``flexarm.__version__``
    when run from a source tree that is not installed).

    Examples
    --------
    >>> package_version().count(".") >= 1
    True
    """
    try:
        return metadata.version("flexarm")
    except metadata.PackageNotFoundError:
        from .. import __version__

        return __version__


@cache
def package_digest() -> str:
    """SHA-256 hex digest of every file of the installed flexarm package (its code and
    shipped data): the key part of a result that any change of the code may change.

    Examples
    --------
    >>> package_digest() == package_digest() and len(package_digest())
    64
    """
    import hashlib

    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(root.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts and path.suffix != ".pyc":
            h.update(path.relative_to(root).as_posix().encode() + b"\x00")
            h.update(path.read_bytes())
    return h.hexdigest()


def cache_key(kind: str, *parts, libraries: tuple[str, ...] = ()) -> str:
    """SHA-256 hex key of an entry of ``kind`` computed from ``parts`` (arrays hashed by
    content, everything else by ``repr``) with the flexarm version
    (:func:`package_version`) and ``libraries`` (PyPI names) at their installed versions.

    Examples
    --------
    >>> cache_key("tets", 0.01) == cache_key("tets", 0.02)
    False
    >>> len(cache_key("tets", 0.01, libraries=("pytetwild",)))
    64
    """
    return digest("flexarm-cache", LAYOUT_VERSION, kind, ("flexarm", package_version()),
                  library_versions(tuple(libraries)), *parts)


def _checksum_path(path: Path) -> Path:
    return path.with_name(path.name + ".sha256")


def _load_verified(path: Path, codec: Codec):
    """The entry's value, or None when it is absent or cannot be trusted (then removed)."""
    check = _checksum_path(path)
    if not path.is_file():
        return None
    try:
        if not check.is_file() or check.read_text().strip() != file_digest(path):
            raise ValueError("checksum missing or wrong (an interrupted or damaged write)")
        return codec.load(path)
    except Exception as exc:  # noqa: BLE001 - any failure to read means: compute again
        reason = (str(exc).splitlines() or [type(exc).__name__])[0]
        log.warning("cache entry %s is damaged (%s): removed, computing it again", path, reason)
        try:
            path.unlink(missing_ok=True)
            check.unlink(missing_ok=True)
        except OSError:  # a read-only cache: the entry is just not used
            pass
        return None


def _sweep_parts(folder: Path) -> None:
    """Remove temporary files of writes that a killed process never finished."""
    now = time.time()
    for part in folder.glob(".*.part*"):
        try:
            if now - part.stat().st_mtime > _STALE_PART_SECONDS:
                part.unlink()
        except OSError:  # another process finished or removed it meanwhile
            continue


def _store(path: Path, value, codec: Codec) -> None:
    _sweep_parts(path.parent)
    with atomic_path(path) as tmp:
        codec.save(tmp, value)
        checksum = file_digest(tmp)
    with atomic_path(_checksum_path(path)) as tmp:
        tmp.write_text(checksum + "\n")


def _entry_path(kind: str, key: str, codec: Codec) -> Path:
    return cache_root() / kind / f"{key}{codec.suffix}"


def lookup(kind: str, key: str, codec: Codec = JSON):
    """The verified value of entry ``key`` of ``kind``, or None (nothing is computed)."""
    return _load_verified(_entry_path(kind, key, codec), codec)


def cached(kind: str, key: str, compute: Callable[[], Any], codec: Codec = JSON,
           enabled: bool = True) -> Cached:
    """The value of entry ``key`` of ``kind``: read and verified, or computed and stored.

    Parameters
    ----------
    kind : str
        Sub-folder of the cache (``"tets"``, ``"superelements"``, ...).
    key : str
        From :func:`cache_key` over every input of ``compute``.
    compute : callable () -> value
    codec : Codec
        How the value is written and read (default: JSON).
    enabled : bool
        False computes without reading or writing the cache.

    Examples
    --------
    >>> import tempfile
    >>> key = cache_key("example", tempfile.mkdtemp())  # a key no run has used
    >>> cached("example", key, lambda: {"n": 3}).is_hit
    False
    >>> cached("example", key, lambda: {"n": 3}).value
    {'n': 3}
    """
    if not enabled:
        return Cached(compute(), None, False)
    try:
        path = _entry_path(kind, key, codec)
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        _warn_unwritable(exc, "")
        return Cached(compute(), None, False)
    with _key_lock(path):
        value = _load_verified(path, codec)
        if value is not None:
            log.info("cache hit %s/%s", kind, path.name)
            return Cached(value, path, True)
        value = compute()
        try:
            _note_version(cache_root())
            _store(path, value, codec)
        except OSError as exc:
            _warn_unwritable(exc, path)
            return Cached(value, None, False)
    log.info("cache stored %s/%s", kind, path.name)
    return Cached(value, path, False)


def _note_version(root: Path) -> None:
    """Record which flexarm stores entries in ``root``; once per process, one info line
    when another version stored there before (its entries have other keys: they are not
    read, and this one computes its own)."""
    version = package_version()
    if (root, version) in _VERSIONS_SEEN:
        return
    _VERSIONS_SEEN.add((root, version))
    marker = root / _VERSION_FILE
    try:
        before = marker.read_text().strip()
    except (OSError, UnicodeDecodeError):
        before = ""
    if before == version:
        return
    if before:
        log.info("cache %s holds entries of flexarm %s, not read by flexarm %s (deleting the "
                 "folder frees their space)", root, before, version)
    with atomic_path(marker) as tmp:
        tmp.write_text(version + "\n")


def _warn_unwritable(exc: OSError, path) -> None:
    where = exc.filename or path or os.environ.get("FLEXARM_CACHE", "~/.cache/flexarm")
    log.warning("cannot write the cache (%s: %s): the result is used without caching",
                where, exc.strerror or exc)


@contextlib.contextmanager
def _key_lock(path: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``<path>.lock`` (no lock where the cache is read-only or
    the platform has no ``fcntl``: then concurrent writers of a key may both compute)."""
    try:
        import fcntl

        handle = open(path.with_name(path.name + ".lock"), "a")  # noqa: SIM115 - held below
    except (ImportError, OSError):
        yield
        return
    with handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)
