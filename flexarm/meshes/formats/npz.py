"""flexarm's own NumPy archive (``.npz``): points, tets and node sets, bit for bit.

Keys: ``format`` (``"flexarm-tetmesh"``), ``version``, ``points`` (n, 3) float64,
``tets`` (m, 4|10) int64, ``set_names`` (k,) str and ``set_<i>`` (s_i,) int64.
Read without pickle.
"""

from __future__ import annotations

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ...fe.mesh import TetMesh

__all__ = ["read", "write", "FORMAT_NAME", "FORMAT_VERSION"]

FORMAT_NAME = "flexarm-tetmesh"
FORMAT_VERSION = 1


def read(path) -> TetMesh:
    """Read a mesh written by :func:`write`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tet.npz"
    >>> write(path, TetMesh.unit_tet().with_node_sets({"base": [0, 1, 2]}))
    >>> mesh = read(path)
    >>> mesh.n_tets, mesh.node_sets["base"].tolist()
    (1, [0, 1, 2])
    """
    with np.load(path, allow_pickle=False) as data:
        if "format" not in data or str(data["format"]) != FORMAT_NAME:
            raise ReadError(f"{path}: not a flexarm mesh archive (no format '{FORMAT_NAME}')")
        version = int(data["version"])
        if version > FORMAT_VERSION:
            raise ReadError(f"{path}: mesh archive version {version} is newer than this flexarm")
        names = [str(n) for n in data["set_names"]]
        sets = {n: data[f"set_{i}"] for i, n in enumerate(names)}
        return TetMesh(data["points"], data["tets"], sets)


def write(path, mesh: TetMesh) -> None:
    """Write ``mesh`` (points, tets, node sets) atomically."""
    names = list(mesh.node_sets)
    arrays = {f"set_{i}": mesh.node_sets[n] for i, n in enumerate(names)}
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(
            f,
            format=np.array(FORMAT_NAME),
            version=np.array(FORMAT_VERSION),
            points=mesh.points,
            tets=mesh.tets,
            set_names=np.array(names, dtype=str),
            **arrays,
        )

