"""Deflection-compensated robot programs: a RAPID program, a process force and an
(identified) robot model in, the program whose loaded tool lands on the programmed path
out, and the virtual lab that runs it.

Modules, each with one job: :mod:`.forces` (process force specs), :mod:`.ik_batch`
(small motions, batched Newton IK), :mod:`.program` (procedures as the arm runs them),
:mod:`.loaded` (the arm's deflection with gravity, joint laws, balancer and tool),
:mod:`.fixed_point` (the target correction), :mod:`.limits` (where a static shift cannot
help), :mod:`.densify` (splitting long motions), :mod:`.rapid_out` (writing only the
robtargets), :mod:`.runs` (a loaded program's path and deviation), :mod:`.result`,
:mod:`.plots`, :mod:`.workflow` (:func:`compensate`), :mod:`.program_out` (the program
as RAPID, KUKA KRL or a CSV of poses, all files or none), :mod:`.path_in` (a CSV of
poses as the program), :mod:`.lab` (the virtual lab running a program), :mod:`.measured`
(a measured path against the program) and :mod:`.history` (the loop's error history).

A member of the flat floor of :mod:`flexarm.studies`: it may import
:mod:`flexarm.studies.contact` and the layers below (:mod:`flexarm.validation` for the
measurement file formats).
"""

from .fixed_point import Correction, correct_targets
from .forces import (
    BallBar,
    ConstantWrench,
    ForceSpec,
    TargetWrenches,
    parse_force,
    read_target_wrenches,
)
from .history import PathHistory, path_history
from .lab import LabRun, lab_program, measure_program
from .limits import LawJump, LimitHit, Limits, NearSingular
from .loaded import LoadedArm, deflection, loaded_arm
from .measured import MeasuredPath, compare_path
from .program import ProgramPath, program_paths
from .program_out import program_format, write_program
from .result import CompensationResult, TargetShift
from .runs import PathRun, run_program
from .workflow import compensate

__all__ = [
    "BallBar", "CompensationResult", "ConstantWrench", "Correction", "ForceSpec", "LabRun",
    "LawJump", "LimitHit", "Limits", "LoadedArm", "MeasuredPath", "NearSingular",
    "PathHistory", "PathRun", "ProgramPath", "TargetShift", "TargetWrenches", "compare_path",
    "compensate", "correct_targets", "deflection", "lab_program", "loaded_arm",
    "measure_program", "parse_force", "path_history", "program_format", "program_paths",
    "read_target_wrenches", "run_program", "write_program",
]
