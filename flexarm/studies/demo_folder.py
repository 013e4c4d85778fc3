"""Multi-file outputs (``demo``, ``study``) built in a temporary folder and moved into
place only when complete.

The files are written into a hidden sibling folder ``.<name>.part-<random>`` (same file
system, so the final moves are renames).  On success every entry is moved into the
output folder, replacing entries of the same name and leaving unrelated files alone,
with the ``last`` entry (the demo's ``index.md``) moved last: its presence means the
output is complete.  On any exception, Ctrl-C included, the temporary folder is
removed and the output folder is untouched, so an interrupted run never leaves
half-written results beside older complete ones.  A folder left by a killed process
is swept by the next run into the same output.
"""

from __future__ import annotations

import contextlib
import logging
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_folder"]

log = logging.getLogger(__name__)

_PART = ".part-"


def _sweep(folder: Path) -> None:
    """Remove temporary folders of ``folder`` whose process no longer runs."""
    for stale in folder.parent.glob(f".{folder.name}{_PART}*"):
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

    Parameters
    ----------
    folder : path-like
        The output folder (created if missing; other files in it are kept).
    last : str, optional
        Name of the entry moved last (e.g. ``"index.md"``).

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
        raise NotADirectoryError(20, "not a folder", str(folder))
    folder.parent.mkdir(parents=True, exist_ok=True)
    _sweep(folder)
    tmp = Path(tempfile.mkdtemp(prefix=f".{folder.name}{_PART}{os.getpid()}-",
                                dir=folder.parent))
    try:
        yield tmp
        _move_into(tmp, folder, last)
        log.info("moved the complete output into %s", folder)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
