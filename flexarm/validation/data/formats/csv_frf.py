"""Receptances per pose: ``pose, q1_deg … q6_deg, input, output, freq_Hz, re_m_per_N,
im_m_per_N``.

``input`` (force) and ``output`` (displacement) are TCP directions ``x``, ``y`` or
``z`` of the base frame.  Checked on reading: every row of a pose has the same joint
angles, ``freq`` ≥ 0, each (pose, input, output, freq) appears once, joint angles
inside ``limits`` when given.  Comparing needs at least
:attr:`~flexarm.validation.tolerances.Tolerances.frf_min_lines` lines per (pose, input,
output) (:func:`check_lines`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ....fe.typing import ArrayLike, PathType
from ...tolerances import tol
from ..measurements import FrfData
from ._checks import check_limits, check_positive, check_same_pose, check_unique
from ._table import (
    Field,
    MeasurementFileError,
    Schema,
    Table,
    joints,
    read_table,
    table_frame,
    write_table,
)

__all__ = ["SCHEMA", "DATA", "from_table", "read", "write", "values", "to_dataframe",
           "check_lines"]

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
    q = v["q"]
    check_same_pose(table, poses, q)
    check_positive(table, freq, "freq", "frequency", strict=False)
    check_unique(table, [poses, v["input"], v["output"], freq], "freq",
                 lambda i: f"frequency {table.text(i, 'freq')} of pose '{poses[i]}', input "
                           f"{v['input'][i]}, output {v['output'][i]}")
    check_limits(table, q, limits)
    return FrfData(poses=poses, q=q, inputs=v["input"], outputs=v["output"], freq_hz=freq,
                   receptance=v["re"] + 1j * v["im"])


def check_lines(data: FrfData, source: PathType | None = None) -> None:
    """Every (pose, input, output) FRF of ``data`` has at least ``tol.frf_min_lines``
    frequency lines, as comparing peaks needs (reading does not ask it).

    Raises :class:`MeasurementFileError` naming ``source`` and, for a CSV file, the line
    of the short FRF's first row.

    Examples
    --------
    >>> import numpy as np
    >>> one = FrfData(poses=["c1"], q=np.zeros((1, 6)), inputs=["y"], outputs=["y"],
    ...               freq_hz=[10.0], receptance=[1e-6 + 0j])
    >>> check_lines(one, "shaker.uff")
    Traceback (most recent call last):
    ...
    flexarm.validation.data.formats._lines.MeasurementFileError: shaker.uff: the FRF of pose \
'c1', input y, output y has 1 frequency line; comparing FRFs needs at least 3 (a peak \
needs a line on each side)
    """
    keys = [data.poses, data.inputs, data.outputs]
    codes = np.column_stack([np.unique(k, return_inverse=True)[1] for k in keys])
    _, first, counts = np.unique(codes, axis=0, return_index=True, return_counts=True)
    short = np.flatnonzero(counts < tol.frf_min_lines)
    if not short.size:
        return
    g = short[np.argmin(first[short])]
    i, n = int(first[g]), int(counts[g])
    where, line = ("FRF data" if source is None else str(source)), None
    if source is not None and Path(source).suffix.lower() == ".csv":
        table = read_table(source, SCHEMA.vocabulary)  # the error path only: its line
        line = int(table.lines[i])
        where = f"{source}, line {line}, column '{table.columns['freq'].name}'"
    raise MeasurementFileError(
        f"{where}: the FRF of pose '{keys[0][i]}', input {keys[1][i]}, output {keys[2][i]} "
        f"has {n} frequency line{'s' if n != 1 else ''}; comparing FRFs needs at least "
        f"{tol.frf_min_lines} (a peak needs a line on each side)", str(source), line)


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
