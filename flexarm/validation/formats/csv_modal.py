"""Natural frequencies per pose: ``pose, q1_deg … q6_deg, mode, freq_Hz``.

Optional ``damping_ratio`` (unitless, 0 ≤ ζ < 1).  Checked on reading: every row of
a pose has the same joint angles, each (pose, mode) appears once, ``mode`` ≥ 1,
``freq`` > 0, joint angles inside ``limits`` when given.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.typing import ArrayLike, PathType
from ..measurements import ModalData
from ._checks import check_limits, check_positive, check_same_pose, check_unique
from ._table import Field, Schema, Table, joints, read_table, write_table

__all__ = ["SCHEMA", "DATA", "from_table", "read", "write"]

SCHEMA = Schema("modal", (
    Field("pose", "label"), *joints(), Field("mode", "int"),
    Field("freq", "real", "frequency", "Hz"),
    Field("damping_ratio", "real", required=False),
))
DATA = ModalData


def from_table(table: Table, limits: ArrayLike | None = None, guessed: bool = False
               ) -> ModalData:
    """Check and convert a read table into :class:`ModalData`."""
    v = table.parse(SCHEMA, guessed)
    poses, modes = v["pose"], v["mode"]
    q = np.column_stack([v[f"q{j}"] for j in range(1, 7)])
    check_same_pose(table, poses, q)
    check_positive(table, modes, "mode", "mode number")
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
    return ModalData(poses=poses, q=q, modes=modes, freq_hz=v["freq"],
                     damping_ratio=v.get("damping_ratio"))


def read(path: PathType, limits: ArrayLike | None = None) -> ModalData:
    """Read a modal measurement file."""
    return from_table(read_table(path, SCHEMA.vocabulary), limits)


def write(path: PathType, data: ModalData, comments=()) -> Path:
    """Write ``data`` in canonical units (deg, Hz), atomically."""
    values = {"pose": data.poses, "mode": data.modes, "freq": data.freq_hz,
              "damping_ratio": data.damping_ratio}
    values.update({f"q{j + 1}": data.q[:, j] for j in range(6)})
    return write_table(path, SCHEMA, values, comments)
