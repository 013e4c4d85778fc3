"""Validation layer: measurement files and data sets (the first slice of the
compare/diagnose loop).

Measurement files are CSV with one header row and a unit suffix on every physical
column; ``#`` lines are comments.  :func:`read_measurements` recognises the kind
(static, modal, FRF, path) from the columns and returns a frozen dataclass of SI
arrays; errors are :class:`MeasurementFileError` (a ``ReadError``) naming file, line
and column.  Imports :mod:`flexarm.fe` only.
"""

from . import formats, units
from .formats import (
    MeasurementFileError,
    example_path,
    read_frf,
    read_measurements,
    read_modal,
    read_path,
    read_static,
    write_frf,
    write_measurements,
    write_modal,
    write_path,
    write_static,
)
from .measurements import DIRECTIONS, FrfData, ModalData, PathData, StaticData
from .units import QUANTITIES, accepted_units, parse_quantity, si_factor

__all__ = [
    "StaticData", "ModalData", "FrfData", "PathData", "DIRECTIONS",
    "read_measurements", "read_static", "read_modal", "read_frf", "read_path",
    "write_measurements", "write_static", "write_modal", "write_frf", "write_path",
    "MeasurementFileError", "example_path",
    "QUANTITIES", "accepted_units", "si_factor", "parse_quantity",
    "formats", "units",
]
