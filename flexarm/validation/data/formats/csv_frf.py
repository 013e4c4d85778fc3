"""Receptances per pose: ``pose, q1_deg … q6_deg, input, output, freq_Hz, re_m_per_N,
im_m_per_N``.

``input`` (force) and ``output`` (displacement) are TCP directions ``x``, ``y`` or
``z`` of the base frame.  Checked on reading: every row of a pose has the same joint
angles, ``freq`` ≥ 0, each (pose, input, output, freq) appears once, joint angles
inside ``limits`` when given.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ....fe.typing import ArrayLike, PathType
from ..measurements import FrfData
from ._checks import check_limits, check_positive, check_same_pose, check_unique
from ._table import Field, Schema, Table, joints, read_table, table_frame, write_table

__all__ = ["SCHEMA", "DATA", "from_table", "read", "write", "values", "to_dataframe"]

SCHEMA = Schema("frf", (
    Field("pose", "label"), *joints(), Field("input", "direction"),
    Field("output", "direction"), Field("freq", "real", "frequency", "Hz"),
    Field("re", "real", "receptance", "m_per_N"), Field("im", "real", "receptance", "m_per_N"),
), noun="an FRF file")
DATA = FrfData


def from_table(table: Table, limits: ArrayLike | None = None, guessed: bool = False
               ) -> FrfData:
    """Check and convert a read table into :class:`FrfData`."""
    v = table.parse(SCHEMA, guessed)
    poses, freq = v["pose"], v["freq"]
    q = np.column_stack([v[f"q{j}"] for j in range(1, 7)])
    check_same_pose(table, poses, q)
    check_positive(table, freq, "freq", "frequency", strict=False)
    check_unique(table, [poses, v["input"], v["output"], freq], "freq",
                 lambda i: f"frequency {table.text(i, 'freq')} of pose '{poses[i]}', input "
                           f"{v['input'][i]}, output {v['output'][i]}")
    check_limits(table, q, limits)
    return FrfData(poses=poses, q=q, inputs=v["input"], outputs=v["output"], freq_hz=freq,
                   receptance=v["re"] + 1j * v["im"])


def read(path: PathType, limits: ArrayLike | None = None) -> FrfData:
    """Read an FRF measurement file."""
    return from_table(read_table(path, SCHEMA.vocabulary), limits)


def values(data: FrfData) -> dict[str, np.ndarray]:
    """Column base -> (n,) values in SI."""
    out = {"pose": data.poses, "input": data.inputs, "output": data.outputs,
           "freq": data.freq_hz, "re": data.receptance.real, "im": data.receptance.imag}
    out.update({f"q{j + 1}": data.q[:, j] for j in range(6)})
    return out


def write(path: PathType, data: FrfData, comments=()) -> Path:
    """Write ``data`` in canonical units (deg, Hz, m/N), atomically."""
    return write_table(path, SCHEMA, values(data), comments)


def to_dataframe(data: FrfData):
    """``pandas.DataFrame`` with the columns and units :func:`write` writes."""
    return table_frame(SCHEMA, values(data))
