"""Nastran bulk data: DMIG stiffness ``KAAX`` and mass ``MAAX`` with interface GRIDs.

Boundary node ``k`` (0-based) is ``GRID k+1`` at its position (basic frame = link
frame); its DOFs are components 1-6 (1-3 for kept region nodes).  Modal coordinates
are ``SPOINT``s numbered from ``s0 = max(1000, n_b) + 1``.  Matrices are symmetric
(``IFO = 6``, upper triangle by column), real double precision (``TIN = 2``), written
in free-field format with full 17-digit values, so nothing is lost (fixed 16-character
fields would keep only about 10 digits).  Include the file in a Nastran run with
``K2GG = KAAX`` and ``M2GG = MAAX`` in case control; pyNastran reads it with
``BDF().read_bdf(path, punch=True)`` (the first line also says ``punch=True``).
The remaining metadata (names, frames, frequencies, mass properties) is one
``$flexarm-json`` comment line, which lets :func:`read` round-trip the superelement.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ..superelement import Superelement, from_arrays
from ._checksum import CHECKSUM_KEY, content_checksum, verify_checksum
from ._meta import meta_from_json, meta_json

__all__ = ["read", "write", "dof_labels"]

_TAG = "$flexarm-json "


def dof_labels(n_b_nodes: int, dofs_per_node: int, n_modes: int):
    """(n,) Nastran point IDs and (n,) components of each superelement DOF.

    >>> [a.tolist() for a in dof_labels(1, 6, 1)]
    [[1, 1, 1, 1, 1, 1, 1001], [1, 2, 3, 4, 5, 6, 0]]
    """
    ids = np.concatenate([np.repeat(np.arange(1, n_b_nodes + 1), dofs_per_node),
                          max(1000, n_b_nodes) + 1 + np.arange(n_modes)])
    comps = np.concatenate([np.tile(np.arange(1, dofs_per_node + 1), n_b_nodes),
                            np.zeros(n_modes, dtype=np.int64)])
    return ids, comps


def _matrix_cards(name: str, A: np.ndarray, ids, comps) -> list[str]:
    n = A.shape[0]
    lines = [f"DMIG,{name},0,6,2,0,,,{n}"]
    for j in range(n):  # one card per column: a loop over matrix columns, not nodes
        rows = np.flatnonzero(A[: j + 1, j])
        if rows.size == 0:
            continue
        entries = [f"{ids[i]},{comps[i]},{float(A[i, j])!r}" for i in rows]
        lines.append(f"DMIG,{name},{ids[j]},{comps[j]},," + entries[0])
        for k in range(1, len(entries), 2):
            lines.append("+," + ",,".join(entries[k : k + 2]))
    return lines


def write(path, se: Superelement) -> None:
    """Write bulk data (``.bdf``/``.dmig``/``.pch``) atomically."""
    ids, comps = dof_labels(len(se.node_positions), se.dofs_per_node, se.n_modes)
    K = np.asarray(se.K, dtype=np.float64)
    M = np.asarray(se.M, dtype=np.float64)
    lines = ["$ pyNastran : punch=True",
             "$ flexarm superelement: DMIG KAAX (stiffness), MAAX (mass); SI units",
             f"$ interfaces: {', '.join(se.interface_names)}",
             _TAG + meta_json(se)]
    for k, p in enumerate(se.node_positions):
        lines.append(f"GRID,{k + 1},,{float(p[0])!r},{float(p[1])!r},{float(p[2])!r}")
    spoints = ids[comps == 0]
    for k in range(0, spoints.size, 6):
        lines.append("SPOINT," + ",".join(str(s) for s in spoints[k : k + 6]))
    lines += _matrix_cards("KAAX", K, ids, comps)
    lines += _matrix_cards("MAAX", M, ids, comps)
    # the checksum is of what a reader gets back from these cards (the upper triangle)
    d = _parse(lines, path)
    lines[3] = _TAG + meta_json(se, content_checksum(d))
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")


def read(path) -> Superelement:
    """Read a file written by :func:`write` (free-field DMIG plus the metadata line)."""
    path = Path(path)
    d = _parse(path.read_text().splitlines(), path)
    verify_checksum(d, d.pop(CHECKSUM_KEY, None), path)
    return from_arrays(d, str(path))


def _parse(text: list[str], path) -> dict:
    """The fields of a DMIG file's lines (the checksum, if any, under its key)."""
    meta = [ln[len(_TAG):] for ln in text if ln.startswith(_TAG)]
    if not meta:
        raise ReadError(f"{path}: no '{_TAG.strip()}' line: not written by flexarm")
    d = meta_from_json(meta[0])
    ids, comps = dof_labels(len(d["node_positions"]), int(d["dofs_per_node"]),
                            len(d["freq_hz"]))
    index = {(int(i), int(c)): k for k, (i, c) in enumerate(zip(ids, comps, strict=True))}
    mats = {"KAAX": None, "MAAX": None}
    name, col = None, None
    for lineno, ln in enumerate(text, start=1):
        f = ln.split(",")
        try:
            if f[0] == "DMIG" and f[2] == "0":
                name = f[1]
                mats[name] = np.zeros((int(f[8]), int(f[8])))
                continue
            if f[0] == "DMIG":
                name, col = f[1], index[(int(f[2]), int(f[3]))]
                entries = f[5:]
            elif f[0] == "+":
                entries = f[1:]
            else:
                continue
            for g, c, a in zip(entries[0::4], entries[1::4], entries[2::4], strict=False):
                row = index[(int(g), int(c))]
                mats[name][row, col] = mats[name][col, row] = float(a)
        except (KeyError, ValueError, IndexError, TypeError):
            raise ReadError(f"{path}:{lineno}: bad DMIG card '{ln[:60]}'") from None
    if mats["KAAX"] is None or mats["MAAX"] is None:
        raise ReadError(f"{path}: needs both DMIG matrices KAAX and MAAX")
    d["K"], d["M"] = mats["KAAX"], mats["MAAX"]
    return d
