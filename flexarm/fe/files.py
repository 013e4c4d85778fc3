"""Atomic file and folder output, and input hashing (shared by every writer and by the
cache).

A file is written under a temporary name beside its target and renamed into place
(:func:`atomic_path`); a multi-file output (``demo``, ``study``, ``compare -o``) is built
in a hidden folder ``.<name>.part-<pid>-<random>`` (inside the output folder when that
exists, else beside it: the same file system, so the moves are renames) and its entries
are moved in when it is complete (:func:`atomic_folder`, :func:`writes_folder`).  On any
exception, Ctrl-C included, the temporary file or folder is removed: an interrupted run or
a full disk never leaves half-written results beside older complete ones.  An OS error
of a temporary file names the file the user asked for.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import hashlib
import inspect
import logging
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "atomic_folder", "atomic_files", "writes_folder", "write_npz",
           "umask_mode", "file_digest", "digest"]

log = logging.getLogger(__name__)

_PART = ".part-"


def _named(exc: OSError, final: Path, temporary: Path) -> OSError:
    """``exc`` naming the file the user asked for: ``final`` for the ``temporary`` file
    or folder, or for no file at all (a full disk's ``write`` names none); a file inside
    a temporary folder at its final place."""
    if exc.strerror is None:
        return exc
    name = exc.filename
    name = final if not isinstance(name, str | bytes | os.PathLike) else Path(os.fsdecode(name))
    with contextlib.suppress(ValueError):
        name = final / name.relative_to(temporary)
    return OSError(exc.errno, exc.strerror, str(name))


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
    except OSError as exc:
        raise _named(exc, path, tmp_path) from exc
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def _sweep(folder: Path) -> None:
    """Remove temporary folders of ``folder`` whose process no longer runs."""
    for where in (folder.parent, folder) if folder.is_dir() else (folder.parent,):
        for stale in where.glob(f".{folder.name}{_PART}*"):
            pid = stale.name.rsplit("-", 2)[-2] if stale.name.count("-") >= 2 else ""
            if pid.isdigit() and _is_running(int(pid)):
                continue
            shutil.rmtree(stale, ignore_errors=True)


def _is_running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _move_into(tmp: Path, folder: Path, last: str | None) -> None:
    """Move every entry of ``tmp`` into ``folder`` (``last`` at the end)."""
    folder.mkdir(parents=True, exist_ok=True)
    entries = sorted(tmp.iterdir(), key=lambda p: (p.name == last, p.name))
    for src in entries:
        dst = folder / src.name
        if dst.is_dir() and not dst.is_symlink():
            # rename the old folder aside first: the new one appears in one step
            old = Path(tempfile.mkdtemp(prefix=f".{src.name}.old-", dir=folder))
            os.replace(dst, old / src.name)
            os.replace(src, dst)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(src, dst)


@contextlib.contextmanager
def atomic_folder(folder, last: str | None = None) -> Iterator[Path]:
    """Yield a temporary folder; move its entries into ``folder`` only on success.

    On success every entry replaces the entry of the same name in ``folder`` (other
    files there are kept), ``last`` (e.g. the demo's ``index.md``) moved last: its
    presence means the output is complete.  On any exception the temporary folder, and
    any parent folder made for it, is removed and ``folder`` is untouched; an OS error
    names the file at its final place.  A folder left by a killed process is swept by the
    next run into the same output.

    Parameters
    ----------
    folder : path-like
        The output folder (created if missing).
    last : str, optional
        Name of the entry moved last.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "run"
    >>> with atomic_folder(out, last="index.md") as tmp:
    ...     _ = (tmp / "table.csv").write_text("a,b")
    ...     _ = (tmp / "index.md").write_text("done")
    ...     out.exists()
    False
    >>> sorted(p.name for p in out.iterdir())
    ['index.md', 'table.csv']
    >>> try:
    ...     with atomic_folder(out) as tmp:
    ...         _ = (tmp / "table.csv").write_text("half")
    ...         raise KeyboardInterrupt
    ... except KeyboardInterrupt:
    ...     pass
    >>> (out / "table.csv").read_text(), len(list(out.parent.iterdir()))
    ('a,b', 1)
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise NotADirectoryError(errno.ENOTDIR, "not a folder", str(folder))
    made = [p for p in folder.parents if not p.exists()]  # deepest first
    folder.parent.mkdir(parents=True, exist_ok=True)
    named = folder.absolute()  # "." has a name too
    _sweep(named)
    # inside an existing folder (its parent may be read-only: "-o ."), else beside it
    tmp = Path(tempfile.mkdtemp(prefix=f".{named.name}{_PART}{os.getpid()}-",
                                dir=folder if folder.is_dir() else folder.parent))
    done = False
    try:
        yield tmp
        _move_into(tmp, folder, last)
        done = True
        log.info("moved the complete output into %s", folder)
    except OSError as exc:
        raise _named(exc, folder, tmp) from exc
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        for parent in made if not done else ():
            with contextlib.suppress(OSError):
                parent.rmdir()  # only if empty


@contextlib.contextmanager
def atomic_files(*paths) -> Iterator[tuple[Path, ...]]:
    """Yield a temporary path for each of the files ``paths`` (in one folder or several);
    they appear at their places only when the block completes, the first one last.

    One :func:`atomic_folder` per folder: on any exception (Ctrl-C, a full disk) none of
    the files is written, the older ones are kept and an OS error names the file at its
    final place.  Other files the block writes beside a temporary path move in with it.
    A path naming an existing folder raises :class:`IsADirectoryError` at once, a file
    named twice :class:`ValueError` (one would overwrite the other).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_files(out / "model.py", out / "data" / "model.npz") as (script, data):
    ...     _ = data.write_bytes(b"arrays")
    ...     _ = script.write_text("load('data/model.npz')")
    ...     (out / "data").exists()
    False
    >>> sorted(p.relative_to(out).as_posix() for p in out.rglob("*"))
    ['data', 'data/model.npz', 'model.py']
    """
    finals = [Path(p) for p in paths]
    for path in finals:
        if path.is_dir():  # found now, not by the move after all the work
            raise IsADirectoryError(errno.EISDIR, "is a folder, not a file name", str(path))
    named = [p.absolute() for p in finals]
    twice = next((finals[i] for i, p in enumerate(named) if p in named[:i]), None)
    if twice is not None:
        raise ValueError(f"{twice}: named twice among the files to write")
    folders = {}  # absolute folder -> as the caller spelt it (errors name it so)
    for p, spelt in zip(named, finals, strict=True):
        folders.setdefault(p.parent, spelt.parent)
    first = named[0].parent
    with contextlib.ExitStack() as stack:
        # entered first, left last: the first file's folder receives its files last
        tmps = {f: stack.enter_context(atomic_folder(
                    spelt, last=finals[0].name if f == first else None))
                for f, spelt in folders.items()}
        yield tuple(tmps[p.parent] / p.name for p in named)


def writes_folder(argument: str = "folder"):
    """Decorator of a writer of several files into the folder given as ``argument``: it
    writes into an :func:`atomic_folder` instead, and the paths it returns (a list or
    tuple) name the files at their final place.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> @writes_folder("out")
    ... def two_files(out, text):
    ...     return [pathlib.Path(out, n) for n in ("a.txt", "b.txt")
    ...             if pathlib.Path(out, n).write_text(text)]
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "report"
    >>> [p.relative_to(target).as_posix() for p in two_files(target, "x")]
    ['a.txt', 'b.txt']
    """
    def decorate(write):
        signature = inspect.signature(write)

        @functools.wraps(write)
        def wrapper(*args, **kwargs):
            bound = signature.bind(*args, **kwargs)
            final = Path(bound.arguments[argument])
            with atomic_folder(final) as tmp:
                bound.arguments[argument] = tmp
                files = write(*bound.args, **bound.kwargs)
            return _relocated(files, tmp, final)
        return wrapper
    return decorate


def _relocated(files, tmp: Path, final: Path):
    if isinstance(files, list | tuple):
        return type(files)(_relocated(f, tmp, final) for f in files)
    if isinstance(files, str | os.PathLike):
        with contextlib.suppress(ValueError):
            return final / Path(files).relative_to(tmp)
    return files


def write_npz(path, arrays: dict, comment: bytes = b"") -> None:
    """What ``numpy.savez(path, **arrays)`` writes (no pickles), with the zip ``comment``,
    the same bytes for the same arrays (no time stamps), and the archive closed on any
    error: a full disk raises one ``OSError``, not a traceback of a half-closed archive.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "a.npz"
    >>> write_npz(out, {"K": np.eye(2)})
    >>> with np.load(out) as z:
    ...     z["K"].tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    import zipfile

    import numpy as np

    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED, allowZip64=True) as archive:
        for name, value in arrays.items():
            member = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            with archive.open(member, "w", force_zip64=True) as out:
                np.lib.format.write_array(out, np.asanyarray(value), allow_pickle=False)
        archive.comment = comment


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
