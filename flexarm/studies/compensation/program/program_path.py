"""A RAPID program as the arm runs it: procedures sampled, joint angles, targets on the path.

:func:`program_paths` turns the procedures of a module into :class:`ProgramPath`
objects: the programmed TCP path (:func:`~flexarm.robot.paths.sample_procedure`), the
joint angles at every sample and at every target, and where each target (``CirPoint``
and ``ToPoint`` of every motion, in execution order) sits on the path.  The joint
angles honour the programmed configuration at the targets and follow the path between
them (:func:`~.path_ik.batched_path_ik`).

Targets are read in the frame of the programmed tool: ``tool0`` (the flange) or a
``tooldata`` the module declares; ``tool="robot"`` reads them as the robot file's TCP.
Positions are in the base frame (``wobj0``); another work object is refused.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from ....fe.typing import FloatArray, IntArray
from ....robot.formats.rapid import JointTarget, RapidModule
from ....robot.ik_path import TOOL0, UnreachableTargetError, target_frames, tool_frame
from ....robot.kinematics import Chain
from ....robot.paths import SampledPath, quat_to_matrix, sample_procedure
from ...tolerances import tol
from ..solve.ik_batch import newton_ik
from ..solve.path_ik import batched_path_ik

__all__ = ["ProgramPath", "program_paths", "procedure_tool"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class ProgramPath:
    """One procedure as the arm runs it.

    Attributes
    ----------
    path : SampledPath
        Programmed TCP path [mm], base frame; ``path.name`` is the procedure.
    tool : (4, 4) float
        The programmed tool on the last body [m].
    q : (n, 6) float
        Joint angles at every sample [rad].
    frames : (n, 4, 4) float
        Programmed tool frames at every sample [m].
    targets : tuple of str
        Every target occurrence in execution order (``CirPoint`` before ``ToPoint``).
    target_samples, target_motions : (k,) int
        Sample index (the nearest one for a ``CirPoint``) and motion index of each.
    target_frames : (k, 4, 4) float
        Programmed frames of the targets themselves [m].
    target_q : (k, 6) float
        Joint angles reaching them [rad].
    is_named : (k,) bool
        The target is a robtarget of the module (inline and ``Offs``/``RelTool``
        targets are not).
    """

    path: SampledPath
    tool: FloatArray
    q: FloatArray
    frames: FloatArray
    targets: tuple[str, ...]
    target_samples: IntArray
    target_motions: IntArray
    target_frames: FloatArray
    target_q: FloatArray
    is_named: np.ndarray

    @property
    def name(self) -> str:
        return self.path.name

    @property
    def points(self) -> FloatArray:
        """(n, 3) programmed tool positions [m]."""
        return self.frames[:, :3, 3]


def procedure_tool(module: RapidModule, name: str, chain: Chain, tool=None) -> FloatArray:
    """(4, 4) frame on the last body [m] that procedure ``name``'s targets are read as.

    ``tool=None`` takes the instructions' tool: ``tool0`` or a ``tooldata`` of the
    module (its ``tframe`` on the flange); ``"tool0"``, ``"robot"`` or a (4, 4) frame
    override it (see :func:`~flexarm.robot.ik_path.tool_frame`).

    Raises
    ------
    ValueError
        Mixed tools in one procedure, or a tool the module does not declare.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> T = procedure_tool(read_rapid(THESIS_RAPID), "Path_30", load_demo_robot().chain)
    >>> T[:3, 2].tolist()  # tool0: z along the flange axis (link x)
    [1.0, 0.0, 0.0]
    """
    if tool is not None:
        return tool_frame(chain, tool)
    proc = module.procedure(name)
    tools = sorted({m.tool for m in proc.motions}, key=str.lower)
    where = module.path or f"module {module.name}"
    if len(tools) > 1:
        raise ValueError(f"{where}: {name} uses several tools ({', '.join(tools)}); "
                         "compensate one tool at a time")
    if tools[0].lower() == "tool0":
        return TOOL0.copy()
    decl = next((d for k, d in module.data.items() if k.lower() == tools[0].lower()), None)
    if decl is None or decl.type.lower() != "tooldata" or decl.value is None:
        raise ValueError(f"{where}: {name}: tool '{tools[0]}' is not a tooldata of the module "
                         "(declare it, or read the targets as the robot's TCP: --tool robot)")
    pos, quat = np.asarray(decl.value[1][0], float), np.asarray(decl.value[1][1], float)
    T = np.eye(4)
    T[:3, :3] = quat_to_matrix(quat)
    T[:3, 3] = pos * 1e-3
    return TOOL0 @ T


def _check_frames(module: RapidModule, name: str) -> None:
    """Refuse work objects other than the base frame and joint targets (not shifted)."""
    where = module.path or f"module {module.name}"
    for m in module.procedure(name).motions:
        if m.wobj is not None and m.wobj.lower() != "wobj0":
            raise ValueError(f"{where}, line {m.line}: work object '{m.wobj}': compensate "
                             "reads targets in the base frame (wobj0) only")
        if any(isinstance(t, JointTarget) for t in m.targets):
            raise ValueError(f"{where}, line {m.line}: {m.kind} to a joint target: joint "
                             "targets cannot be shifted (program the pose as a robtarget)")


def _occurrences(module: RapidModule, path: SampledPath, name: str):
    """(names, samples, motions, frames, is_named) of every target on ``path``."""
    proc = module.procedure(name)
    named = {k.lower() for k in module.targets}
    seg = path.segments
    ends = np.flatnonzero(np.r_[seg[1:] != seg[:-1], True])
    names, samples, motions, pos, quats = [], [], [], [], []
    for k, m in enumerate(proc.motions):
        rows = np.flatnonzero(seg == k)
        for t in m.targets:
            if t is m.to_point:
                i = int(ends[k])
            else:  # the circle point: the nearest sample of its motion
                d = np.linalg.norm(path.points_mm[rows] - t.pos_mm, axis=1)
                i = int(rows[np.argmin(d)])
            names.append(t.name)
            samples.append(i)
            motions.append(k)
            pos.append(t.pos_mm)
            quats.append(t.quat)
    is_named = np.array([n.lower() in named for n in names], dtype=bool)
    return (tuple(names), np.array(samples, np.int64), np.array(motions, np.int64),
            target_frames(np.array(pos), np.array(quats)), is_named)


def program_paths(robot, module: RapidModule, procs=None, tool=None,
                  step_mm: float = 2.0) -> tuple[ProgramPath, ...]:
    """The procedures ``procs`` of ``module`` (default: all) as the arm runs them.

    Parameters
    ----------
    robot : Robot
        Kinematics and joint limits.
    module : RapidModule
        From :func:`~flexarm.robot.formats.rapid.read_rapid`.
    procs : sequence of str, optional
        Procedure names (case-insensitive); all with motions by default.
    tool : None, "tool0", "robot" or (4, 4) float
        See :func:`procedure_tool`.
    step_mm : float
        Path sampling step [mm].

    Returns
    -------
    tuple of ProgramPath

    Raises
    ------
    ValueError
        Unknown procedure, another work object, a joint target, an undeclared tool, or
        a target out of reach (naming the file and line).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> (pp,) = program_paths(load_demo_robot(), read_rapid(THESIS_RAPID), ["Path_30"], step_mm=20)
    >>> pp.targets
    ('Target_70', 'Target_80', 'Target_90', 'Target_100', 'Target_110')
    """
    chain = robot.chain
    where = module.path or f"module {module.name}"
    try:
        names = [p for p, proc in module.procedures.items() if proc.motions] if procs is None \
            else [module.procedure(p).name for p in procs]
    except KeyError as exc:
        raise ValueError(f"{where}: {exc.args[0]}") from None
    out = []
    for name in names:
        _check_frames(module, name)
        T_tool = procedure_tool(module, name, chain, tool)
        ch = replace(chain, tool=T_tool)
        proc = module.procedure(name)
        try:
            path = sample_procedure(proc, step_mm=step_mm)
        except ValueError as exc:
            raise ValueError(f"{where}: {name}: {exc}") from None
        confs = np.array([m.to_point.conf for m in proc.motions], dtype=np.int64)
        try:
            q = batched_path_ik(ch, path, confs, robot.lower, robot.upper)
        except UnreachableTargetError as exc:
            raise ValueError(f"{where}: {name}: {exc}") from None
        occ_names, samples, motions, frames, is_named = _occurrences(module, path, name)
        seed = q[samples]
        tq, err = newton_ik(ch, frames, seed)
        if err.max() > tol.ik_pose_error:
            k = int(np.argmax(err))
            raise ValueError(f"{where}, line {path.lines[motions[k]]}: {name}: target "
                             f"{occ_names[k]} is out of the arm's reach")
        out.append(ProgramPath(path, T_tool, q, target_frames(path.points_mm, path.quats),
                               occ_names, samples, motions, frames, tq, is_named))
    return tuple(out)
