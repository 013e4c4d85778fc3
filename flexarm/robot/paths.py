"""TCP paths from RAPID procedures: sampling and circle/sphere geometry.

A procedure read by :func:`flexarm.robot.formats.rapid.read_rapid` becomes a
:class:`SampledPath`: TCP positions [mm] and orientations (unit quaternions
``[w, x, y, z]``, scalar first as in RAPID) in the work-object frame of its
instructions, densely sampled by arc length.

Interpolation follows the programmed geometry:

* ``MoveL``: straight line, orientation by SLERP (shortest rotation).
* ``MoveC``: the circle through start, ``CirPoint`` and ``ToPoint`` computed exactly
  (:func:`circle_through`), sampled by arc length; orientation by SLERP start ->
  CirPoint -> ToPoint (RAPID's ``CirPathMode \\CirPointOri``; the default path-frame
  mode gives the same result when the programmed orientations turn with the circle or
  stay constant, as in the thesis module).
* ``MoveJ`` / ``MoveAbsJ``: a straight line *flagged* as joint-interpolated: the real
  TCP path is linear in joint space and needs the arm's kinematics (see ``notes``).

Corner zones (``z100`` ...) are not modelled: the path passes through every target.
The geometry of single segments (circles, spheres, line and arc sampling) lives in
:mod:`flexarm.robot.path_geometry` and the quaternion helpers in
:mod:`flexarm.robot.quaternions`; the circle/sphere functions and the quaternion helpers
are re-exported here.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..fe.typing import ArrayLike, BoolArray, FloatArray, IntArray
from .formats.rapid import JointTarget, Motion, Procedure, RobTarget
from .path_geometry import circle_through, fit_circle, fit_sphere, sample_arc, sample_line
from .quaternions import (
    quat_angle,
    quat_conjugate,
    quat_from_intrinsic_xyz,
    quat_from_matrix,
    quat_multiply,
    quat_normalize,
    quat_to_matrix,
    slerp,
)

__all__ = [
    "SampledPath",
    "sample_procedure",
    "circle_through",
    "fit_circle",
    "fit_sphere",
    "quat_normalize",
    "quat_multiply",
    "quat_conjugate",
    "quat_to_matrix",
    "quat_from_matrix",
    "quat_from_intrinsic_xyz",
    "quat_angle",
    "slerp",
]

logger = logging.getLogger(__name__)


FK = Callable[[FloatArray], "tuple[ArrayLike, ArrayLike]"]
#: A TCP pose: position (3,) [mm] and unit quaternion (4,) ``[w, x, y, z]``.
Pose = tuple[FloatArray, FloatArray]
#: Instructions interpolated in joint space (drawn as straight lines here).
_JOINT_KINDS = ("MoveJ", "MoveAbsJ")


# ----------------------------------------------------------------------------- sampling

@dataclass(frozen=True, eq=False)
class SampledPath:
    """A densely sampled TCP path.

    Parameters
    ----------
    name : str
        Procedure name.
    points_mm : (n, 3) float
        TCP positions [mm] in the work-object frame of the instructions.
    quats : (n, 4) float
        Unit orientations ``[w, x, y, z]``, sign-continuous along the path.
    segments : (n,) int
        Index of the motion (in ``Procedure.motions``) each sample belongs to; sample 0
        (the start) belongs to motion 0.
    kinds : tuple of str
        Instruction of every motion (``"MoveL"``, ``"MoveC"``, ...).
    arc_length_mm : (n,) float
        Exact TCP path length from the start [mm] (circle arcs as arcs, not chords).
    lines : tuple of int
        File line of every motion.
    notes : tuple of str
        Approximations made (joint moves drawn straight, corner zones ignored, ...).
    targets : tuple of tuple of str
        Names of every motion's targets as written (``CirPoint`` first for ``MoveC``,
        the destination last); empty when not known.
    """

    name: str
    points_mm: FloatArray
    quats: FloatArray
    segments: IntArray
    kinds: tuple[str, ...]
    arc_length_mm: FloatArray
    lines: tuple[int, ...]
    notes: tuple[str, ...]
    targets: tuple[tuple[str, ...], ...] = ()

    def motion_text(self, k: int) -> str:
        """``"MoveC via Target_80 to Target_90 (line 71)"``: motion ``k`` for messages."""
        names = self.targets[k] if k < len(self.targets) else ()
        via = "".join(f" via {t}" for t in names[:-1])
        to = f" to {names[-1]}" if names else ""
        return f"{self.kinds[k]}{via}{to} (line {self.lines[k]})"

    def __post_init__(self) -> None:
        for attr, dtype in (("points_mm", np.float64), ("quats", np.float64),
                            ("segments", np.int64), ("arc_length_mm", np.float64)):
            arr = np.array(getattr(self, attr), dtype=dtype)
            arr.setflags(write=False)
            object.__setattr__(self, attr, arr)

    @property
    def n_points(self) -> int:
        return len(self.points_mm)

    @property
    def is_joint_interpolated(self) -> BoolArray:
        """(n,) bool: samples of ``MoveJ``/``MoveAbsJ`` motions (drawn as straight lines)."""
        joint = np.array([k in _JOINT_KINDS for k in self.kinds], dtype=bool)
        return joint[self.segments]

    @property
    def points_m(self) -> FloatArray:
        """(n, 3) positions [m] (SI, for the rest of flexarm)."""
        return self.points_mm * 1e-3



class _Segment(NamedTuple):
    """Samples of one motion, excluding its start pose.

    Attributes
    ----------
    points : (m, 3) float
        TCP positions [mm].
    quats : (m, 4) float
        Unit orientations ``[w, x, y, z]``, not yet sign-continuous.
    arc : (m,) float
        Path length from the motion's start [mm].
    end : Pose
        Programmed destination pose, the start of the next motion.
    """

    points: FloatArray
    quats: FloatArray
    arc: FloatArray
    end: Pose


def _target_pose(m: Motion, fk: FK | None) -> Pose:
    """TCP pose of a motion's destination: position [mm] and unit quaternion.

    Raises
    ------
    ValueError
        If the destination is a joint target and there is no ``fk`` to turn it into a pose.
    """
    target = m.to_point
    if isinstance(target, JointTarget):
        if fk is None:
            raise ValueError(f"MoveAbsJ on line {m.line}: a joint target needs fk= "
                             "(the arm's forward kinematics) to become a TCP pose")
        pos, quat = fk(np.asarray(target.joints_deg, dtype=np.float64))
        return np.asarray(pos, dtype=np.float64), quat_normalize(quat)
    return target.pos_mm, quat_normalize(target.quat)


def _start_pose(motions: Sequence[Motion], start: RobTarget | None, fk: FK | None,
                notes: list[str]) -> tuple[Pose, int]:
    """Pose the path starts from [mm], and the index of the first motion to sample.

    Without ``start`` the first motion's destination is taken (its approach is unknown, so
    it is noted and not sampled); a ``MoveC`` needs its start, so it cannot come first.
    """
    if start is None:
        if motions[0].kind == "MoveC":
            raise ValueError(f"MoveC on line {motions[0].line} starts the procedure: pass "
                             "start= (the robot's pose before it)")
        pose = _target_pose(motions[0], fk)
        notes.append(f"path starts at {motions[0].kind} line {motions[0].line}'s destination "
                     "(the approach from the robot's previous pose is not sampled)")
        return pose, 1
    return (start.pos_mm, quat_normalize(start.quat)), 0


def _sample_linear(m: Motion, start: Pose, fk: FK | None, step_mm: float,
                   step_rad: float) -> _Segment:
    """A ``MoveL`` from ``start``: straight line [mm], SLERP orientation (steps in rad)."""
    p1, q1 = _target_pose(m, fk)
    P, Q, S = sample_line(start[0], start[1], p1, q1, step_mm, step_rad)
    return _Segment(P, Q, S, (p1, q1))


def _sample_joint(m: Motion, start: Pose, fk: FK | None, step_mm: float, step_rad: float,
                  notes: list[str]) -> _Segment:
    """A ``MoveJ``/``MoveAbsJ`` from ``start``, drawn as ``MoveL`` (steps in mm and rad).

    The true TCP path is linear in joint space and needs the arm's kinematics, so the
    approximation is recorded in ``notes``.
    """
    segment = _sample_linear(m, start, fk, step_mm, step_rad)
    notes.append(f"{m.kind} line {m.line} drawn as a straight line: the real TCP "
                 "path is linear in joint space (needs the arm's kinematics)")
    return segment


def _sample_circular(m: Motion, start: Pose, fk: FK | None, step_mm: float,
                     step_rad: float) -> _Segment:
    """A ``MoveC`` from ``start`` along its exact circle (steps in mm of arc and rad).

    Raises
    ------
    ValueError
        If start, ``CirPoint`` and ``ToPoint`` are collinear or coincide.
    """
    end = _target_pose(m, fk)
    cir, to = m.cir_point, m.to_point
    try:
        circle = circle_through(start[0], cir.pos_mm, to.pos_mm)
    except ValueError:
        raise ValueError(f"MoveC on line {m.line}: start, CirPoint '{cir.name}' and ToPoint "
                         f"'{to.name}' are collinear or coincide (no circle)") from None
    P, Q, S = sample_arc(circle, start[0], start[1], cir.pos_mm, cir.quat, to.pos_mm, to.quat,
                         step_mm, step_rad)
    return _Segment(P, Q, S, end)


def _sample_motions(motions: Sequence[Motion], first: int, start: Pose, fk: FK | None,
                    step_mm: float, step_rad: float,
                    notes: list[str]) -> list[tuple[int, _Segment]]:
    """Sample ``motions[first:]`` one after the other, each from the previous destination.

    Returns
    -------
    list of (int, _Segment)
        Index of every sampled motion in ``motions`` and its samples (lengths in mm).
    """
    segments = []
    pose = start
    for k in range(first, len(motions)):
        m = motions[k]
        if m.kind == "MoveC":
            segment = _sample_circular(m, pose, fk, step_mm, step_rad)
        elif m.kind in _JOINT_KINDS:
            segment = _sample_joint(m, pose, fk, step_mm, step_rad, notes)
        else:
            segment = _sample_linear(m, pose, fk, step_mm, step_rad)
        segments.append((k, segment))
        pose = segment.end
    return segments


def _zone_and_frame_notes(motions: Sequence[Motion]) -> list[str]:
    """Notes on what the samples ignore: corner zones and mixed tools or work objects."""
    notes = [f"{m.kind} line {m.line}: corner zone '{m.zone}' not modelled (the path passes "
             "through the target)" for m in motions if not m.is_fine]
    wobjs = sorted({m.wobj or "wobj0" for m in motions})
    tools = sorted({m.tool for m in motions})
    if len(wobjs) > 1:
        notes.append(f"instructions use several work objects ({', '.join(wobjs)}): positions "
                     "are mixed frames")
    if len(tools) > 1:
        notes.append(f"instructions use several tools ({', '.join(tools)})")
    return notes


def _sign_continuous(Q: FloatArray) -> FloatArray:
    """(n, 4) quaternions with signs flipped so neighbours never point apart."""
    # q and -q are the same rotation; consumers differencing or interpolating samples
    # need no jump, so flip where a sample points away from its predecessor
    flips = np.r_[1.0, np.where(np.sum(Q[1:] * Q[:-1], axis=1) < 0, -1.0, 1.0)]
    return Q * np.cumprod(flips)[:, None]


def _assemble(procedure: Procedure, start: Pose, segments: Sequence[tuple[int, _Segment]],
              notes: list[str]) -> SampledPath:
    """The start pose (sample 0, of motion 0) and the motions' samples as one path [mm]."""
    p, q = start
    pts: list[FloatArray] = [p[None]]
    quats: list[FloatArray] = [q[None]]
    segs: list[IntArray] = [np.zeros(1, dtype=np.int64)]
    arcs: list[FloatArray] = [np.zeros(1)]
    s0 = 0.0
    for k, segment in segments:
        pts.append(segment.points)
        quats.append(segment.quats)
        segs.append(np.full(len(segment.points), k, dtype=np.int64))
        arcs.append(s0 + segment.arc)
        s0 += float(segment.arc[-1])
    motions = procedure.motions
    return SampledPath(procedure.name, np.concatenate(pts), _sign_continuous(np.concatenate(quats)),
                       np.concatenate(segs), tuple(m.kind for m in motions), np.concatenate(arcs),
                       tuple(m.line for m in motions), tuple(notes),
                       tuple(tuple(t.name for t in m.targets) for m in motions))


def sample_procedure(
    procedure: Procedure,
    start: RobTarget | None = None,
    step_mm: float = 1.0,
    step_deg: float = 1.0,
    fk: FK | None = None,
) -> SampledPath:
    """Sample the TCP path of a RAPID procedure.

    Parameters
    ----------
    procedure : Procedure
        From :func:`~flexarm.robot.formats.rapid.read_rapid`.
    start : RobTarget, optional
        Where the robot is before the first instruction.  Without it the path starts at
        the first instruction's destination (the approach move is not sampled), and a
        ``MoveC`` cannot come first.
    step_mm : float
        Largest distance between samples along the path [mm].
    step_deg : float
        Largest orientation change between samples [deg].
    fk : callable, optional
        ``fk(joints_deg (6,)) -> (pos_mm (3,), quat (4,))`` of the arm with its tool in
        the work-object frame; needed only for ``MoveAbsJ``.

    Returns
    -------
    SampledPath

    Examples
    --------
    >>> from importlib.resources import files
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> mod = read_rapid(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")
    >>> path = sample_procedure(mod.procedures["Path_30"], step_mm=5.0)
    >>> round(float(path.arc_length_mm[-1]), 6)  # one turn of a 155 mm circle
    973.893723
    """
    if not step_mm > 0 or not step_deg > 0:
        raise ValueError(f"step_mm and step_deg must be > 0, got {step_mm}, {step_deg}")
    logger.info("sampling RAPID procedure %s", procedure.name)
    step_rad = math.radians(step_deg)
    motions: tuple[Motion, ...] = procedure.motions
    if not motions:
        raise ValueError(f"procedure {procedure.name} has no motions")
    notes: list[str] = []
    start_pose, first = _start_pose(motions, start, fk, notes)
    segments = _sample_motions(motions, first, start_pose, fk, step_mm, step_rad, notes)
    notes += _zone_and_frame_notes(motions)
    path = _assemble(procedure, start_pose, segments, notes)
    logger.info("sampled %s: %d points, %.1f mm", procedure.name, path.n_points,
                float(path.arc_length_mm[-1]))
    return path
