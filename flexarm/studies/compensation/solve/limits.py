"""Where a static shift of the targets cannot help, and what can.

Three limits of compensation, each with the way round it:

* a joint law that *jumps* along the path (a backlash whose torque changes sign, a
  hysteresis loop reversed by more than its friction torque): the joint crosses its
  play somewhere between two targets and the tool jumps by it there, which no fixed
  offset of the targets removes.  Named with the procedure, the motion (its targets and
  line), the joint and the size; the remedy is a preload that keeps the joint's torque
  one-signed (its size and direction at the tool), another place for the workpiece
  where gravity dominates the joint, or a slower feed (a smaller process force);
* a compensated target beyond a joint limit or out of reach: another pose of the
  workpiece or another configuration;
* a target near a singularity (the scaled Jacobian's condition number above
  :attr:`~flexarm.studies.tolerances.Tolerances.singular_condition`): small deflections
  need large joint corrections; another pose of the workpiece, or a slower feed so the
  axes can follow.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ....assembly.nonlinear import Backlash, Hysteresis
from ....fe.typing import FloatArray
from ....robot.kinematics import jacobian
from ...tolerances import tol
from .loaded import LoadedArm, joint_torques

__all__ = ["LawJump", "LimitHit", "NearSingular", "Limits", "law_jumps", "limit_hits",
           "near_singular", "scaled_condition"]


@dataclass(frozen=True)
class LawJump:
    """A joint law jumping along a path: its joint (0-based), where and how much.

    ``motion_text`` names the motion (targets, line), ``arc_mm`` where along the
    procedure, ``jump`` the joint's extra rotation change [rad], ``tcp_jump`` the tool's
    translation [m], ``preload`` the torque [N m] that keeps the joint one-signed over the
    motion and ``preload_force`` (3,) [N] a tool force giving it (base frame);
    ``samples`` the (first, last + 1) samples of the motion.
    """

    procedure: str
    joint: int
    kind: str
    motion_text: str
    arc_mm: float
    jump: float
    tcp_jump: float
    preload: float
    preload_force: tuple
    motion: int

    def text(self) -> str:
        f = np.asarray(self.preload_force)
        mag = float(np.linalg.norm(f))
        d = ", ".join(f"{x:.2f}" for x in f / mag) if mag > 0 else "-"
        return (f"{self.procedure}: joint {self.joint + 1} {self.kind} switches in "
                f"{self.motion_text}, {self.arc_mm:.0f} mm into the procedure: the joint "
                f"jumps {self.jump * 1e3:.3f} mrad ({self.tcp_jump * 1e3:.3f} mm at the tool), "
                f"which no target offset removes. Keep its torque one-signed: a preload of "
                f">= {self.preload:.0f} N m (a tool force of {mag:.0f} N along ({d}), base "
                f"frame), or a workpiece pose where gravity loads joint {self.joint + 1} more, "
                f"or a slower feed (a smaller process force)")


@dataclass(frozen=True)
class LimitHit:
    """A compensated target beyond joint ``joint``'s limit (``kind="limit"``, ``value``
    and ``limit`` [rad]) or out of reach (``kind="reach"``)."""

    procedure: str
    target: str
    kind: str
    joint: int = -1
    value: float = 0.0
    limit: float = 0.0

    def text(self) -> str:
        if self.kind == "reach":
            return (f"{self.procedure}: {self.target}: the compensated target is out of the "
                    "arm's reach; move the workpiece towards the arm")
        return (f"{self.procedure}: {self.target}: joint {self.joint + 1} at "
                f"{np.degrees(self.value):.2f} deg passes its limit "
                f"{np.degrees(self.limit):.2f} deg; another pose of the workpiece or another "
                "configuration")


@dataclass(frozen=True)
class NearSingular:
    """A target near a singularity: scaled Jacobian ``condition`` [-] and the largest
    joint correction [rad] the compensation asks there."""

    procedure: str
    target: str
    condition: float
    correction: float

    def text(self) -> str:
        return (f"{self.procedure}: {self.target} is near a singularity (condition "
                f"{self.condition:.0f}): the compensation turns a joint by "
                f"{self.correction * 1e3:.2f} mrad; another pose of the workpiece, or a slower "
                "feed so the axes can follow")


@dataclass(frozen=True, eq=False)
class Limits:
    """Everything :mod:`.limits` found, per kind."""

    jumps: tuple[LawJump, ...] = ()
    hits: tuple[LimitHit, ...] = ()
    singular: tuple[NearSingular, ...] = ()

    def lines(self) -> list[str]:
        items = [*self.jumps, *self.hits, *self.singular]
        return [x.text() for x in items]

    def jump_mask(self, procedure: str, segments: np.ndarray) -> np.ndarray:
        """(n,) bool: samples (motion index ``segments`` (n,) of a sampled path) of
        ``procedure``'s motions where a law jumps."""
        motions = [j.motion for j in self.jumps if j.procedure == procedure]
        return np.isin(np.asarray(segments), motions)


def _width(law) -> tuple[str, float] | None:
    """(kind, width [rad]) of a law that jumps (backlash, hysteresis), else None."""
    base = getattr(law, "law", law)
    amp = abs(getattr(law, "amplitude", 0.0))
    if isinstance(base, Backlash):
        return "backlash", amp or base.width
    if isinstance(base, Hysteresis):
        return "hysteresis", amp or base.lost_motion
    return None


def _runs(moving: np.ndarray) -> list[tuple[int, int]]:
    """(start, end) index pairs of the runs of True in ``moving`` (steps i -> i + 1)."""
    idx = np.flatnonzero(moving)
    if len(idx) == 0:
        return []
    cut = np.flatnonzero(np.diff(idx) > 2) + 1
    return [(int(g[0]), int(g[-1]) + 1) for g in np.split(idx, cut)]


def law_jumps(la: LoadedArm, pp, wrench: FloatArray) -> list[LawJump]:
    """The jumps of ``la``'s backlash and hysteresis laws along program path ``pp``
    (:class:`~.program_path.ProgramPath`) under the path wrenches ``wrench`` (n, 6).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.effects import parse_effect
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.compensation.solve.forces import BallBar
    >>> from flexarm.studies.compensation.solve.loaded import loaded_arm
    >>> from flexarm.studies.compensation.program import program_paths
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> robot = load_demo_robot()
    >>> (pp,) = program_paths(robot, read_rapid(THESIS_RAPID), ["Path_30"], step_mm=5)
    >>> la = loaded_arm(robot, [parse_effect("backlash:j1=0.2mrad")])
    >>> jumps = law_jumps(la, pp, BallBar(400.0).at(pp.frames, [1.33334, 0.04778, 0.588]))
    >>> [(j.joint, j.motion) for j in jumps]  # joint 1 turns round in both half circles
    [(0, 1), (0, 2)]
    """
    if not la.laws:
        return []
    tau = joint_torques(la, pp.q, wrench, pp.tool)
    J = jacobian(replace(la.arm.chain, tool=pp.tool), pp.q)
    seg = pp.path.segments
    out = []
    for j, laws in sorted(la.laws.items()):
        for law in laws:
            kind_width = _width(law)
            if kind_width is None or kind_width[1] <= 0:
                continue
            kind, width = kind_width
            extra = np.asarray(law.deflection(tau[:, j]), float)
            step = np.abs(np.diff(extra))
            for a, b in _runs(step > tol.law_moving_share * width):
                change = float(extra[b] - extra[a])
                if abs(change) < tol.law_switch_share * width:
                    continue
                i = (a + b) // 2
                k = int(seg[b])
                rows = np.flatnonzero(seg == k)
                t = tau[rows, j]
                need = float(min(t.max(), -t.min())) if t.min() < 0 < t.max() else 0.0
                lever = J[i, :3, j]
                g = float(np.linalg.norm(lever))
                sign = float(np.sign(np.mean(t))) or 1.0
                force = tuple(sign * need / g * lever / g) if g else (0.0, 0.0, 0.0)
                out.append(LawJump(pp.name, j, kind, pp.path.motion_text(k),
                                   float(pp.path.arc_length_mm[i]), abs(change),
                                   abs(change) * g, need, force, k))
    return out


def limit_hits(name: str, targets, q: FloatArray, reached: np.ndarray, lower: FloatArray,
               upper: FloatArray) -> list[LimitHit]:
    """Compensated targets (names, joint angles ``q`` (k, 6) [rad]) out of reach or past
    a joint limit.

    Examples
    --------
    >>> q = np.zeros((2, 6))
    >>> q[1, 2] = 1.2
    >>> [h.kind for h in limit_hits("P", ["a", "b"], q, np.array([False, True]),
    ...                             -np.ones(6), np.ones(6))]
    ['reach', 'limit']
    """
    out = []
    for i, t in enumerate(targets):
        if not reached[i]:
            out.append(LimitHit(name, t, "reach"))
            continue
        for j in np.flatnonzero((q[i] < lower) | (q[i] > upper)):
            lim = lower[j] if q[i, j] < lower[j] else upper[j]
            out.append(LimitHit(name, t, "limit", int(j), float(q[i, j]), float(lim)))
    return out


def scaled_condition(chain, q: FloatArray) -> FloatArray:
    """(n,) condition number of the tool Jacobian with its translation rows divided by
    the lever from joint 2 to the tool (so that rows of metres and radians compare).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> ch = load_demo_robot().chain
    >>> c = scaled_condition(ch, np.radians([[0, 52, -19, 12, -15, -11], [0, 30, 0, 0, 0, 0]]))
    >>> bool(c[0] < 80 < c[1])  # the wrist is singular at q5 = 0
    True
    """
    from ....robot.kinematics import link_frames, tcp_frame

    F = link_frames(chain, q)
    p = tcp_frame(chain, q, F)[..., :3, 3]
    lever = np.linalg.norm(p - F[..., 2, :3, 3], axis=-1)
    J = jacobian(chain, q, F)
    J[..., :3, :] /= lever[..., None, None]
    return np.linalg.cond(J)


def near_singular(name: str, chain, targets, q: FloatArray, dq: FloatArray
                  ) -> list[NearSingular]:
    """Targets whose :func:`scaled_condition` passes the tolerance, with their largest
    joint correction ``dq`` (k, 6) [rad].

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> q = np.radians([[0, 40, 0, 20, 50, 10], [0, 40, 0, 20, 0.05, 10]])
    >>> [s.target for s in near_singular("P", load_demo_robot().chain, ["a", "b"], q,
    ...                                  np.zeros((2, 6)))]
    ['b']
    """
    cond = scaled_condition(chain, q)
    return [NearSingular(name, t, float(cond[i]), float(np.abs(dq[i]).max()))
            for i, t in enumerate(targets) if cond[i] > tol.singular_condition]
