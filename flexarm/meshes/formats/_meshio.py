"""Conversion between :class:`TetMesh` and ``meshio.Mesh`` shared by the meshio formats.

Node sets travel as point data ``"set:<name>"`` (1 on members, 0 elsewhere).
Tet10 node order is VTK's in both objects; meshio itself permutes the two
mid-edge nodes that Gmsh orders differently (its local nodes 8 and 9).
"""

from __future__ import annotations

import logging

import numpy as np

from ...fe.errors import MeshError
from ...fe.files import atomic_path
from ...fe.mesh import TetMesh

__all__ = ["to_meshio", "from_meshio", "read_meshio", "write_meshio", "SET_PREFIX"]

logger = logging.getLogger(__name__)

SET_PREFIX = "set:"
_CELL_TYPE = {1: "tetra", 2: "tetra10"}


def to_meshio(mesh: TetMesh, set_dtype=np.uint8, cell_dtype=np.int64):
    """``meshio.Mesh`` with one tetra/tetra10 block and the node sets as point data."""
    import meshio

    point_data = {}
    for name, ids in mesh.node_sets.items():
        mask = np.zeros(mesh.n_nodes, dtype=set_dtype)
        mask[ids] = 1
        point_data[SET_PREFIX + name] = mask
    cells = [(_CELL_TYPE[mesh.order], mesh.tets.astype(cell_dtype))]
    return meshio.Mesh(np.asarray(mesh.points, dtype=np.float64), cells, point_data=point_data)


def from_meshio(data, name: str) -> TetMesh:
    """TetMesh from the tetra or tetra10 blocks of a ``meshio.Mesh`` (other cells dropped).

    Nodes used only by dropped cells are removed (node sets renumbered).
    """
    blocks = {}
    dropped = set()
    for block in data.cells:
        if block.type in ("tetra", "tetra10"):
            blocks.setdefault(block.type, []).append(np.asarray(block.data, dtype=np.int64))
        else:
            dropped.add(block.type)
    if not blocks:
        found = ", ".join(sorted(dropped)) or "no cells"
        raise MeshError(f"{name}: no tetrahedra (tetra or tetra10 cells) in the file ({found})")
    if len(blocks) > 1:
        raise MeshError(f"{name}: mixes tetra and tetra10 cells; keep one element order")
    tets = np.concatenate(next(iter(blocks.values())))
    if dropped:
        logger.info("%s: kept the tetrahedra, dropped %s cells", name, ", ".join(sorted(dropped)))
    points = np.asarray(data.points, dtype=np.float64)
    if points.shape[1] == 2:
        raise MeshError(f"{name}: the points are 2-D, a volume mesh needs (n, 3)")
    sets = {
        key[len(SET_PREFIX) :]: np.flatnonzero(np.asarray(val).ravel() > 0.5)
        for key, val in data.point_data.items()
        if key.startswith(SET_PREFIX)
    }
    used = np.unique(tets)
    if len(used) < len(points):
        new_id = np.full(len(points), -1, dtype=np.int64)
        new_id[used] = np.arange(len(used))
        logger.info("%s: removed %d nodes no element uses", name, len(points) - len(used))
        points, tets = points[used], new_id[tets]
        sets = {k: new_id[v[np.isin(v, used)]] for k, v in sets.items()}
    return TetMesh(points, tets, sets)


def read_meshio(path, file_format: str) -> TetMesh:
    """Read ``path`` with the reader of meshio's submodule ``file_format``.

    The submodule's reader is called directly: ``meshio.read`` prints and calls
    ``sys.exit(1)`` when its reader raises ``meshio.ReadError`` (meshio 5.3).
    """
    import importlib

    reader = importlib.import_module(f"meshio.{file_format}").read
    return from_meshio(reader(str(path)), str(path))


def write_meshio(path, mesh: TetMesh, file_format: str, set_dtype=np.uint8, **kwargs) -> None:
    """Write atomically with meshio's ``file_format`` writer."""
    import meshio

    cell_dtype = kwargs.pop("cell_dtype", np.int64)
    data = to_meshio(mesh, set_dtype=set_dtype, cell_dtype=cell_dtype)
    with atomic_path(path) as tmp:
        meshio.write(tmp, data, file_format=file_format, **kwargs)
