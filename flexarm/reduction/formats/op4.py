"""Nastran OUTPUT4 (OP4) binary matrices, and the superelement as OP4 (write only).

An OP4 file is a sequence of Fortran unformatted records (a 4-byte length before and
after each): per matrix a header ``NCOL, NROW, FORM, TYPE, NAME`` (8 characters), then
one record per non-null column ``ICOL, IROW, NW`` and the ``NW`` words of the column
from row ``IROW`` to its last non-zero, and a closing record with ``ICOL = NCOL + 1``.
We write real double precision (``TYPE = 2``), little-endian, bit for bit; ``FORM`` 6
(symmetric, also for a matrix symmetric up to round-off, then written as the mean of its
triangles), 1 (square) or 2 (rectangular).  Nastran reads it with ``INPUTT4``;
pyNastran with ``pyNastran.op4.read_op4``.  (pyNastran 1.4's own binary writer makes
files its reader rejects, and its ASCII writer breaks on three-digit exponents, so
the few lines of the format are ours.)

A superelement file holds ``KAAX`` and ``MAAX`` (form 6), the DOF table ``DOFTAB``
(one row per DOF: point ID, component 1-6 or 0 for a modal SPOINT, interface number
1-based or 0; the numbering of :func:`~flexarm.reduction.formats.dmig.dof_labels`) and
``GRIDXYZ``, the boundary node positions [m] in the link frame.  With its recovery
matrix it also holds ``OTM`` (form 2; full-FE node displacements [m] per unit reduced
coordinate, the output transformation matrix of a Nastran superelement) and ``OTMDOF``,
its row table (one row per row of ``OTM``: FE node number of the link mesh, 1-based, and
component 1-3 in the link frame).  SI units.  It carries no names or mode data: write
HDF5 (``.h5``) as well to read the superelement back.
"""

from __future__ import annotations

import re
import struct

import numpy as np

from ...fe.files import atomic_path
from ..superelement import Superelement
from ..tolerances import tol
from .dmig import dof_labels

__all__ = ["write_matrices", "write", "superelement_matrices"]

_NAME = re.compile(r"^[A-Z][A-Z0-9_]{0,7}$")


def _record(f, payload: bytes) -> None:
    n = struct.pack("<i", len(payload))
    f.write(n + payload + n)


def _symmetric(A: np.ndarray, limit: float) -> np.ndarray | None:
    """``A`` made exactly symmetric when it is within ``limit`` of it, else None.

    The test is scaled by the diagonal, so that coordinates of different units (m and rad,
    N/m and N m/rad) weigh alike; where a diagonal entry is 0 the largest entry scales.
    The mean of the two triangles is mirrored: an exactly symmetric ``A`` is kept bit for
    bit.
    """
    if A.shape[0] != A.shape[1]:
        return None
    if np.array_equal(A, A.T):
        return A
    d = np.sqrt(np.abs(np.diag(A)))
    d[d == 0] = np.sqrt(np.abs(A).max())
    with np.errstate(over="ignore", invalid="ignore"):
        off = np.abs(A - A.T) / np.outer(d, d)
    if not np.all(off <= limit):
        return None
    mean = np.where(A == A.T, A, 0.5 * A + 0.5 * A.T)
    return np.triu(mean) + np.triu(mean, 1).T


def write_matrices(path, matrices: dict, symmetry_tol: float | None = None) -> None:
    """Write ``{NAME: (nrow, ncol) float array}`` to ``path`` as binary OP4, atomically.

    Names are 1-8 upper-case letters, digits or ``_`` starting with a letter; values are
    written as float64 exactly.  A square matrix symmetric within ``symmetry_tol``
    (default ``tol.op4_symmetry``: round-off, scaled by the diagonal) is written as form 6
    with the mean of its two triangles; other square matrices as form 1, rectangular ones
    as form 2.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "k.op4"
    >>> write_matrices(p, {"KAAX": np.array([[2.0, -1.0], [-1.0, 2.0]])})
    >>> p.stat().st_size
    132
    """
    for name, A in matrices.items():
        if not _NAME.match(name):
            raise ValueError(f"OP4 matrix name must be 1-8 characters A-Z, 0-9, _ starting "
                             f"with a letter, got '{name}'")
        if np.ndim(A) != 2:
            raise ValueError(f"OP4 matrix {name} must be 2-D, got shape {np.shape(A)}")
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        for name, A in matrices.items():
            A = np.asarray(A, dtype="<f8")
            nrow, ncol = A.shape
            S = _symmetric(A, tol.op4_symmetry if symmetry_tol is None else symmetry_tol)
            form = 6 if S is not None else 1 if nrow == ncol else 2
            A = A if S is None else S
            _record(f, struct.pack("<4i8s", ncol, nrow, form, 2, name.ljust(8).encode()))
            nz = A != 0
            has = nz.any(axis=0)
            first = np.argmax(nz, axis=0)
            last = nrow - 1 - np.argmax(nz[::-1], axis=0)
            for j in np.flatnonzero(has):  # one record per column: the format's unit
                v = np.ascontiguousarray(A[first[j] : last[j] + 1, j])
                _record(f, struct.pack("<3i", j + 1, first[j] + 1, 2 * v.size) + v.tobytes())
            _record(f, struct.pack("<3i", ncol + 1, 1, 2) + np.zeros(1, "<f8").tobytes())


def superelement_matrices(se: Superelement) -> dict:
    """``KAAX``, ``MAAX``, ``DOFTAB``, ``GRIDXYZ`` and, with a recovery matrix, ``OTM``
    and ``OTMDOF`` of ``se`` (see the module docstring)."""
    n_nodes = len(se.node_positions)
    ids, comps = dof_labels(n_nodes, se.dofs_per_node, se.n_modes)
    iface = np.concatenate([np.repeat(np.asarray(se.node_interface) + 1, se.dofs_per_node),
                            np.zeros(se.n_modes, dtype=np.int64)])
    out = {"KAAX": np.asarray(se.K, dtype=float), "MAAX": np.asarray(se.M, dtype=float),
           "DOFTAB": np.column_stack([ids, comps, iface]).astype(float),
           "GRIDXYZ": np.asarray(se.node_positions, dtype=float).reshape(-1, 3)}
    if se.T is not None:
        rows = np.arange(np.shape(se.T)[0])
        out["OTM"] = np.asarray(se.T, dtype=float)
        out["OTMDOF"] = np.column_stack([rows // 3 + 1, rows % 3 + 1]).astype(float)
    return out


def write(path, se: Superelement) -> None:
    """Write ``se`` as binary OP4 (``.op4``) atomically."""
    write_matrices(path, superelement_matrices(se))
