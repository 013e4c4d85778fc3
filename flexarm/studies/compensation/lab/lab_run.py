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

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ....assembly.arm import ArmSpec
from ....fe.files import atomic_files
from ....fe.typing import PathType
from ....validation.data.formats import write_path
from ....validation.data.measurements import PathData
from ....validation.tolerances import tol as validation_tol
from ..program.path_in import read_program
from ..program.program_path import program_paths
from ..solve.forces import ForceSpec, parse_force, path_wrenches
from ..solve.limits import law_jumps
from ..solve.loaded import LoadedArm, loaded_arm
from ..solve.runs import PathRun, path_deviation, run_program
from ..workflow import procedure_pivot

__all__ = ["LabRun", "measure_program", "lab_program"]


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
    about : tuple of str
        What ran (program, reference, force, hidden effects, noise): the files' comments.
    """

    runs: tuple[PathRun, ...]
    data: tuple[PathData, ...]
    about: tuple[str, ...] = ()

    def run(self, name: str) -> PathRun:
        """The run of procedure ``name``."""
        return next(r for r in self.runs if r.name.lower() == name.lower())

    def text(self) -> str:
        """What the ``lab --program`` command prints (mm)."""
        lines = list(self.about)
        for r in self.runs:
            what = "radial deviation from the programmed circle" if r.circle is not None \
                else "distance from the programmed path"
            lines.append(f"  {r.name:12s} {len(r.points)} readings: RMS {what} "
                         f"{r.rms() * 1e3:.4f} mm, peak {r.peak * 1e3:.4f} mm")
            if r.is_jump is not None and r.is_jump.any():
                lines.append(f"  {'':12s} a hidden joint law jumps on {r.is_jump.mean():.0%} "
                             f"of the readings; RMS elsewhere {r.rms(~r.is_jump) * 1e3:.4f} mm")
        return "\n".join(lines)

    def paths(self, path: PathType) -> list[Path]:
        """The files :meth:`write` writes: ``path`` for one procedure, else
        ``<stem>_<procedure><suffix>`` for each."""
        path = Path(path)
        if len(self.runs) == 1:
            return [path]
        return [path.with_name(f"{path.stem}_{r.name}{path.suffix}") for r in self.runs]

    def write(self, path: PathType) -> list[Path]:
        """The readings as path CSVs (``step, x_mm, y_mm, z_mm, f_N``, what ``circle
        --measured``, ``compare --program`` and ``history`` read; a ``# procedure:``
        comment names the procedure), all or none of them
        (:func:`~flexarm.fe.files.atomic_files`); returns the paths."""
        files = self.paths(path)
        with atomic_files(*files) as tmps:
            for tmp, d, r in zip(tmps, self.data, self.runs, strict=True):
                write_path(tmp, d, [*self.about, f"procedure: {r.name}"])
        return files


def measure_program(truth: LoadedArm, robot, program: PathType, force: ForceSpec,
                    procs=None, pivots: dict | None = None, reference: PathType | None = None,
                    noise: float = validation_tol.tracker_sigma, seed: int = 0,
                    tool=None, step_mm: float = 2.0, orientation=None,
                    krl_config: PathType | None = None) -> LabRun:
    """Run ``program`` on the lab's arm ``truth`` and read the tool path with a tracker.

    Parameters
    ----------
    truth : LoadedArm
        The "real" robot (:func:`~.loaded.loaded_arm` with the hidden effects).
    robot : Robot
        Its kinematics and joint limits (what the controller uses).
    program : path
        The program run: a RAPID module or a CSV of poses
        (:func:`~.path_in.read_program`).
    force : ForceSpec
        The process force.
    procs : sequence of str, optional
        Procedures run (default: all).
    pivots : dict, optional
        Procedure -> ball-bar pivot (3,) [m] (the bar's fixed ball stays where it is when
        the program changes; see :attr:`~.result.CompensationResult.pivots`).
    reference : path, optional
        The program the path is measured against (default: ``program``), a RAPID module
        or a CSV of poses.
    noise : float
        Tracker noise per coordinate [m].
    seed : int
    tool, step_mm, orientation, krl_config
        As :func:`lab_program` takes them.

    Returns
    -------
    LabRun

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.effects import parse_effect
    >>> from flexarm.studies.compensation.solve.forces import BallBar
    >>> from flexarm.studies.compensation.solve.loaded import loaded_arm
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> robot = load_demo_robot()
    >>> truth = loaded_arm(robot, [parse_effect("backlash:j2=0.1mrad")])
    >>> lab = measure_program(truth, robot, THESIS_RAPID, BallBar(800.0), ["Path_30"],
    ...                       step_mm=10)
    >>> run = lab.run("Path_30")
    >>> bool(1e-3 < run.rms() < 3e-3), bool(run.is_jump.any())  # mm, no reversal of joint 2
    (True, False)
    """
    module = read_program(program, robot, tool, orientation, krl_config)[2]
    ref_module = module if reference is None else \
        read_program(reference, robot, tool, orientation, krl_config)[2]
    pps = program_paths(robot, module, procs, tool, step_mm)
    names = [pp.name for pp in pps]
    refs = pps if reference is None else program_paths(robot, ref_module, names, tool,
                                                       step_mm)
    rng = np.random.default_rng(seed)
    runs, data = [], []
    for pp, ref in zip(pps, refs, strict=True):
        pivot = (pivots or {}).get(pp.name)
        if pivot is None:
            pivot = procedure_pivot(force, ref_module, pp.name)
        jumps = law_jumps(truth, pp, path_wrenches(force, pp, pivot=pivot))
        is_jump = np.isin(pp.path.segments, [j.motion for j in jumps])
        run = run_program(truth, pp, force, pivot, reference=ref, is_jump=is_jump)
        points = run.points + noise * rng.standard_normal(run.points.shape)
        run = replace(run, points=points, deviation=path_deviation(points, ref.points))
        magnitude = np.linalg.norm(path_wrenches(force, pp, pivot=pivot)[:, :3], axis=1)
        runs.append(run)
        data.append(PathData(steps=np.arange(len(points)), points=points, force=magnitude))
    return LabRun(tuple(runs), tuple(data))


def lab_program(program: PathType, robot=None, effects: Sequence = (),
                force: ForceSpec | str | None = None, *, procs: Sequence[str] | None = None,
                reference: PathType | None = None,
                spec: ArmSpec = ArmSpec(),  # noqa: B008 (frozen dataclass)
                noise: float = validation_tol.tracker_sigma, seed: int = 0, pivot=None,
                tool=None, step_mm: float = 2.0, orientation=None,
                krl_config: PathType | None = None,
                progress: Callable[[str], None] | None = None) -> LabRun:
    """The virtual lab runs ``program`` on ``robot`` with the hidden ``effects``.

    Parameters
    ----------
    program : path
        The program run (e.g. the compensated one): a RAPID module or a CSV of poses
        (:func:`~.path_in.read_program`).
    robot : Robot, path or None
        The lab's robot as its controller knows it (None: the demo arm).
    effects : sequence of Effect
        What the model does not know (stiffness errors, backlash ...).
    force : ForceSpec or str
        The process force (:func:`~.forces.parse_force`).
    procs : sequence of str, optional
        Procedures run (default: all with motions).
    reference : path, optional
        The program the path is measured against (the original of a compensated
        program; default ``program``), a RAPID module or a CSV of poses.  The ball-bar
        pivot is fitted to it.
    spec : ArmSpec
        The lab arm's model.
    noise : float
        Tracker noise per coordinate [m].
    seed : int
    pivot : (3,) float, optional
        Ball-bar pivot [m].
    tool : None, "tool0", "robot" or (4, 4) float
        What the targets are read as.
    step_mm : float
        Reading step along the path [mm].
    orientation : (4,) float, optional
        Quaternion ``[w, x, y, z]`` of every pose of a CSV of positions only.
    krl_config : path, optional
        The controller's ``$config.dat`` of a KRL program (and reference).

    Returns
    -------
    LabRun

    Examples
    --------
    >>> from flexarm.robot.effects import parse_effect
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> lab = lab_program(THESIS_RAPID, None, [parse_effect("stiffness:j2=0.7")],
    ...                   "ballbar:800N", procs=["Path_30"], step_mm=10)
    >>> bool(1e-3 < lab.run("Path_30").rms() < 3e-3)
    True
    """
    from ....robot import load_robot
    from ....robot.description import Robot

    if force is None:
        raise ValueError("give the process force (e.g. ballbar:800N, tool:fz=300)")
    robot = robot if isinstance(robot, Robot) else load_robot(robot)
    force = parse_force(force, pivot) if isinstance(force, str) else force
    truth = loaded_arm(robot, effects, spec, progress=progress)
    lab = measure_program(truth, robot, program, force, procs, None, reference, noise, seed,
                          tool, step_mm, orientation, krl_config)
    hidden = "; ".join(f"{e.label} " + ",".join(f"{k}={v:g}" for k, v in e.params)
                       for e in effects) or "none"
    about = (f"flexarm lab: {Path(program).name} run under {force.label}, measured against "
             f"{Path(reference or program).name}",
             f"lab arm: {truth.label}; hidden effects: {hidden}; tracker noise "
             f"{noise * 1e6:g} um per coordinate, seed {seed}")
    return replace(lab, about=about)
