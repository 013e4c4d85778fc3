"""Validation layer: measurements, their comparison with the model, and the diagnosis of
the physical effect the model misses.

Measurement files are CSV with one header row and a unit suffix on every physical
column; ``#`` lines are comments.  :func:`read_measurements` recognises the kind
(static, modal, FRF, path) from the columns and returns a frozen dataclass of SI
arrays; errors are :class:`MeasurementFileError` (a ``ReadError``) naming file, line
and column.  The jobs: :func:`run_lab` (virtual lab data with hidden effects),
:func:`compare` (model vs data: errors, chi^2_red, plots) and :func:`run_diagnosis`
(fit, rank candidate effects, accept, repeat), on the models of
:func:`validation_models`.

The sub-packages, each importing only those above it in this list:

- ``tolerances``, ``models``: the rules of the diagnosis and the models it works on;
- :mod:`~flexarm.validation.data`: measurement sets, their files, units and points;
- :mod:`~flexarm.validation.static`: the GLS fit, candidates, residual structure, misfit;
- :mod:`~flexarm.validation.dynamic`: modal model, pairing, EMA, MAC and shapes, damping;
- :mod:`~flexarm.validation.lab`, :mod:`~flexarm.validation.planning`,
  :mod:`~flexarm.validation.diagnosis` (siblings): the virtual lab, test planning, the
  diagnosis search and its history;
- ``workflow``: the functions the command line calls.
"""


from .data import formats, units
from .data.formats import (
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
from .data.measurements import DIRECTIONS, FrfData, ModalData, PathData, StaticData
from .data.units import QUANTITIES, accepted_units, parse_quantity, si_factor
from .lab.virtual_lab import LabResult, run_lab
from .models import ValidationModels, ValidationOptions, validation_models
from .workflow import DiagnosisRun, compare, run_diagnosis

__all__ = [
    "StaticData", "ModalData", "FrfData", "PathData", "DIRECTIONS",
    "read_measurements", "read_static", "read_modal", "read_frf", "read_path",
    "write_measurements", "write_static", "write_modal", "write_frf", "write_path",
    "MeasurementFileError", "example_path",
    "QUANTITIES", "accepted_units", "si_factor", "parse_quantity",
    "formats", "units",
    "run_lab", "LabResult", "compare", "run_diagnosis", "DiagnosisRun",
    "validation_models", "ValidationModels", "ValidationOptions",
]
