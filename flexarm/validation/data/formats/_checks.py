"""Checks of parsed measurement columns that several kinds share (vectorised).

Each check raises the :class:`~._table.MeasurementFileError` of the first offending
row in file order, naming its line and column.
"""

from __future__ import annotations

import numpy as np

from ....fe.typing import ArrayLike, FloatArray
from ..measurements import first_rows
from ..units import split_column
from ._table import Table

__all__ = ["check_contiguous", "check_increasing", "check_limits",
           "check_positive", "check_same_pose", "check_unique"]


def check_contiguous(table: Table, labels: np.ndarray, base: str, what: str) -> None:
    """The rows of each label (series) form one block."""
    starts = first_rows(labels)
    _, first, inverse = np.unique(labels[starts], return_index=True, return_inverse=True)
    again = np.flatnonzero(first[inverse] != np.arange(len(starts)))
    if again.size:
        row, earlier = starts[again[0]], starts[first[inverse[again[0]]]]
        raise table.error(row, base, f"{what} '{labels[row]}' continues here after other "
                          f"{what} (it started on line {table.lines[earlier]}); keep the rows "
                          f"of a {what} together")


def check_increasing(table: Table, labels: np.ndarray | None, steps: np.ndarray,
                     what: str = "series") -> None:
    """``steps`` increase strictly within each label (within the file if ``labels`` is None)."""
    same = np.ones(len(steps) - 1, dtype=bool) if labels is None else labels[1:] == labels[:-1]
    bad = np.flatnonzero(same & (steps[1:] <= steps[:-1]))
    if bad.size:
        i = bad[0] + 1
        owner = "" if labels is None else f" of {what} '{labels[i]}'"
        raise table.error(i, "step", f"step {steps[i]} does not follow step {steps[i - 1]}"
                          f"{owner} (steps must increase, in measurement order)")


def check_positive(table: Table, values: FloatArray, base: str, what: str,
                   strict: bool = True) -> None:
    """``values`` > 0 (``strict``) or >= 0."""
    bad = np.flatnonzero(values <= 0 if strict else values < 0)
    if bad.size:
        i = bad[0]
        rule = "positive" if strict else "zero or positive"
        raise table.error(i, base, f"{what} must be {rule}, got {table.text(i, base)}")


def _joint_mismatch(table: Table, rows_cols: np.ndarray, message) -> None:
    if rows_cols.size:
        i, j = (int(k) for k in rows_cols[0])
        raise table.error(i, f"q{j + 1}", message(i, j))


def check_limits(table: Table, q: FloatArray, limits: ArrayLike | None) -> None:
    """Joint angles ``q`` (n, 6) [rad] inside ``limits`` (6, 2) [rad], if given."""
    if limits is None:
        return
    limits = np.asarray(limits, dtype=np.float64)
    if limits.shape != (q.shape[1], 2):
        raise ValueError(f"limits must have shape ({q.shape[1]}, 2) [rad], got {limits.shape}")
    bad = np.argwhere((q < limits[:, 0]) | (q > limits[:, 1]))

    def message(i, j):
        column = table.columns[f"q{j + 1}"]
        unit = split_column(column.name)[1]
        lo, hi = (limits[j] / float(column.factor)).tolist()
        return (f"{table.text(i, f'q{j + 1}')} is outside the limits [{lo:g}, {hi:g}] {unit} "
                f"of joint {j + 1}")

    _joint_mismatch(table, bad, message)


def check_same_pose(table: Table, poses: np.ndarray, q: FloatArray, what: str = "pose",
                    rule=lambda i, j, first: "one pose, one set of angles",
                    exempt: np.ndarray | None = None) -> None:
    """Every row of a pose (or a series: ``what``) has the joint angles of its first row;
    rows where ``exempt`` (n,) is True are not checked.  ``rule(row, joint, first_row)``
    gives the parenthesis that ends the message."""
    _, first, inverse = np.unique(poses, return_index=True, return_inverse=True)
    origin = first[inverse]
    # a joint at a time: a million rows of six angles need no (n, 6) copy
    differs = np.zeros(q.shape, bool)
    for j in range(q.shape[1]):
        differs[:, j] = q[:, j] != q[origin, j]
    bad = np.argwhere(differs)
    if exempt is not None:
        bad = bad[~exempt[bad[:, 0]]]
    _joint_mismatch(table, bad, lambda i, j: (
        f"{what} '{poses[i]}' has other joint angles here than on line "
        f"{table.lines[origin[i]]} ({rule(i, j, int(origin[i]))})"))


def check_unique(table: Table, keys: list[np.ndarray], base: str, describe) -> None:
    """No two rows share all ``keys``; ``describe(row)`` names the repeated entry."""
    codes = np.column_stack([np.unique(k, return_inverse=True)[1] for k in keys])
    _, first, inverse = np.unique(codes, axis=0, return_index=True, return_inverse=True)
    origin = first[inverse.ravel()]
    bad = np.flatnonzero(origin != np.arange(len(origin)))
    if bad.size:
        i = bad[0]
        raise table.error(i, base, f"{describe(i)} is already given on line "
                          f"{table.lines[origin[i]]}")
