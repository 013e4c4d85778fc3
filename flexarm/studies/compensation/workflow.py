"""``compensate``: a RAPID program, a process force and a robot model in, the corrected
program out.

:func:`compensate` reads the module, runs every chosen procedure through the loaded arm
(:mod:`.program_path`, :mod:`.loaded`), shifts each named robtarget by the fixed point of
:mod:`.fixed_point`, rewrites only those robtargets in the user's text
(:mod:`.rapid_out`), predicts the loaded path of the programmed and of the compensated
program (:mod:`.runs`) and names where a static shift cannot help (:mod:`.limits`).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ...assembly.arm import ArmSpec
from ...fe.typing import PathType
from ...robot.formats.rapid import RapidModule, RobTarget
from ...robot.ik_path import TOOL0, rapid_conf, target_frames
from ...robot.quaternions import quat_from_matrix
from ..contact.ball_bar import default_pivot
from ..tolerances import tol
from .program.densify import densify
from .program.path_in import read_program
from .program.program_path import ProgramPath, program_paths
from .program.rapid_out import module_of_text, rewrite_targets, written_pose
from .result import CompensationResult, TargetShift
from .solve.fixed_point import correct_targets
from .solve.forces import BallBar, ForceSpec, parse_force, path_wrenches, target_wrenches
from .solve.ik_batch import pose_errors
from .solve.limits import Limits, law_jumps, limit_hits, near_singular
from .solve.loaded import LoadedArm, law_rotations, loaded_arm
from .solve.runs import run_program

__all__ = ["compensate", "procedure_pivot"]

log = logging.getLogger(__name__)


def procedure_pivot(force: ForceSpec, module, name: str):
    """The ball-bar pivot (3,) [m] of procedure ``name`` (the force's own, else the module's
    default), or None for other forces.

    Examples
    --------
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> (procedure_pivot(BallBar(800.0), read_rapid(THESIS_RAPID), "Path_40") * 1e3).round(2)
    array([1333.34,   47.78,  588.13])
    """
    if not isinstance(force, BallBar):
        return None
    if force.pivot is not None:
        return np.asarray(force.pivot, dtype=float)
    return default_pivot(module, name)


def _correct(la: LoadedArm, pp: ProgramPath, force, pivot):
    """(correction of the named targets, law jumps) of one procedure."""
    w_path = path_wrenches(force, pp, pivot=pivot)
    rot = law_rotations(la, pp.q, w_path, pp.tool)[pp.target_samples]
    w = target_wrenches(force, pp, pivot)
    k = pp.is_named
    corr = correct_targets(la, pp.tool, pp.target_frames[k], pp.target_q[k], w[k], rot[k])
    return corr, law_jumps(la, pp, w_path)


def _first_uses(occurrences) -> tuple[dict, dict, dict]:
    """Per lower-case robtarget name: its first use ``(proc, frame, before, after)``, the
    largest distance [m] between the frames its uses ask for, and the procedures."""
    first: dict[str, tuple] = {}
    spread: dict[str, float] = {}
    users: dict[str, list[str]] = {}
    for name, proc, frame, before, after in occurrences:
        key = name.lower()
        users.setdefault(key, []).append(proc)
        if key not in first:
            first[key] = (proc, frame, before, after)
            spread[key] = 0.0
        else:
            gap = float(np.linalg.norm(frame[:3, 3] - first[key][1][:3, 3]))
            spread[key] = max(spread[key], gap)
    return first, spread, users


def _shifts(module, occurrences, skip) -> tuple[list[TargetShift], dict, list[str]]:
    """One :class:`TargetShift` per robtarget (its first use), the poses to write and notes."""
    first, spread, users = _first_uses(occurrences)
    targets = {k.lower(): t for k, t in module.targets.items()}
    keys = [k for k in first if k not in skip]
    if not keys:
        return [], {}, []
    old = [targets[k] for k in keys]
    F = np.array([first[k][1] for k in keys])
    quats = quat_from_matrix(F[:, :3, :3])
    quats *= np.where(np.einsum("ki,ki->k", quats, [t.quat for t in old]) < 0, -1.0, 1.0)[:, None]
    written = [written_pose(p, q) for p, q in zip(F[:, :3, 3] * 1e3, quats, strict=True)]
    pos = np.array([w[0] for w in written])
    quat = np.array([w[1] for w in written])
    shift = pose_errors(target_frames(np.array([t.pos_mm for t in old]),
                                      np.array([t.quat for t in old])),
                        target_frames(pos, quat))
    shifts, new, notes = [], {}, []
    for i, (k, t) in enumerate(zip(keys, old, strict=True)):
        proc, _frame, before, after = first[k]
        shifts.append(TargetShift(t.name, proc, t.pos_mm, pos[i], t.quat, quat[i], before,
                                  after, shift[i], spread[k]))
        new[t.name] = (pos[i], quat[i])
        if spread[k] > tol.shared_target_spread:
            notes.append(f"{t.name} is used by {', '.join(dict.fromkeys(users[k]))} with loads "
                         f"asking for shifts up to {spread[k] * 1e3:.4f} mm apart; written "
                         f"for {proc}")
    return shifts, new, notes


def _crossings(name: str, chain, module, targets, q) -> list[str]:
    """A note when compensated targets land across a quadrant boundary of their programmed
    configuration (kept as written: the branch is the same, a hair's breadth away)."""
    confs = {k.lower(): t.conf for k, t in module.targets.items()}
    want = np.array([confs[t.lower()] for t in targets]).reshape(-1, 4)
    moved = [t for t, c, w in zip(targets, rapid_conf(chain, q), want, strict=True)
             if np.any(c != w)]
    if not moved:
        return []
    shown = ", ".join(dict.fromkeys(moved[:3])) + (" ..." if len(moved) > 3 else "")
    return [f"{name}: {len(moved)} compensated targets ({shown}) sit across a quadrant "
            "boundary of their programmed configuration by a fraction of a degree; the "
            "configuration is kept as programmed (check ConfL/ConfJ on the controller)"]


def _joints(chain, pps) -> dict[str, tuple[np.ndarray, int]]:
    """Lower-case robtarget -> (joint angles [rad], ABB ``cfx``) at its first use in the
    program paths ``pps`` (what a controller's configuration data is derived from)."""
    out: dict[str, tuple[np.ndarray, int]] = {}
    for pp in pps:
        cfx = rapid_conf(chain, pp.target_q)[:, 3]
        for name, q, c, ok in zip(pp.targets, pp.target_q, cfx, pp.is_named, strict=True):
            if ok:
                out.setdefault(name.lower(), (q, int(c)))
    return out


def _with_targets(module: RapidModule, new: dict) -> RapidModule:
    """``module`` with the robtargets ``new`` (name -> (pos_mm, quat)) in its data and in
    every motion that uses them (what reading the rewritten text gives)."""
    poses = {k.lower(): v for k, v in new.items()}

    def swap(t):
        v = poses.get(t.name.lower()) if isinstance(t, RobTarget) else None
        return t if v is None else RobTarget(t.name, v[0], v[1], t.conf, t.extax)

    procs = {k: replace(p, motions=tuple(replace(m, targets=tuple(swap(t) for t in m.targets))
                                         for m in p.motions))
             for k, p in module.procedures.items()}
    return replace(module, targets={k: swap(t) for k, t in module.targets.items()},
                   procedures=procs)


def _per_procedure(la: LoadedArm, robot, module, pps, force):
    """Correct every procedure's named targets: (occurrences, limits, notes, pivots,
    iterations, lower-case names of targets left alone)."""
    occurrences, jumps, hits, singular, notes, pivots = [], [], [], [], [], {}
    iterations = 0
    skip: set[str] = set()
    for pp in pps:
        pivots[pp.name] = procedure_pivot(force, module, pp.name)
        corr, found = _correct(la, pp, force, pivots[pp.name])
        iterations = max(iterations, corr.iterations)
        jumps += found
        names = [t for t, ok in zip(pp.targets, pp.is_named, strict=True) if ok]
        notes += [f"{pp.name}: target '{t}' (line {pp.path.lines[m]}) is an expression, not "
                  "a robtarget of the module: not shifted"
                  for t, ok, m in zip(pp.targets, pp.is_named, pp.target_motions, strict=True)
                  if not ok]
        new_hits = limit_hits(pp.name, names, corr.q, corr.is_reached, robot.lower, robot.upper)
        hits += new_hits
        skip |= {h.target.lower() for h in new_hits}
        chain = replace(robot.chain, tool=pp.tool)
        singular += near_singular(pp.name, chain, names, corr.q,
                                  corr.q - pp.target_q[pp.is_named])
        occurrences += [(n, pp.name, corr.frames[i], corr.before[i], corr.after[i])
                        for i, n in enumerate(names)]
        notes += _crossings(pp.name, chain, module, names, corr.q)
    return (occurrences, Limits(tuple(jumps), tuple(hits), tuple(singular)), notes, pivots,
            iterations, skip)


def compensate(program: PathType, robot=None, force: ForceSpec | str | None = None, *,
               procs: Sequence[str] | None = None,
               spec: ArmSpec = ArmSpec(),  # noqa: B008 (frozen dataclass)
               effects: Sequence = (), tool=None, gravity: bool = True, pivot=None,
               step_mm: float = 2.0, split_mm: float | None = None, arm=None,
               orientation=None, krl_config: PathType | None = None,
               progress: Callable[[str], None] | None = None) -> CompensationResult:
    """Shift the robtargets of a RAPID program so that the loaded tool lands on the program.

    Parameters
    ----------
    program : path
        RAPID module (``.mod``), or a CSV of poses (``.csv``, read as a module by
        :func:`~.path_in.read_program`: positions, and a quaternion or angles per row).
    robot : Robot, path or None
        The robot (e.g. the file ``diagnose --apply`` wrote); None: the demo arm.
    force : ForceSpec or str
        The process force (:func:`~.forces.parse_force`: ``"ballbar:800N"``,
        ``"tool:fz=300"``, ``"base:fz=-200"``, ``"forces.csv"``).
    procs : sequence of str, optional
        Procedures to compensate (default: every procedure with motions).
    spec : ArmSpec
        Arm model (E-model by default, ``ArmSpec("cb")`` for flexible links).
    effects : sequence of Effect
        Effects on top of the robot file's.
    tool : None, "tool0", "robot" or (4, 4) float
        What the targets are read as (default: the instructions' tool).
    gravity : bool
        Compensate the gravity sag too (absolute accuracy); False: only the process
        load, relative to the unloaded run.
    pivot : (3,) float, optional
        Ball-bar pivot [m] (default: each procedure's, see :func:`procedure_pivot`).
    step_mm : float
        Path sampling step [mm] (torque history, limits, predicted paths).
    split_mm : float, optional
        Split every ``MoveL``/``MoveC`` longer than this [mm] into equal sub-motions
        through new robtargets first (:func:`~.densify.densify`), so that the
        compensated path follows a deflection that changes along a motion; None keeps
        the module's structure (only the robtargets change).
    arm : ArmModel, optional
        A model of ``robot`` already built.
    orientation : (4,) float, optional
        Quaternion ``[w, x, y, z]`` of every pose of a CSV that gives positions only.
    krl_config : path, optional
        The controller's ``$config.dat`` of a KRL program (``BAS (#TOOL, n)``; default:
        the one beside the ``.src``, if any).

    Returns
    -------
    CompensationResult

    Examples
    --------
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> res = compensate(THESIS_RAPID, force="ballbar:800N", procs=["Path_30"], step_mm=10)
    >>> [s.name for s in res.shifts]
    ['Target_70', 'Target_80', 'Target_90', 'Target_100', 'Target_110']
    >>> bool(res.runs_after[0].rms() < res.runs_before[0].rms() / 2)
    True
    """
    from ...robot import load_robot
    from ...robot.description import Robot

    if force is None:
        raise ValueError("give the process force (e.g. ballbar:800N, tool:fz=300)")
    robot = robot if isinstance(robot, Robot) else load_robot(robot)
    force = parse_force(force, pivot) if isinstance(force, str) else force
    if pivot is not None and isinstance(force, BallBar) and force.pivot is None:
        force = BallBar(force.force, force.pull, tuple(np.asarray(pivot, float)))
    text, encoding, module = read_program(program, robot, tool, orientation, krl_config)
    la = loaded_arm(robot, effects, spec, gravity, arm, progress=progress)
    split_notes: list[str] = []
    if split_mm is not None:
        fine = program_paths(robot, module, procs, tool, min(step_mm, split_mm / 4))
        text, split_notes = densify(text, module, fine, robot.chain, split_mm)
        module = module_of_text(text, encoding, str(program))
    pps = program_paths(robot, module, procs, tool, step_mm)
    occurrences, limits, notes, pivots, iterations, skip = _per_procedure(la, robot, module,
                                                                         pps, force)
    shifts, new, more = _shifts(module, occurrences, skip)
    notes += more
    notes += [f"{t}: left as programmed (see limits)" for t in sorted(skip)]
    t = max((float(np.linalg.norm(s.shift[:3])) for s in shifts), default=0.0)
    r = max((float(np.linalg.norm(s.shift[3:])) for s in shifts), default=0.0)
    what = "gravity sag and process load" if gravity else "process load (unloaded run = 0)"
    header = ["flexarm compensate: robtargets shifted so that the loaded tool lands on the "
              "programmed path",
              f"model: {la.label} ({what}); force: {force.label}",
              f"procedures: {', '.join(pp.name for pp in pps)}; {len(shifts)} robtargets "
              f"shifted, largest {t * 1e3:.3f} mm, {r * 1e3:.3f} mrad"]
    if split_notes:
        header.append(f"motions longer than {split_mm:g} mm split into equal sub-motions "
                      f"({len(split_notes)} motions)")
    new_text = rewrite_targets(text, new, header)
    compensated = _with_targets(module, new)
    pps_c = program_paths(robot, compensated, [pp.name for pp in pps], tool, step_mm)
    before = tuple(run_program(la, pp, force, pivots[pp.name],
                               is_jump=limits.jump_mask(pp.name, pp.path.segments))
                   for pp in pps)
    after = tuple(run_program(la, pc, force, pivots[pp.name], reference=pp,
                              is_jump=limits.jump_mask(pp.name, pc.path.segments))
                  for pp, pc in zip(pps, pps_c, strict=True))
    log.info("compensated %s: %d targets", program, len(shifts))
    return CompensationResult(str(program), new_text, encoding, tuple(shifts), before, after,
                              limits, la.label, force.label, iterations,
                              tuple(split_notes + notes), force, pivots, split_mm,
                              tuple(header), _joints(robot.chain, pps_c),
                              {pp.name: np.linalg.inv(TOOL0) @ pp.tool for pp in pps})
