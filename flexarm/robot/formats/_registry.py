"""File-extension registry of robot description formats (like meshio's ``register_format``)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

__all__ = ["register_format", "reader", "writer", "read", "write"]

_READERS: dict[str, Callable] = {}
_WRITERS: dict[str, Callable] = {}


def register_format(extensions: list[str], read: Callable | None, write: Callable | None) -> None:
    """Register ``read(path)``/``write(path, robot)`` for file extensions (with dot)."""
    for ext in extensions:
        if read is not None:
            _READERS[ext.lower()] = read
        if write is not None:
            _WRITERS[ext.lower()] = write


def reader(path) -> Callable:
    ext = Path(path).suffix.lower()
    if ext not in _READERS:
        raise ValueError(f"no robot reader for '{ext}' files (known: {sorted(_READERS)})")
    return _READERS[ext]


def writer(path) -> Callable:
    ext = Path(path).suffix.lower()
    if ext not in _WRITERS:
        raise ValueError(f"no robot writer for '{ext}' files (known: {sorted(_WRITERS)})")
    return _WRITERS[ext]


def read(path, **kwargs):
    """Read a robot description, format chosen by extension (.toml, .urdf)."""
    return reader(path)(path, **kwargs)


def write(path, robot, **kwargs) -> None:
    """Write a robot description, format chosen by extension (.toml)."""
    writer(path)(path, robot, **kwargs)
