"""Loaded path (circle) tests: ``step, x_mm, y_mm, z_mm, f_N``.

One row per tracker reading: TCP position in the base frame and the magnitude of the
bar force.  Checked on reading: ``step`` increases strictly.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ....fe.typing import ArrayLike, PathType
from ..measurements import PathData
from ._checks import check_increasing
from ._table import Field, Schema, Table, read_table, table_frame, vector, write_table

__all__ = ["SCHEMA", "DATA", "from_table", "read", "write", "values", "to_dataframe"]

SCHEMA = Schema("path", (
    Field("step", "int"), *vector("", "length", "mm"), Field("f", "real", "force", "N"),
))
DATA = PathData


def from_table(table: Table, limits: ArrayLike | None = None, guessed: bool = False
               ) -> PathData:
    """Check and convert a read table into :class:`PathData` (``limits`` unused)."""
    v = table.parse(SCHEMA, guessed)
    check_increasing(table, None, v["step"])
    return PathData(steps=v["step"], points=v["xyz"],
                    force=v["f"])


def read(path: PathType, limits: ArrayLike | None = None) -> PathData:
    """Read a path measurement file."""
    return from_table(read_table(path, SCHEMA.vocabulary), limits)


def values(data: PathData) -> dict[str, np.ndarray]:
    """Column base -> (n,) values in SI."""
    out = {"step": data.steps, "f": data.force}
    out.update({c: data.points[:, k] for k, c in enumerate("xyz")})
    return out


def write(path: PathType, data: PathData, comments=()) -> Path:
    """Write ``data`` in canonical units (mm, N), atomically."""
    return write_table(path, SCHEMA, values(data), comments)


def to_dataframe(data: PathData):
    """``pandas.DataFrame`` with the columns and units :func:`write` writes."""
    return table_frame(SCHEMA, values(data))
