"""Gmsh MSH (``.msh``), through meshio: written as MSH 4.1 binary, read in any version.

Gmsh orders the Tet10 mid-edge nodes like VTK except that local nodes 8 and 9
(edges (1,3) and (2,3)) are swapped; meshio applies that permutation both ways,
so our VTK-ordered ``tets`` round-trip unchanged.  Node sets are written as
``$NodeData`` fields ``set:<name>`` (float 0/1, as Gmsh data is floating point).
"""

from __future__ import annotations

import numpy as np

from ...fe.mesh import TetMesh
from ._meshio import read_meshio, write_meshio

__all__ = ["read", "write"]


def read(path) -> TetMesh:
    """Read the tetrahedra and ``set:*`` node data of a Gmsh ``.msh`` file."""
    return read_meshio(path, "gmsh")


def write(path, mesh: TetMesh) -> None:
    """Write ``mesh`` as binary Gmsh MSH 4.1, atomically."""
    # Binary MSH stores indices as size_t: hand meshio that type (else it warns).
    write_meshio(path, mesh, "gmsh", set_dtype=np.float64, cell_dtype=np.uint64, binary=True)

