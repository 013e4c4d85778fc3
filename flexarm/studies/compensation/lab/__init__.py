"""The lab loop: a program run by the virtual lab, a measured path against its program,
and the loop's error history.

Modules: :mod:`.lab_run` (the virtual lab runs a program: the measured path of a robot
with hidden effects), :mod:`.measured` (a measured path against the programmed one,
no model involved) and :mod:`.history` (the error at each step of the loop).

The top rank of :mod:`flexarm.studies.compensation`: it may import every sibling
(:mod:`~flexarm.studies.compensation.solve`, :mod:`~flexarm.studies.compensation.program`,
:mod:`~flexarm.studies.compensation.plots`, :mod:`~flexarm.studies.compensation.workflow`),
the layers below :mod:`flexarm.studies` (:mod:`flexarm.validation` for the measurement
files) and its own modules in the order of the sub-layer table (``tests/test_layers.py``).
"""

from .history import PathHistory, path_history
from .lab_run import LabRun, lab_program, measure_program
from .measured import MeasuredPath, compare_path

__all__ = ["LabRun", "MeasuredPath", "PathHistory", "compare_path", "lab_program",
           "measure_program", "path_history"]
