"""The virtual lab runs a program: the measured path of a robot with hidden effects.

The same idea as the static virtual lab (:mod:`flexarm.validation.lab.virtual_lab`),
applied along a path: the "real" robot is a :class:`~.loaded.LoadedArm` with effects the
model does not know (stiffness errors, a backlash, ...), it runs the program under the
process force (:func:`~.runs.run_program`: the force where the tool is, the laws along
the path's torque history, gravity), and a laser tracker reads the tool position with
independent noise.  :func:`measure_program` returns one :class:`~.runs.PathRun` per
procedure, measured against the *programmed* path of a reference program (the original,
when the measured program is its compensated version), and the readings as
:class:`~flexarm.validation.data.measurements.PathData` (the path CSV ``circle
--measured`` reads), with the samples where the hidden laws jump.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...fe.typing import PathType
from ...robot.formats.rapid import read_rapid
from ...validation.data.measurements import PathData
from ...validation.tolerances import tol as validation_tol
from .forces import ForceSpec, path_wrenches
from .limits import law_jumps
from .loaded import LoadedArm
from .program import program_paths
from .runs import PathRun, path_deviation, run_program
from .workflow import procedure_pivot

__all__ = ["LabRun", "measure_program"]


@dataclass(frozen=True, eq=False)
class LabRun:
    """Measured runs of a program, one per procedure.

    Attributes
    ----------
    runs : tuple of PathRun
        Measured tool path against the programmed one; ``is_jump`` marks the motions
        where a hidden law jumps.
    data : tuple of PathData
        The readings per procedure (positions [m], the force magnitude [N]).
    """

    runs: tuple[PathRun, ...]
    data: tuple[PathData, ...]

    def run(self, name: str) -> PathRun:
        """The run of procedure ``name``."""
        return next(r for r in self.runs if r.name.lower() == name.lower())


def measure_program(truth: LoadedArm, robot, program: PathType, force: ForceSpec,
                    procs=None, pivots: dict | None = None, reference: PathType | None = None,
                    noise: float = validation_tol.tracker_sigma, seed: int = 0,
                    tool=None, step_mm: float = 2.0) -> LabRun:
    """Run ``program`` on the lab's arm ``truth`` and read the tool path with a tracker.

    Parameters
    ----------
    truth : LoadedArm
        The "real" robot (:func:`~.loaded.loaded_arm` with the hidden effects).
    robot : Robot
        Its kinematics and joint limits (what the controller uses).
    program : path
        The RAPID module run.
    force : ForceSpec
        The process force.
    procs : sequence of str, optional
        Procedures run (default: all).
    pivots : dict, optional
        Procedure -> ball-bar pivot (3,) [m] (the bar's fixed ball stays where it is when
        the program changes; see :attr:`~.result.CompensationResult.pivots`).
    reference : path, optional
        The programmed module the path is measured against (default: ``program``).
    noise : float
        Tracker noise per coordinate [m].
    seed : int

    Returns
    -------
    LabRun

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.effects import parse_effect
    >>> from flexarm.studies.compensation.forces import BallBar
    >>> from flexarm.studies.compensation.loaded import loaded_arm
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> robot = load_demo_robot()
    >>> truth = loaded_arm(robot, [parse_effect("backlash:j2=0.1mrad")])
    >>> lab = measure_program(truth, robot, THESIS_RAPID, BallBar(800.0), ["Path_30"],
    ...                       step_mm=10)
    >>> run = lab.run("Path_30")
    >>> bool(1e-3 < run.rms() < 3e-3), bool(run.is_jump.any())  # mm, no reversal of joint 2
    (True, False)
    """
    module = read_rapid(program)
    pps = program_paths(robot, module, procs, tool, step_mm)
    names = [pp.name for pp in pps]
    refs = pps if reference is None else program_paths(robot, read_rapid(reference), names,
                                                       tool, step_mm)
    rng = np.random.default_rng(seed)
    runs, data = [], []
    for pp, ref in zip(pps, refs, strict=True):
        pivot = (pivots or {}).get(pp.name)
        if pivot is None:
            pivot = procedure_pivot(force, read_rapid(reference or program), pp.name)
        jumps = law_jumps(truth, pp, path_wrenches(force, pp, pivot=pivot))
        is_jump = np.isin(pp.path.segments, [j.motion for j in jumps])
        run = run_program(truth, pp, force, pivot, reference=ref, is_jump=is_jump)
        points = run.points + noise * rng.standard_normal(run.points.shape)
        run = replace(run, points=points, deviation=path_deviation(points, ref.points))
        magnitude = np.linalg.norm(path_wrenches(force, pp, pivot=pivot)[:, :3], axis=1)
        runs.append(run)
        data.append(PathData(steps=np.arange(len(points)), points=points, force=magnitude))
    return LabRun(tuple(runs), tuple(data))
