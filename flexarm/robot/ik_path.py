"""Inverse kinematics along sampled RAPID paths, honouring the configuration data.

A RAPID ``robtarget`` gives the pose of the *programmed tool* (``tool0`` = the
flange: origin at the turning-disc face, z out of the flange, x pointing down at
zero joint angles) in the work object (``wobj0`` = the base frame) [mm], plus the
configuration ``conf = [cf1, cf4, cf6, cfx]``.  The arm's own TCP (``robot.tool``,
for the demo arm 150 mm out of the flange) is a different point: :func:`tool_frame`
names which one the targets are read as.

The closed form of :func:`flexarm.robot.ik.ik_analytic` gives up to eight
branches; joints 4 and 6 may also turn by whole revolutions.  At every programmed
target the branch whose :func:`rapid_conf` equals the programmed ``conf`` is the
requested one.  Between targets (and wherever ``conf`` cannot be met, e.g. the
inconsistent data of the thesis's ``Path_60``) the branch nearest the previous
sample is taken (continuity), as the controller does with ``ConfL\\Off``.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from ..fe.errors import ConvergenceError
from ..fe.typing import FloatArray, IntArray
from .ik import IKConfig, ik, ik_analytic
from .kinematics import Chain, link_frames, tcp_frame
from .paths import SampledPath, quat_to_matrix

__all__ = ["PathIK", "UnreachableTargetError", "tool_frame", "target_frames", "rapid_conf",
           "ik_conf", "ik_path"]

log = logging.getLogger(__name__)

#: ABB ``tool0`` on the last link: no offset, z along the joint-6 axis (link x).
TOOL0 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0],
                  [0.0, 0.0, 0.0, 1.0]])


def tool_frame(chain: Chain, tool: str | FloatArray = "tool0") -> FloatArray:
    """(4, 4) frame on the last body that the RAPID targets are read as.

    Parameters
    ----------
    chain : Chain
    tool : {"tool0", "robot"} or (4, 4) float
        ``"tool0"``: the flange (what the program uses); ``"robot"``: the arm's TCP
        ``chain.tool``; or an explicit frame in the last body's frame [m].

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> tool_frame(two_link_arm().chain)[:3, 2].tolist()
    [1.0, 0.0, 0.0]
    """
    if isinstance(tool, str):
        if tool == "tool0":
            return TOOL0.copy()
        if tool == "robot":
            return np.array(chain.tool, dtype=float)
        raise ValueError(f"tool must be 'tool0', 'robot' or a (4, 4) frame, got '{tool}'")
    T = np.asarray(tool, dtype=float)
    if T.shape != (4, 4):
        raise ValueError(f"tool frame must be (4, 4), got {T.shape}")
    return T


def target_frames(points_mm: FloatArray, quats: FloatArray) -> FloatArray:
    """(n, 4, 4) frames [m] from positions (n, 3) [mm] and quaternions (n, 4) ``[w, x, y, z]``."""
    P = np.asarray(points_mm, dtype=float).reshape(-1, 3)
    T = np.zeros((len(P), 4, 4))
    T[:, :3, :3] = quat_to_matrix(np.asarray(quats, dtype=float).reshape(-1, 4))
    T[:, :3, 3] = P * 1e-3
    T[:, 3, 3] = 1.0
    return T


def rapid_conf(chain: Chain, q: FloatArray) -> IntArray:
    """(..., 4) ABB configuration ``[cf1, cf4, cf6, cfx]`` of joint angles ``q`` (..., 6) [rad].

    ``cf1/cf4/cf6 = floor(q / 90 deg)``; ``cfx`` bit 2: wrist centre behind axis 1,
    bit 1: wrist centre behind the lower arm (the line through axes 2 and 3), bit 0:
    axis 5 negative.  The wrist centre is the joint-5 origin.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> r = load_demo_robot()
    >>> rapid_conf(r.chain, np.radians([100, 10, 0, -30, 20, 200])).tolist()
    [1, -1, 2, 0]
    """
    q = np.asarray(q, dtype=float)
    F = link_frames(chain, q)
    pw, p2, p3 = F[..., 5, :3, 3], F[..., 2, :3, 3], F[..., 3, :3, 3]
    c1, s1 = np.cos(q[..., 0]), np.sin(q[..., 0])
    behind_1 = c1 * pw[..., 0] + s1 * pw[..., 1] < 0
    y1 = np.stack([-s1, c1, np.zeros_like(c1)], axis=-1)  # joint-2 axis
    forward = np.cross(y1, p3 - p2)
    behind_lower = np.einsum("...i,...i->...", pw - p2, forward) < 0
    cfx = 4 * behind_1 + 2 * behind_lower + (q[..., 4] < 0)
    quad = np.floor(np.degrees(q[..., [0, 3, 5]]) / 90.0).astype(np.int64)
    return np.concatenate([quad, cfx[..., None].astype(np.int64)], axis=-1)


def ik_conf(chain: Chain, target: FloatArray, conf, lower: FloatArray,
            upper: FloatArray) -> FloatArray | None:
    """Joint angles [rad] reaching ``target`` (4, 4) [m] with the configuration ``conf``.

    Joints 4 and 6 are turned by whole revolutions into their quadrant ``cf4``/``cf6``.
    Returns None when no branch within ``lower``/``upper`` has this configuration.
    """
    want = np.asarray(conf, dtype=np.int64)
    for c in IKConfig.all():
        q = ik_analytic(chain, target, c)
        if np.any(np.isnan(q)):
            continue
        for j, cf in ((3, want[1]), (5, want[2])):
            q[j] += 2 * np.pi * np.floor((cf * 90.0 + 45.0 - np.degrees(q[j])) / 360.0 + 0.5)
        if np.any(q < lower) or np.any(q > upper):
            continue
        if np.array_equal(rapid_conf(chain, q), want):
            return q
    return None


class UnreachableTargetError(ValueError):
    """A programmed target, or the path to it, is out of the arm's reach (or needs a joint
    beyond its limits).  ``line`` is the motion's line in the RAPID file."""

    def __init__(self, message: str, line: int):
        super().__init__(message)
        self.line = line


def _unreachable(path: SampledPath, i: int, T: FloatArray, is_target: bool) -> str:
    """Why sample ``i`` of ``path`` (tool frame ``T`` (4, 4) [m]) cannot be reached."""
    k = int(path.segments[i])
    p = path.points_mm[i]
    at = f"({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm, {np.linalg.norm(T[:3, 3]):.2f} m from the base"
    if is_target:
        return (f"{path.motion_text(k)}: its target at {at}, is out of the arm's reach or "
                "needs a joint beyond its limits")
    end = path.points_mm[np.flatnonzero(path.segments == k)[-1]]
    return (f"{path.motion_text(k)}: the path leaves the arm's reach (or its joint limits) "
            f"{float(path.arc_length_mm[i]):.0f} mm into the procedure, at {at}; the target is at "
            f"({end[0]:.1f}, {end[1]:.1f}, {end[2]:.1f}) mm")


@dataclass(frozen=True, eq=False)
class PathIK:
    """Joint angles along a sampled path.

    Attributes
    ----------
    q : (n, 6) float
        Joint angles [rad] at every path sample.
    frames : (n, 4, 4) float
        Frames of the targeted tool reached by ``q`` (FK), base frame [m].
    tool : (4, 4) float
        The tool frame on the last body that the targets were read as [m].
    target_samples : (k,) int
        Sample index of every programmed ``ToPoint``.
    conf_programmed, conf_reached : (k, 4) int
        RAPID configuration asked for and reached at those samples.
    is_conf_met : (k,) bool
    notes : tuple of str
    """

    q: FloatArray
    frames: FloatArray
    tool: FloatArray
    target_samples: IntArray
    conf_programmed: IntArray
    conf_reached: IntArray
    is_conf_met: np.ndarray
    notes: tuple[str, ...]


def ik_path(chain: Chain, path: SampledPath, confs, lower: FloatArray, upper: FloatArray,
            tool: str | FloatArray = "tool0", q_start: FloatArray | None = None) -> PathIK:
    """Solve IK at every sample of ``path`` with the programmed configurations.

    Parameters
    ----------
    chain : Chain
        The arm's kinematics (``robot.chain``); its own tool is replaced by ``tool``.
    path : SampledPath
        From :func:`~flexarm.robot.paths.sample_procedure`; positions in the base frame.
    confs : (n_motions, 4) int or None
        ``conf`` of every motion's ``ToPoint`` (``Procedure.motions[k].to_point.conf``);
        None: no configuration data (continuity from ``q_start`` only).
    lower, upper : (6,) float
        Joint limits [rad].
    tool : {"tool0", "robot"} or (4, 4) float
        See :func:`tool_frame`.
    q_start : (6,) float, optional
        Angles [rad] the first sample's branch is chosen nearest to when its ``conf``
        is not given or not reachable (zeros by default).

    Returns
    -------
    PathIK

    Raises
    ------
    UnreachableTargetError
        At the first sample out of reach, naming the motion, its targets and line.

    Examples
    --------
    >>> from importlib.resources import files
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.robot.paths import sample_procedure
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> r = load_demo_robot()
    >>> proc = read_rapid(files("flexarm") / "data/rapid/ldbb_thesis.mod").procedures["Path_30"]
    >>> sol = ik_path(r.chain, sample_procedure(proc, step_mm=20), [m.to_point.conf for m in
    ...               proc.motions], r.lower, r.upper)
    >>> bool(sol.is_conf_met.all())
    True
    """
    T_tool = tool_frame(chain, tool)
    ch = replace(chain, tool=T_tool)
    lo, hi = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    has_conf = confs is not None
    if not has_conf:
        confs = np.zeros((len(path.kinds), 4), dtype=np.int64)
    confs = np.asarray(confs, dtype=np.int64).reshape(-1, 4)
    if len(confs) != len(path.kinds):
        raise ValueError(f"confs must be ({len(path.kinds)}, 4) (one per motion), got "
                         f"{confs.shape}")
    log.info("IK along %s (%d samples)", path.name, path.n_points)
    T = target_frames(path.points_mm, path.quats)
    n = len(T)
    seg = path.segments
    last = np.flatnonzero(np.r_[seg[1:] != seg[:-1], True])  # last sample of each motion
    is_target = np.zeros(n, dtype=bool)
    is_target[last] = True
    notes: list[str] = []
    q = np.zeros((n, 6))

    def solve(i: int, near: FloatArray) -> FloatArray:
        try:
            return ik(ch, T[i], q_near=near, lower=lo, upper=hi)
        except (ValueError, ConvergenceError):
            raise UnreachableTargetError(_unreachable(path, i, T[i], bool(is_target[i])),
                                         path.lines[seg[i]]) from None

    prev = ik_conf(ch, T[0], confs[seg[0]], lo, hi) if is_target[0] and has_conf else None
    if prev is None:
        prev = solve(0, np.zeros(6) if q_start is None else np.asarray(q_start, dtype=float))
        if has_conf:
            notes.append("first sample: programmed conf not reachable, took the branch "
                         "nearest q_start")
    q[0] = prev
    for i in range(1, n):
        q[i] = solve(i, q[i - 1])
    reached = rapid_conf(ch, q[last])
    wanted = confs[seg[last]]
    met = np.all(reached == wanted, axis=1) if has_conf else np.ones(len(last), dtype=bool)
    if not has_conf:
        wanted = reached.copy()
    for k in np.flatnonzero(~met):
        notes.append(f"motion {seg[last[k]]} (line {path.lines[seg[last[k]]]}): conf "
                     f"{wanted[k].tolist()} programmed, {reached[k].tolist()} reached by "
                     "continuity")
    log.info("IK along %s done: %d/%d targets with their programmed conf", path.name,
             int(met.sum()), len(met))
    return PathIK(q, tcp_frame(ch, q), T_tool, last, wanted, reached, met, tuple(notes))
