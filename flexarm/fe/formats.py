"""One file-format registry class for every kind of file the package reads and writes
(volume meshes, superelements, robot descriptions), like meshio's ``register_format``.

A :class:`FormatRegistry` holds the formats of one kind of object.  Each format has a
name, its file extensions, and a reader and/or a writer; the registry finds the format
of a path by its extension (or by an explicit name), and its :meth:`~FormatRegistry.read`
turns every failure of a reader into one :class:`~flexarm.fe.errors.ReadError` line that
names the file and the format.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .errors import FlexarmError, ReadError

__all__ = ["FileFormat", "FormatRegistry"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class FileFormat:
    """A file format: ``name``, lower-case ``extensions`` with the dot, ``read(path, **kw)``
    and ``write(path, obj, **kw)`` (either may be None: read-only or write-only)."""

    name: str
    extensions: tuple[str, ...]
    read: Callable[..., Any] | None = None
    write: Callable[..., Any] | None = None


class FormatRegistry:
    """The formats of one kind of object (``what``, e.g. ``"volume mesh"``).

    Examples
    --------
    >>> reg = FormatRegistry("note")
    >>> _ = reg.register("text", (".txt", ".TEXT"), read=lambda p: open(p).read())
    >>> reg.format_of("a/b/readme.TXT").name, reg.extensions()
    ('text', ('.text', '.txt'))
    >>> reg.find("readme.md") is None
    True
    """

    def __init__(self, what: str):
        self.what = what
        self._by_name: dict[str, FileFormat] = {}
        self._by_ext: dict[str, FileFormat] = {}

    def register(self, name: str, extensions, read: Callable | None = None,
                 write: Callable | None = None) -> FileFormat:
        """Register a format (a later registration of a name or extension wins)."""
        fmt = FileFormat(name, tuple(e.lower() for e in extensions), read, write)
        self._by_name[name] = fmt
        for ext in fmt.extensions:
            self._by_ext[ext] = fmt
        return fmt

    def names(self) -> tuple[str, ...]:
        """Registered format names, in registration order."""
        return tuple(self._by_name)

    def extensions(self, mode: str | None = None) -> tuple[str, ...]:
        """Sorted registered extensions (``mode="r"``/``"w"``: only readable/writable)."""
        return tuple(sorted(e for e, f in self._by_ext.items()
                            if mode is None or (f.read if mode == "r" else f.write)))

    def find(self, path) -> FileFormat | None:
        """The format registered for ``path``'s extension, or None."""
        return self._by_ext.get(Path(path).suffix.lower())

    def format_of(self, path, name: str | None = None, mode: str | None = None) -> FileFormat:
        """The format named ``name``, else the one of ``path``'s extension.

        ``mode`` ``"r"`` or ``"w"`` also requires a reader or a writer.  Raises
        ``ValueError`` naming the path and the known names or extensions.
        """
        if name is not None:
            if name not in self._by_name:
                raise ValueError(f"{self.what} format must be one of "
                                 f"{', '.join(self._by_name)}, got '{name}'")
            fmt = self._by_name[name]
        else:
            fmt = self.find(path)
            if fmt is None:
                suffix = Path(path).suffix or "(none)"
                raise ValueError(f"{path}: unknown {self.what} extension '{suffix}' "
                                 f"(known: {', '.join(self.extensions(mode))})")
        if mode is not None and (fmt.read if mode == "r" else fmt.write) is None:
            verb = "read" if mode == "r" else "write"
            raise ValueError(f"{path}: cannot {verb} {self.what} files of format {fmt.name} "
                             f"(can {verb}: {', '.join(self.extensions(mode))})")
        return fmt

    def read(self, path, name: str | None = None, **options):
        """Read ``path`` with its format; a reader's failure becomes one ``ReadError`` line."""
        path = Path(path)
        fmt = self.format_of(path, name, "r")
        if not path.exists():
            raise FileNotFoundError(2, "no such file", str(path))
        log.info("reading %s %s (%s)", self.what, path, fmt.name)
        try:
            return fmt.read(path, **options)
        except (FlexarmError, FileNotFoundError):
            raise
        except Exception as exc:  # noqa: BLE001 - readers of foreign formats raise anything
            raise ReadError(f"{path}: cannot read it as a {fmt.name} {self.what} ({exc})") from exc

    def write(self, path, obj, name: str | None = None, **options) -> Path:
        """Write ``obj`` to ``path`` with its format (writers write atomically)."""
        path = Path(path)
        fmt = self.format_of(path, name, "w")
        log.info("writing %s %s (%s)", self.what, path, fmt.name)
        fmt.write(path, obj, **options)
        return path
