"""The deflection and its correction: what the loaded arm does at a pose and how far a
target must move so that the loaded tool lands on it.

Modules: :mod:`.forces` (process force specs and the wrench at each target or path
sample), :mod:`.ik_batch` (small motions and batched Newton IK), :mod:`.path_ik` (joint
angles along a sampled path), :mod:`.sag` (gravity sag of many poses at once),
:mod:`.loaded` (the arm's deflection with gravity, joint laws, balancer and tool),
:mod:`.fixed_point` (the target correction), :mod:`.limits` (where a static shift cannot
help) and :mod:`.runs` (a loaded program's path and its deviation).

The lowest rank of :mod:`flexarm.studies.compensation`: it may import the layers below
:mod:`flexarm.studies`, :mod:`flexarm.studies.tolerances` and its own modules, in the
order of the sub-layer table (``tests/test_layers.py``), never the program files, the
result or the lab.
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
from .limits import LawJump, LimitHit, Limits, NearSingular
from .loaded import LoadedArm, deflection, loaded_arm
from .runs import PathRun, run_program

__all__ = [
    "BallBar", "ConstantWrench", "Correction", "ForceSpec", "LawJump", "LimitHit", "Limits",
    "LoadedArm", "NearSingular", "PathRun", "TargetWrenches", "correct_targets",
    "deflection", "loaded_arm", "parse_force", "read_target_wrenches", "run_program",
]
