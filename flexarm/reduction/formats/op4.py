"""Nastran OUTPUT4 (OP4) binary matrices, and the superelement as OP4 (write only).

An OP4 file is a sequence of Fortran unformatted records (a 4-byte length before and
after each): per matrix a header ``NCOL, NROW, FORM, TYPE, NAME`` (8 characters), then
one record per non-null column ``ICOL, IROW, NW`` and the ``NW`` words of the column
from row ``IROW`` to its last non-zero, and a closing record with ``ICOL = NCOL + 1``.
We write real double precision (``TYPE = 2``), little-endian, bit for bit; ``FORM`` 6
(symmetric), 1 (square) or 2 (rectangular).  Nastran reads it with ``INPUTT4``;
pyNastran with ``pyNastran.op4.read_op4``.  (pyNastran 1.4's own binary writer makes
files its reader rejects, and its ASCII writer breaks on three-digit exponents, so
the few lines of the format are ours.)

A superelement file holds ``KAAX`` and ``MAAX`` (form 6), the DOF table ``DOFTAB``
(one row per DOF: point ID, component 1-6 or 0 for a modal SPOINT, interface number
1-based or 0; the numbering of :func:`~flexarm.reduction.formats.dmig.dof_labels`) and
``GRIDXYZ``, the boundary node positions [m] in the link frame.  SI units.  It carries
no names or mode data: write HDF5 (``.h5``) as well to read the superelement back.
"""

from __future__ import annotations

import re
import struct

import numpy as np

from ...fe.files import atomic_path
from ..superelement import Superelement
from .dmig import dof_labels

__all__ = ["write_matrices", "write", "superelement_matrices"]

_NAME = re.compile(r"^[A-Z][A-Z0-9_]{0,7}$")


def _record(f, payload: bytes) -> None:
    n = struct.pack("<i", len(payload))
    f.write(n + payload + n)


def _form(A: np.ndarray) -> int:
    if A.shape[0] != A.shape[1]:
        return 2
    return 6 if np.array_equal(A, A.T) else 1


def write_matrices(path, matrices: dict) -> None:
    """Write ``{NAME: (nrow, ncol) float array}`` to ``path`` as binary OP4, atomically.

    Names are 1-8 upper-case letters, digits or ``_`` starting with a letter; values are
    written as float64 exactly.

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
            _record(f, struct.pack("<4i8s", ncol, nrow, _form(A), 2, name.ljust(8).encode()))
            nz = A != 0
            has = nz.any(axis=0)
            first = np.argmax(nz, axis=0)
            last = nrow - 1 - np.argmax(nz[::-1], axis=0)
            for j in np.flatnonzero(has):  # one record per column: the format's unit
                v = np.ascontiguousarray(A[first[j] : last[j] + 1, j])
                _record(f, struct.pack("<3i", j + 1, first[j] + 1, 2 * v.size) + v.tobytes())
            _record(f, struct.pack("<3i", ncol + 1, 1, 2) + np.zeros(1, "<f8").tobytes())


def superelement_matrices(se: Superelement) -> dict:
    """``KAAX``, ``MAAX``, ``DOFTAB`` and ``GRIDXYZ`` of ``se`` (see the module docstring)."""
    n_nodes = len(se.node_positions)
    ids, comps = dof_labels(n_nodes, se.dofs_per_node, se.n_modes)
    iface = np.concatenate([np.repeat(np.asarray(se.node_interface) + 1, se.dofs_per_node),
                            np.zeros(se.n_modes, dtype=np.int64)])
    return {"KAAX": np.asarray(se.K, dtype=float), "MAAX": np.asarray(se.M, dtype=float),
            "DOFTAB": np.column_stack([ids, comps, iface]).astype(float),
            "GRIDXYZ": np.asarray(se.node_positions, dtype=float).reshape(-1, 3)}


def write(path, se: Superelement) -> None:
    """Write ``se`` as binary OP4 (``.op4``) atomically."""
    write_matrices(path, superelement_matrices(se))
