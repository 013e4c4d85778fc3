"""Static load-deflection series: ``series, step, q1_deg … q6_deg, fx_N … dz_mm``.

Columns (any accepted unit suffix; canonical units shown)::

    series, step, q1_deg … q6_deg, fx_N, fy_N, fz_N, dx_mm, dy_mm, dz_mm
    optional: mx_Nm, my_Nm, mz_Nm, rx_mrad, ry_mrad, rz_mrad, sigma_mm

Rules, checked on reading:

- the rows of a series are contiguous and its ``step`` increases strictly, in
  measurement order (load/unload order is kept, it carries hysteresis);
- the first row of a series (its smallest step) is the **reference reading**: every
  displacement is relative to it, so its ``dx, dy, dz`` (and ``rx, ry, rz``) must be
  exactly 0.  A nonzero value means absolute positions or a shifted reference, which
  the analysis would otherwise mistake for an effect;
- a series holds one pose: its joint angles are those of its first row.  A series
  whose angles change at most of its steps (more than
  :attr:`~flexarm.validation.tolerances.Tolerances.moving_series_share`) is a path
  measured under load (the loaded circle in this schema) and keeps them; one that
  changes at a few steps only was moved in the middle of a load series, and is refused;
- ``sigma`` > 0; joint angles inside ``limits`` when given.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ....fe.typing import ArrayLike, PathType
from ...tolerances import tol
from ..measurements import StaticData, first_rows
from ._checks import (
    check_contiguous,
    check_increasing,
    check_limits,
    check_positive,
    check_same_pose,
)
from ._table import Field, Schema, Table, joints, read_table, table_frame, vector, write_table

__all__ = ["SCHEMA", "DATA", "from_table", "read", "write", "values", "to_dataframe"]

SCHEMA = Schema("static", (
    Field("series", "label"), Field("step", "int"), *joints(),
    *vector("f", "force", "N"), *vector("d", "length", "mm"),
    *vector("m", "moment", "Nm", required=False), *vector("r", "angle", "mrad", required=False),
    Field("sigma", "real", "length", "mm", required=False),
))
DATA = StaticData


def _stack(values: dict, prefix: str) -> np.ndarray | None:
    if prefix + "x" not in values:
        return None
    return values[prefix] if prefix in values else np.column_stack(
        [values[prefix + c] for c in "xyz"])


def from_table(table: Table, limits: ArrayLike | None = None, guessed: bool = False
               ) -> StaticData:
    """Check and convert a read table into :class:`StaticData`."""
    v = table.parse(SCHEMA, guessed)
    series, steps = v["series"], v["step"]
    check_contiguous(table, series, "series", "series")
    check_increasing(table, series, steps, "series")
    q = v["q"]
    check_same_pose(table, series, q, "series", lambda i, j, first: (
        f"{table.text(i, f'q{j + 1}')} instead of {table.text(first, f'q{j + 1}')}: a load "
        "series holds one pose; was the robot moved?"), _moving(series, q))
    disp, rot = _stack(v, "d"), _stack(v, "r")
    starts = first_rows(series)
    for prefix, what in (("d", "displacement"), ("r", "rotation")):
        if prefix + "x" not in v:
            continue
        bad = np.argwhere(_stack(v, prefix)[starts] != 0)
        if bad.size:
            i, base = starts[bad[0, 0]], prefix + "xyz"[bad[0, 1]]
            raise table.error(i, base, f"the first row of series '{series[i]}' (step "
                              f"{steps[i]}) is its reference reading, so its {what} must be "
                              f"0, got {table.text(i, base)}")
    if "sigma" in v:
        check_positive(table, v["sigma"], "sigma", "sigma")
    check_limits(table, q, limits)
    return StaticData(series=series, steps=steps, q=q, force=_stack(v, "f"), disp=disp,
                      moment=_stack(v, "m"), rot=rot, sigma=v.get("sigma"))


def _moving(series: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(n,) bool: rows of the series whose joint angles change at more than
    ``tol.moving_series_share`` of their steps (paths; the rows of a series are
    contiguous)."""
    starts = first_rows(series)
    lengths = np.diff(np.r_[starts, len(series)])
    changed = np.r_[False, np.any(q[1:] != q[:-1], axis=1)]
    changed[starts] = False
    moves = np.add.reduceat(changed.astype(np.int64), starts) if len(starts) else starts
    return np.repeat(moves > tol.moving_series_share * (lengths - 1), lengths)


def read(path: PathType, limits: ArrayLike | None = None) -> StaticData:
    """Read a static measurement file (see the module docstring for the rules)."""
    return from_table(read_table(path, SCHEMA.vocabulary), limits)


def values(data: StaticData) -> dict[str, np.ndarray | None]:
    """Column base -> (n,) values in SI (None: optional column absent)."""
    out = {"series": data.series, "step": data.steps, "sigma": data.sigma}
    out.update({f"q{j + 1}": data.q[:, j] for j in range(6)})
    for prefix, arr in (("f", data.force), ("d", data.disp), ("m", data.moment),
                        ("r", data.rot)):
        out.update({prefix + c: None if arr is None else arr[:, k]
                    for k, c in enumerate("xyz")})
    return out


def write(path: PathType, data: StaticData, comments=()) -> Path:
    """Write ``data`` in canonical units (mm, N, deg, N m, mrad), atomically."""
    return write_table(path, SCHEMA, values(data), comments)


def to_dataframe(data: StaticData):
    """``pandas.DataFrame`` with the columns and units :func:`write` writes."""
    return table_frame(SCHEMA, values(data))
