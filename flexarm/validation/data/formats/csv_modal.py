"""Natural frequencies per pose: ``pose, q1_deg … q6_deg, mode, freq_Hz``.

Optional ``damping_ratio`` (unitless, 0 ≤ ζ < 1).  Checked on reading: every row of
a pose has the same joint angles, each (pose, mode) appears once, ``mode`` ≥ 1,
``freq`` > 0, joint angles inside ``limits`` when given.

Mode shapes at measurement points: with the optional columns ``node`` (node id of
the test geometry), ``dir`` (base-frame direction ``x``, ``y``, ``z``), ``phi`` (the
shape's value there, any scaling) and ``phi_im`` (its imaginary part, complex
shapes), a file holds one row per pose, mode and DOF; frequency and damping repeat
on every row of a mode.  Every mode then lists the same DOFs, each (pose, mode,
node, dir) appears once, and reading gives a
:class:`~flexarm.validation.data.shape_data.ShapeData`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ....fe.typing import ArrayLike, PathType
from ..measurements import ModalData
from ..shape_data import ShapeData
from ._checks import check_limits, check_positive, check_same_pose, check_unique
from ._table import Field, Schema, Table, joints, read_table, table_frame, write_table

__all__ = ["SCHEMA", "SHAPES_SCHEMA", "DATA", "from_table", "read", "write", "values",
           "to_dataframe"]

SCHEMA = Schema("modal", (
    Field("pose", "label"), *joints(), Field("mode", "int"),
    Field("freq", "real", "frequency", "Hz"),
    Field("damping_ratio", "real", required=False),
))
#: The modal schema with the mode-shape columns (not part of the kind's vocabulary, so
#: that a plain modal file's messages list only its own columns).
SHAPES_SCHEMA = Schema("modal", SCHEMA.fields + (
    Field("node", "int", required=False), Field("dir", "direction", required=False),
    Field("phi", "real", required=False), Field("phi_im", "real", required=False),
), noun="a modal file with mode shapes")
_SHAPE = ("node", "dir", "phi")
DATA = ModalData


def from_table(table: Table, limits: ArrayLike | None = None, guessed: bool = False
               ) -> ModalData:
    """Check and convert a read table into :class:`ModalData`."""
    if {n.lower() for n in table.unknown} & {*_SHAPE, "phi_im"}:
        table = read_table(table.source, SHAPES_SCHEMA.vocabulary)
    v = table.parse(SHAPES_SCHEMA if "node" in table.columns or "phi" in table.columns
                    or "dir" in table.columns else SCHEMA, guessed)
    poses, modes = v["pose"], v["mode"]
    q = v["q"]
    check_same_pose(table, poses, q)
    check_positive(table, modes, "mode", "mode number")
    has_shapes = _check_shape_columns(table, v)
    if has_shapes:
        check_unique(table, [poses, modes, v["node"], v["dir"]], "node",
                     lambda i: f"DOF {v['node'][i]}{v['dir'][i]} of mode {modes[i]} of pose "
                               f"'{poses[i]}'")
    else:
        check_unique(table, [poses, modes], "mode",
                     lambda i: f"mode {modes[i]} of pose '{poses[i]}'")
    check_positive(table, v["freq"], "freq", "natural frequency")
    if "damping_ratio" in v:
        zeta = v["damping_ratio"]
        check_positive(table, zeta, "damping_ratio", "damping ratio", strict=False)
        bad = np.flatnonzero(zeta >= 1)
        if bad.size:
            raise table.error(bad[0], "damping_ratio", "damping ratio must be below 1 (a "
                              f"fraction of critical damping), got "
                              f"{table.text(bad[0], 'damping_ratio')}")
    check_limits(table, q, limits)
    if has_shapes:
        return _shape_data(table, v, q)
    return ModalData(poses=poses, q=q, modes=modes, freq_hz=v["freq"],
                     damping_ratio=v.get("damping_ratio"))


def _check_shape_columns(table: Table, v: dict) -> bool:
    """Whether the file holds shapes; raises when only some shape columns are there."""
    present = [b for b in (*_SHAPE, "phi_im") if b in v]
    if not present:
        return False
    missing = [b for b in _SHAPE if b not in v]
    if missing:
        raise table.error(None, None, f"mode shapes need the columns node, dir and phi; "
                          f"'{table.columns[present[0]].name}' is given without "
                          f"{', '.join(repr(m) for m in missing)}")
    return True


def _shape_data(table: Table, v: dict, q: np.ndarray) -> ShapeData:
    """Long rows (pose, mode, DOF) -> one row per (pose, mode) with its shape vector."""
    poses, modes = v["pose"], v["mode"]
    key = np.char.add(np.char.add(poses, "\x00"), modes.astype(str))
    _, first, inv = np.unique(key, return_index=True, return_inverse=True)
    order = np.argsort(first)  # modes in file order
    rank = np.argsort(order)[inv.ravel()]
    dofs = np.char.add(v["node"].astype(str), v["dir"])
    dof_names, dof_first, dof_of = np.unique(dofs, return_index=True, return_inverse=True)
    dof_order = np.argsort(dof_first)
    col = np.argsort(dof_order)[dof_of.ravel()]
    n, m = len(first), len(dof_names)
    counts = np.bincount(rank, minlength=n)
    if np.any(counts != m):
        r = int(np.flatnonzero(counts != m)[0])
        i = int(first[order[r]])
        raise table.error(i, "node", f"mode {modes[i]} of pose '{poses[i]}' lists "
                          f"{counts[r]} DOFs; every mode must list the same {m} DOFs")
    for base, what in (("freq", "frequency"), ("damping_ratio", "damping ratio")):
        if base not in v:
            continue
        head = v[base][first[order]][rank]
        bad = np.flatnonzero(head != v[base])
        if bad.size:
            raise table.error(bad[0], base, f"the {what} of mode {modes[bad[0]]} of pose "
                              f"'{poses[bad[0]]}' differs from its first row")
    phi = v["phi"] + 1j * v["phi_im"] if "phi_im" in v else v["phi"]
    shapes = np.zeros((n, m), dtype=phi.dtype)
    shapes[rank, col] = phi
    rows = first[order]
    zeta = v.get("damping_ratio")
    first_dof = dof_first[dof_order]
    return ShapeData(poses=poses[rows], q=q[rows], modes=modes[rows], freq_hz=v["freq"][rows],
                     damping_ratio=None if zeta is None else zeta[rows],
                     nodes=v["node"][first_dof], dirs=v["dir"][first_dof], shapes=shapes)


def read(path: PathType, limits: ArrayLike | None = None) -> ModalData:
    """Read a modal measurement file."""
    return from_table(read_table(path, SHAPES_SCHEMA.vocabulary), limits)


def values(data: ModalData) -> dict[str, np.ndarray | None]:
    """Column base -> values in SI, one row per mode (per DOF for a ``ShapeData``)."""
    rows, extra = np.arange(len(data.poses)), {}
    if isinstance(data, ShapeData):
        m = data.n_dofs
        rows = np.repeat(rows, m)
        phi = data.shapes.ravel()
        extra = {"node": np.tile(data.nodes, len(data.poses)),
                 "dir": np.tile(data.dirs, len(data.poses)), "phi": phi.real,
                 "phi_im": phi.imag if np.iscomplexobj(phi) else None}
    zeta = data.damping_ratio
    out = {"pose": data.poses[rows], "mode": data.modes[rows], "freq": data.freq_hz[rows],
           "damping_ratio": None if zeta is None else zeta[rows], **extra}
    out.update({f"q{j + 1}": data.q[rows, j] for j in range(6)})
    return out


def write(path: PathType, data: ModalData, comments=()) -> Path:
    """Write ``data`` in canonical units (deg, Hz), atomically; a
    :class:`~flexarm.validation.data.shape_data.ShapeData` as one row per DOF."""
    return write_table(path, SHAPES_SCHEMA, values(data), comments)


def to_dataframe(data: ModalData):
    """``pandas.DataFrame`` with the columns and units :func:`write` writes."""
    return table_frame(SHAPES_SCHEMA, values(data))
