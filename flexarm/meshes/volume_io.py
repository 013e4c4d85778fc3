"""Read and write tetrahedral meshes; the file extension picks the format module."""

from __future__ import annotations

import logging
from pathlib import Path

from ..fe.errors import FlexarmError, ReadError
from ..fe.mesh import TetMesh
from ..fe.typing import PathType
from . import formats

__all__ = ["read_volume_mesh", "write_volume_mesh"]

logger = logging.getLogger(__name__)


def _supported() -> str:
    return "supported: " + ", ".join(formats.registry.extensions())


def read_volume_mesh(path: PathType) -> TetMesh:
    """Read a tetrahedral mesh (``.vtu``, ``.msh``, ``.vtk`` or flexarm ``.npz``).

    Only tetra (Tet4) or tetra10 (Tet10, VTK node order) cells are kept; nodes that
    no tetrahedron uses are dropped.  Point data ``set:<name>`` become node sets.

    Parameters
    ----------
    path : path-like

    Returns
    -------
    TetMesh

    Raises
    ------
    ReadError
        Missing file, unknown extension or unreadable contents.
    MeshError
        The file holds no tetrahedra.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "bar.vtu"
    >>> write_volume_mesh(path, TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1), order=2))
    >>> mesh = read_volume_mesh(path)
    >>> mesh.n_tets, mesh.order
    (24, 2)
    """
    path = Path(path)
    fmt = formats.registry.find(path)
    if not path.is_file():
        raise ReadError(f"{path}: no such file")
    if fmt is None:
        raise ReadError(f"{path}: cannot read '{path.suffix}' volume meshes ({_supported()})")
    logger.info("reading %s mesh %s", fmt.name, path)
    try:
        mesh = fmt.read(path)
    except FlexarmError:
        raise
    except Exception as exc:  # meshio and numpy raise many types on corrupt bytes
        raise ReadError(f"{path}: cannot read it as {fmt.name}: {exc}") from exc
    logger.info("read %s: %d nodes, %d elements", path, mesh.n_nodes, mesh.n_tets)
    return mesh


def write_volume_mesh(path: PathType, mesh: TetMesh) -> None:
    """Write a tetrahedral mesh atomically; the extension picks the format.

    ``.msh`` is written as Gmsh MSH 4.1 binary; node sets go along as point data
    (``set:<name>``).  On failure nothing is left at ``path``.

    Parameters
    ----------
    path : path-like
        ``.vtu``, ``.msh``, ``.vtk`` or ``.npz``.
    mesh : TetMesh

    Raises
    ------
    ValueError
        Unknown extension.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tet.msh"
    >>> write_volume_mesh(path, TetMesh.unit_tet())
    >>> read_volume_mesh(path).tets.tolist()
    [[0, 1, 2, 3]]
    """
    path = Path(path)
    fmt = formats.registry.find(path)
    if fmt is None:
        raise ValueError(f"{path}: cannot write '{path.suffix}' volume meshes ({_supported()})")
    logger.info("writing %s mesh %s (%d elements)", fmt.name, path, mesh.n_tets)
    fmt.write(path, mesh)
