"""Programs in and out: what the arm runs, read from a RAPID module, a KUKA KRL program or
a CSV of poses, and the compensated program written as RAPID, KUKA KRL or a CSV of poses.

Modules: :mod:`.program_path` (procedures as the arm runs them: sampled path and joint
angles), :mod:`.krl_in` (a KRL ``.src``/``.dat`` pair as a RAPID module), :mod:`.path_in`
(a CSV of poses as a RAPID module, and :func:`read_program`, the one reader of a program
file for ``compensate``, ``lab``, ``compare`` and ``history``),
:mod:`.rapid_out` (rewriting only the robtargets of a module's text), :mod:`.densify`
(splitting long motions) and :mod:`.program_out` (the program for other controllers, all
files or none).

It may import :mod:`flexarm.studies.compensation.solve` (the batched IK), the layers
below :mod:`flexarm.studies` and :mod:`flexarm.studies.tolerances`, and its own modules
in the order of the sub-layer table (``tests/test_layers.py``); never the result, the
workflow or the lab.
"""

from .path_in import read_program
from .program_out import program_format, write_program
from .program_path import ProgramPath, program_paths

__all__ = ["ProgramPath", "program_format", "program_paths", "read_program", "write_program"]
