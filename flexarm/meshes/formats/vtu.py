"""VTK XML unstructured grid (``.vtu``), through meshio (zlib-compressed binary)."""

from __future__ import annotations

from ...fe.mesh import TetMesh
from ._meshio import read_meshio, write_meshio

__all__ = ["read", "write"]


def read(path) -> TetMesh:
    """Read the tetrahedra and ``set:*`` point data of a ``.vtu`` file."""
    return read_meshio(path, "vtu")


def write(path, mesh: TetMesh) -> None:
    """Write ``mesh`` as ``.vtu`` (node sets as uint8 point data), atomically."""
    write_meshio(path, mesh, "vtu")

