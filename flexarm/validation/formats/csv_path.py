"""Loaded path (circle) tests: ``step, x_mm, y_mm, z_mm, f_N``.

One row per tracker reading: TCP position in the base frame and the magnitude of the
bar force.  Checked on reading: ``step`` increases strictly.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.typing import ArrayLike, PathType
from ..measurements import PathData
from ._checks import check_increasing
from ._table import Field, Schema, Table, read_table, vector, write_table

__all__ = ["SCHEMA", "DATA", "from_table", "read", "write"]

SCHEMA = Schema("path", (
    Field("step", "int"), *vector("", "length", "mm"), Field("f", "real", "force", "N"),
))
DATA = PathData


def from_table(table: Table, limits: ArrayLike | None = None, guessed: bool = False
               ) -> PathData:
    """Check and convert a read table into :class:`PathData` (``limits`` unused)."""
    v = table.parse(SCHEMA, guessed)
    check_increasing(table, None, v["step"])
    return PathData(steps=v["step"], points=np.column_stack([v["x"], v["y"], v["z"]]),
                    force=v["f"])


def read(path: PathType, limits: ArrayLike | None = None) -> PathData:
    """Read a path measurement file."""
    return from_table(read_table(path, SCHEMA.vocabulary), limits)


def write(path: PathType, data: PathData, comments=()) -> Path:
    """Write ``data`` in canonical units (mm, N), atomically."""
    values = {"step": data.steps, "f": data.force}
    values.update({c: data.points[:, k] for k, c in enumerate("xyz")})
    return write_table(path, SCHEMA, values, comments)
