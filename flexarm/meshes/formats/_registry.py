"""Which module reads and writes which volume-mesh file extension (like meshio's registry).

Each format module calls :func:`register_format` once at import; the package
``__init__`` imports them all.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ...fe.mesh import TetMesh

__all__ = ["VolumeFormat", "register_format", "format_for", "extensions"]


@dataclass(frozen=True)
class VolumeFormat:
    """A volume-mesh file format.

    Attributes
    ----------
    name : str
        Short name used in messages (``"vtu"``, ``"gmsh"``, ...).
    extensions : tuple of str
        Lower-case file extensions with the dot (``(".vtu",)``).
    read : callable (path) -> TetMesh
    write : callable (path, TetMesh) -> None
        Writes atomically.
    """

    name: str
    extensions: tuple[str, ...]
    read: Callable[[Path], TetMesh]
    write: Callable[[Path, TetMesh], None]


_formats: dict[str, VolumeFormat] = {}


def register_format(
    name: str,
    extensions: tuple[str, ...],
    read: Callable[[Path], TetMesh],
    write: Callable[[Path, TetMesh], None],
) -> VolumeFormat:
    """Register ``read``/``write`` for ``extensions`` (later registrations win)."""
    fmt = VolumeFormat(name, tuple(e.lower() for e in extensions), read, write)
    for ext in fmt.extensions:
        _formats[ext] = fmt
    return fmt


def extensions() -> tuple[str, ...]:
    """Sorted tuple of every registered extension.

    Examples
    --------
    >>> from flexarm.meshes import formats
    >>> formats.extensions()
    ('.msh', '.npz', '.vtk', '.vtu')
    """
    return tuple(sorted(_formats))


def format_for(path) -> VolumeFormat | None:
    """The format registered for ``path``'s extension, or None.

    Examples
    --------
    >>> from flexarm.meshes import formats
    >>> formats.format_for("link.MSH").name
    'gmsh'
    """
    return _formats.get(Path(path).suffix.lower())
