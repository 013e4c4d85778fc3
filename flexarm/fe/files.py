"""Atomic file output and input hashing (shared by every writer and by the cache)."""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "umask_mode", "file_digest", "digest"]


@contextlib.contextmanager
def atomic_path(path, suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; move it into place only on success.

    Nothing half-written is ever left at ``path``: on any exception (Ctrl-C included) the
    temporary file is removed and ``path`` is untouched.  ``path`` naming an existing
    folder raises :class:`IsADirectoryError` at once.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "out.txt"
    >>> with atomic_path(target) as tmp:
    ...     _ = tmp.write_text("done")
    >>> target.read_text()
    'done'
    """
    path = Path(path)
    if path.is_dir():  # found now, not by the final rename after all the work
        raise IsADirectoryError(errno.EISDIR, "is a folder, not a file name", str(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    suffix = path.suffix if suffix is None else suffix
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".part{suffix}", dir=path.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        # mkstemp makes 0600 files; give the result the permissions a plain open() would.
        os.chmod(tmp_path, umask_mode(0o666))
        os.replace(tmp_path, path)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def umask_mode(base: int) -> int:
    """The permission bits a new file (``base`` 0o666) or folder (0o777) gets from a plain
    ``open()`` or ``mkdir()`` under the process umask; for what ``mkstemp``/``mkdtemp``
    create private (0600/0700) and is then moved into place.

    Examples
    --------
    >>> old = os.umask(0o027)
    >>> oct(umask_mode(0o777)), oct(umask_mode(0o666))
    ('0o750', '0o640')
    >>> _ = os.umask(old)
    """
    umask = os.umask(0)
    os.umask(umask)
    return base & ~umask


def file_digest(path) -> str:
    """SHA-256 hex digest of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def digest(*parts) -> str:
    """SHA-256 hex digest of the ``repr`` of ``parts`` (bytes and arrays hashed by content)."""
    h = hashlib.sha256()
    for p in parts:
        if isinstance(p, bytes | bytearray):
            h.update(bytes(p))
        elif hasattr(p, "tobytes") and hasattr(p, "dtype"):
            h.update(str((p.dtype.str, p.shape)).encode())
            h.update(p.tobytes())
        else:
            h.update(repr(p).encode())
        h.update(b"\x00")
    return h.hexdigest()
