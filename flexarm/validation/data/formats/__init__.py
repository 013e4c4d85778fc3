"""Measurement files: static series, modal, FRF and path tests as CSV.

The kind of a file is recognised from its columns (:func:`read_measurements`); the
per-kind functions read one kind only.  Writers use canonical units (mm, N, deg, N m,
mrad, Hz, m/N), start with a ``# flexarm`` comment line and replace the target
atomically.  Reading a written file gives identical arrays.
"""

from __future__ import annotations

import logging
from pathlib import Path

from ....fe.formats import FormatRegistry
from ....fe.typing import ArrayLike, PathType
from ..measurements import FrfData, ModalData, PathData, StaticData
from . import csv_frf, csv_modal, csv_path, csv_static, uff, uff_write
from ._registry import KINDS, detect_kind, register_kind, vocabulary
from ._table import MeasurementFileError, read_table
from .uff import UffOptions

__all__ = [
    "KINDS", "MeasurementFileError", "detect_kind", "register_kind",
    "read_measurements", "read_static", "read_modal", "read_frf", "read_path",
    "write_measurements", "write_static", "write_modal", "write_frf", "write_path",
    "example_path", "registry", "UffOptions",
]

log = logging.getLogger(__name__)

for _module in (csv_static, csv_modal, csv_frf, csv_path):
    register_kind(_module)

Measurements = StaticData | ModalData | FrfData | PathData
EXAMPLES = Path(__file__).resolve().parents[3] / "data" / "examples"


def read_measurements(path: PathType, limits: ArrayLike | None = None,
                      uff: UffOptions | None = None) -> Measurements:
    """Read a measurement file of any kind, recognised from its columns.

    Parameters
    ----------
    path : path-like
        CSV file (see :mod:`flexarm.validation` for the schemas).
    limits : (6, 2) float, optional
        Lower and upper joint limits [rad], e.g.
        ``np.column_stack([robot.lower, robot.upper])``; rows outside raise.
    uff : UffOptions, optional
        What a universal file from another tool does not say (its pose, ...).

    Returns
    -------
    StaticData or ModalData or FrfData or PathData
        Arrays in SI units.

    Raises
    ------
    MeasurementFileError
        (a :class:`~flexarm.fe.errors.ReadError`) naming file, line and column.

    Examples
    --------
    >>> data = read_measurements(example_path("static"))
    >>> type(data).__name__, data.n_series
    ('StaticData', 2)
    """
    fmt = registry.find(path)
    if fmt is not None and fmt.name == "uff":
        return registry.read(path, uff=uff)
    if fmt is not None and fmt.name != "csv":  # other extensions are read as CSV
        return registry.read(path)
    table = read_table(path, vocabulary())
    kind, guessed = detect_kind(table)
    data = KINDS[kind].from_table(table, limits, guessed)
    log.debug("read %s measurements from %s: %d rows", kind, path, data.n_rows)
    return data


def read_static(path: PathType, limits: ArrayLike | None = None) -> StaticData:
    """Read a static load-deflection file; see :mod:`.csv_static` for the rules.

    Examples
    --------
    >>> data = read_static(example_path("static"))
    >>> data.disp.shape, list(data.series_slices())
    ((10, 3), ['c1_y', 'c2_x'])
    """
    return csv_static.read(path, limits)


def read_modal(path: PathType, limits: ArrayLike | None = None,
               uff: UffOptions | None = None) -> ModalData:
    """Read a modal (natural frequency) file: a modal CSV, or a universal file with mode
    shapes (55 sets: frequencies, damping ratios and shapes, :class:`ShapeData`).

    Examples
    --------
    >>> read_modal(example_path("modal")).pose_labels()
    ['c1', 'c2']
    """
    fmt = registry.find(path)
    if fmt is not None and fmt.name == "uff":
        data = registry.read(path, uff=uff)
        if not isinstance(data, ModalData):
            raise MeasurementFileError(
                f"{path}: FRFs but no mode shapes (no 55 sets): identify the modes first, "
                f"flexarm ema {Path(path).name} -o modal.csv, and give that file")
        return data
    return csv_modal.read(path, limits)


def read_frf(path: PathType, limits: ArrayLike | None = None) -> FrfData:
    """Read an FRF (receptance) file.

    Examples
    --------
    >>> read_frf(example_path("frf")).receptance.dtype
    dtype('complex128')
    """
    return csv_frf.read(path, limits)


def read_path(path: PathType) -> PathData:
    """Read a loaded path (circle) test file.

    Examples
    --------
    >>> read_path(example_path("path")).points.shape
    (8, 3)
    """
    return csv_path.read(path)


def write_measurements(path: PathType, data: Measurements, comments=()) -> Path:
    """Write any measurement dataclass to ``path`` (atomic); returns the path.

    Parameters
    ----------
    path : path-like
        Target CSV file.
    data : StaticData or ModalData or FrfData or PathData
        What to write.
    comments : iterable of str
        Extra ``#`` lines after the title line (provenance, seeds, ...).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> data = read_measurements(example_path("modal"))
    >>> out = write_measurements(pathlib.Path(tempfile.mkdtemp()) / "m.csv", data)
    >>> read_measurements(out) == data
    True
    """
    for module in KINDS.values():
        if isinstance(data, module.DATA):
            return module.write(path, data, comments)
    raise ValueError(f"cannot write a {type(data).__name__} as measurements "
                     f"(expected one of {', '.join(m.DATA.__name__ for m in KINDS.values())})")


def _check_type(data, cls: type, name: str) -> None:
    if not isinstance(data, cls):
        raise ValueError(f"{name} needs a {cls.__name__}, got {type(data).__name__}")


def write_static(path: PathType, data: StaticData, comments=()) -> Path:
    """Write static series in mm, N, deg (N m, mrad), atomically; returns the path."""
    _check_type(data, StaticData, "write_static")
    return csv_static.write(path, data, comments)


def write_modal(path: PathType, data: ModalData, comments=()) -> Path:
    """Write natural frequencies in deg, Hz, atomically; returns the path."""
    _check_type(data, ModalData, "write_modal")
    return csv_modal.write(path, data, comments)


def write_frf(path: PathType, data: FrfData, comments=()) -> Path:
    """Write receptances in deg, Hz, m/N, atomically; returns the path."""
    _check_type(data, FrfData, "write_frf")
    return csv_frf.write(path, data, comments)


def write_path(path: PathType, data: PathData, comments=()) -> Path:
    """Write a path test in mm, N, atomically; returns the path."""
    _check_type(data, PathData, "write_path")
    return csv_path.write(path, data, comments)


#: Measurement files by extension: CSV (every kind, recognised by its columns) and
#: universal files (mode shapes and FRFs, :mod:`.uff`).
registry = FormatRegistry("measurement")
registry.register("csv", (".csv", ".txt"), read=read_measurements, write=write_measurements)
registry.register("uff", uff.EXTENSIONS, read=uff.read, write=uff_write.write)


def example_path(kind: str) -> Path:
    """Path of the shipped example file of ``kind`` (static, modal, frf or path).

    Examples
    --------
    >>> example_path("static").name
    'static_example.csv'
    """
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got '{kind}'")
    return EXAMPLES / f"{kind}_example.csv"
