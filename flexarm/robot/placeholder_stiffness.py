"""Placeholder joint stiffness scaled to the robot's size, and the first-mode band it promises.

A published robot description (URDF) carries no stiffness.  Until measurements identify
it (``flexarm diagnose --apply``), each joint gets a *placeholder* gear torsion
[N m/rad] from the robot's size, still marked ``source="placeholder"``.

Notes
-----
**The rule.**  A gear is sized for the torque its joint carries, and for geometrically
similar gears torque capacity and torsional stiffness both grow as the cube of their
size: the twist at the design torque is about the same for small and large robots.  So

* the design moment of the main axes is the weight of the robot at half its reach,
  ``tau = g m R / 2`` [N m] (``m`` the robot's mass [kg], ``R`` its reach [m]: the
  largest horizontal distance of the wrist centre from the joint-1 axis);
* joints 2 and 3 twist :data:`TWIST` [rad] under it: ``k_2 = tau / TWIST``;
* every joint takes a share of ``k_2`` (:data:`SHARES`, joint 1 included: its
  E-model spring also carries the lateral compliance of base and frame, which makes
  the sideways direction the weakest at the TCP);
* where the URDF gives every joint a ``<limit effort>`` (the joint's torque limit
  [N m]), joints 3 to n take ``effort_i / effort_2`` of ``k_2`` instead: a gear
  for a smaller torque is a smaller, softer gear.

``m`` is the datasheet mass given at import, else the sum of the URDF's ``<inertial>``
masses, else the mass of the CAD.  With ``J ~ m R^2`` the first mode then scales as
``f ~ sqrt(g / (TWIST R))``; the rule promises, for the first E-model frequency at the
mid-workspace pose (:func:`mid_workspace_pose`), the band ``F_ANCHOR sqrt(R_ANCHOR / R)``
times ``[1 / BAND_FACTOR, BAND_FACTOR]``.

**Published figures behind the numbers.**

* ABB IRB 4600-60/2.05 (425 kg, 60 kg payload, reach 2.05 m): A. Hosseini (2019),
  *Modelling and Measurement of Industrial Manipulators for High-Precision Contact
  Applications*, MSc thesis, KTH: the first eigenfrequency is "just over 10 Hz"
  (Sec. 4.3, Fig. 4.27; ~10 Hz in the conclusions, as in Pan et al.'s IRB 6400 chatter,
  Fig. 2.10), and the TCP deflects "more than 6 mm" in Y at pose P1 under 800 N
  (Sec. 4.1.1).  The thesis does **not** publish joint stiffnesses (its E-model takes ABB's
  calibrated values from a configuration file, App. A.9).  flexarm's demo arm of this
  class reproduces those figures with (6.5e5, 4e6, 4e6, 3e5, 2.5e5, 1.5e5) N m/rad
  (README: f1 7.6-16 Hz over P1-P3, 6.16 mm at P1): :data:`SHARES` are these values
  over joint 2's, and :data:`TWIST` puts ``k_2`` of a 425 kg, 2.05 m robot at 4.3e6
  N m/rad (7 % above the demo's).  :data:`F_ANCHOR` and :data:`R_ANCHOR` are the
  thesis's 10 Hz at 2.05 m.
* KUKA KR-series: Y. Zhao (2020), MSc thesis, Leibniz Universitaet Hannover (imes), as
  coded in its stiffness model, takes a KR 240-2-class joint compliance of
  1.52e-7 rad/(N m) about the joint axis (6.6e6 N m/rad) from A. Klimchik (2011), PhD
  thesis, Ecole Centrale de Nantes, p. 52, and scales joint compliance with the
  inverse of the robot's gravity moment ``m g R / 2``, as this rule does.  For a KR 210
  R2700 (1.25 t, 2.7 m) this rule gives 1.7e7 N m/rad on joints 2-3, 2.5 times that
  figure (a second-hand figure, and not per joint).  The joint-by-joint identifications
  of Dumas, Caro, Garnier and Furet (2011, "Joint stiffness identification of
  six-revolute industrial serial robots", KR240-2), Klimchik et al. (2013,
  "Identification of geometrical and elastostatic parameters of heavy industrial
  robots", KR-270) and Jubien, Abba and Gautier (2014, KR500, joints 1-2) were located
  but their tables could not be read here: no number of theirs is used.
* Universal Robots (strain-wave gears): no published joint stiffness or first-mode
  figure was found.  The UR10's own ``<limit effort>`` (330, 330, 150, 56, 56, 56 N m,
  ur_description) sets its joint shares; its band is the rule's scaling, not anchored
  by a measurement (``robot_class="lightweight"`` says so).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..fe.typing import ArrayLike, FloatArray
from .kinematics import Chain, link_frames

__all__ = ["G", "TWIST", "SHARES", "F_ANCHOR", "R_ANCHOR", "BAND_FACTOR",
           "LIGHTWEIGHT_KG_PER_M", "RobotSize", "PlaceholderStiffness", "reach",
           "mid_workspace_pose", "placeholder_stiffness", "example_chain"]

#: Standard gravity [m/s^2].
G = 9.80665
#: Twist [rad] of joints 2-3 under the design moment ``g m R / 2``.
TWIST = 1.0e-3
#: Stiffness of each joint over joint 2's, from the demo arm of the IRB 4600 class.
SHARES = (0.1625, 1.0, 1.0, 0.075, 0.0625, 0.0375)
#: First mode [Hz] of the anchor robot (IRB 4600) and its reach [m].
F_ANCHOR, R_ANCHOR = 10.0, 2.05
#: The promised band is the scaled anchor frequency times / over this factor.
BAND_FACTOR = 1.5
#: Below this mass per reach [kg/m] a robot is of the lightweight (collaborative) class.
LIGHTWEIGHT_KG_PER_M = 40.0
_GRID = 61  # (q2, q3) samples per joint for the reach and the mid-workspace pose
_MID_REACH = 0.6  # the mid-workspace wrist centre: this fraction of the reach out


@dataclass(frozen=True)
class RobotSize:
    """What the rule reads: ``mass`` [kg], ``reach`` [m] and the URDF's torque limits
    ``effort`` [N m] per joint (None: the file gives none, or not for every joint);
    ``mass_source`` says where the mass comes from ("datasheet", "URDF inertials",
    "CAD")."""

    mass: float
    reach: float
    effort: tuple[float, ...] | None = None
    mass_source: str = "datasheet"


@dataclass(frozen=True)
class PlaceholderStiffness:
    """Placeholder gear torsion per joint ``torsion`` [N m/rad] from ``size``, the
    design moment ``moment`` [N m], the robot class and the band [Hz] it promises for
    the first E-model frequency at the mid-workspace pose."""

    torsion: tuple[float, ...]
    size: RobotSize
    moment: float
    robot_class: str
    band_hz: tuple[float, float]

    def text(self) -> str:
        """One line: the size, the stiffness of joints 1-3 and the promised band."""
        main = ", ".join(f"{k:.2g}" for k in self.torsion[:3])
        effort = "; joints 3+ by the URDF efforts" if self.size.effort else ""
        return (f"size rule: {self.size.mass:.1f} kg ({self.size.mass_source}), reach "
                f"{self.size.reach:.2f} m -> joints 1-3 {main} N m/rad{effort}; "
                f"{self.robot_class} class: first E-model mode {self.band_hz[0]:.1f}-"
                f"{self.band_hz[1]:.1f} Hz at mid-workspace")


def _wrist_frames(chain: Chain, lower: FloatArray, upper: FloatArray):
    """Poses (g, g, n) on a (q2, q3) grid (other joints nearest 0 within limits) and the
    frames (g, g, n + 1, 4, 4) there."""
    lo, hi = np.maximum(lower, -math.pi), np.minimum(upper, math.pi)
    q = np.clip(np.zeros(chain.n_joints), lower, upper)
    Q = np.broadcast_to(q, (_GRID, _GRID, chain.n_joints)).copy()
    Q[..., 1], Q[..., 2] = np.meshgrid(np.linspace(lo[1], hi[1], _GRID),
                                       np.linspace(lo[2], hi[2], _GRID), indexing="ij")
    return Q, link_frames(chain, Q)


def _geometry(chain: Chain, lower: ArrayLike, upper: ArrayLike):
    """Grid poses, signed horizontal reach and height [m] of the wrist centre (the
    origin of joint 5, or of the last joint), and the elbow's height over the shoulder."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    if chain.n_joints < 3:
        raise ValueError(f"the size rule needs an arm of >= 3 joints, got {chain.n_joints}")
    Q, F = _wrist_frames(chain, lower, upper)
    wrist = min(5, chain.n_joints)
    F0 = link_frames(chain, np.clip(np.zeros(chain.n_joints), lower, upper))
    axis, o1, o2 = F0[1, :3, :3] @ chain.axes[0], F0[1, :3, 3], F0[2, :3, 3]
    axis = axis / np.linalg.norm(axis)

    def horizontal(v):
        return v - (v @ axis)[..., None] * axis

    out = horizontal(F0[wrist, :3, 3] - o1)  # the arm's forward direction at rest
    out = out / max(np.linalg.norm(out), 1e-12)
    w = F[..., wrist, :3, 3]
    r = horizontal(w - o1) @ out
    return Q, r, (w - o2) @ axis, (F[..., 3, :3, 3] - o2) @ axis



def example_chain() -> Chain:
    """A 6R arm for the examples: joint 1 about z 0.5 m above the base, a 0.2 m offset,
    a 0.8 m upper arm, a 0.3 + 0.4 m forearm to the wrist centre, a 0.1 m flange."""
    return Chain(origins=[[0, 0, 0.5], [0.2, 0, 0], [0, 0, 0.8], [0.3, 0, 0],
                          [0.4, 0, 0], [0.1, 0, 0]],
                 axes=[[0, 0, 1], [0, 1, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]],
                 parents=[0, 1, 2, 3, 4, 5])

def reach(chain: Chain, lower: ArrayLike, upper: ArrayLike) -> float:
    """The largest horizontal distance [m] of the wrist centre (origin of joint 5) from
    the joint-1 axis over joints 2 and 3 within their limits (the datasheet reach).

    Examples
    --------
    >>> ch = example_chain()  # a 6R arm: shoulder 0.5 m up, arms 0.8 and 0.7 m
    >>> round(reach(ch, [-3, -2, -3, -3, -2, -3], [3, 2, 3, 3, 2, 3]), 3)  # 0.2+0.8+0.3+0.4
    1.7
    """
    _, r, _, _ = _geometry(chain, lower, upper)
    return float(r.max())


def mid_workspace_pose(chain: Chain, lower: ArrayLike, upper: ArrayLike) -> FloatArray:
    """(n,) joint angles [rad] that put the wrist centre in front of the robot, at
    :data:`_MID_REACH` of its reach and the height of joint 2, elbow up; the other
    joints at 0 (or their nearest limit).

    Examples
    --------
    >>> ch = example_chain()  # a 6R arm: shoulder 0.5 m up, arms 0.8 and 0.7 m
    >>> q = mid_workspace_pose(ch, [-3, -2, -3, -3, -2, -3], [3, 2, 3, 3, 2, 3])
    >>> w = link_frames(ch, q)[5, :3, 3]
    >>> bool(abs(w[0] - 0.6 * 1.7) < 0.06 and abs(w[2] - 0.5) < 0.06)
    True
    """
    Q, r, h, elbow = _geometry(chain, lower, upper)
    R = float(r.max())
    # the elbow term (1 % of the reach) only breaks the tie between elbow up and down
    cost = (r / R - _MID_REACH) ** 2 + (h / R) ** 2 - 0.01 * elbow / R
    cost = np.where(r > 0, cost, np.inf)
    return Q[np.unravel_index(np.argmin(cost), cost.shape)].copy()


def placeholder_stiffness(size: RobotSize, n_joints: int = 6) -> PlaceholderStiffness:
    """The placeholder gear torsion of each joint [N m/rad] of a robot of ``size``.

    Parameters
    ----------
    size : RobotSize
        Mass [kg], reach [m] and the URDF's per-joint torque limits [N m] (or None).
    n_joints : int
        Joints of the arm; joints past the sixth take the last share.

    Examples
    --------
    >>> p = placeholder_stiffness(RobotSize(425.0, 2.05))  # IRB 4600-60/2.05
    >>> [f"{k:.3g}" for k in p.torsion], p.robot_class
    (['6.94e+05', '4.27e+06', '4.27e+06', '3.2e+05', '2.67e+05', '1.6e+05'], 'industrial')
    >>> [round(f, 2) for f in p.band_hz]
    [6.67, 15.0]
    >>> ur10 = placeholder_stiffness(RobotSize(28.9, 1.21, (330, 330, 150, 56, 56, 56)))
    >>> [f"{k:.3g}" for k in ur10.torsion], ur10.robot_class
    (['2.79e+04', '1.71e+05', '7.79e+04', '2.91e+04', '2.91e+04', '2.91e+04'], 'lightweight')
    """
    if not (size.mass > 0 and size.reach > 0):
        raise ValueError(f"the size rule needs a mass > 0 kg and a reach > 0 m, got "
                         f"{size.mass:g} kg and {size.reach:g} m")
    moment = G * size.mass * size.reach / 2
    k2 = moment / TWIST
    shares = np.array([SHARES[min(i, len(SHARES) - 1)] for i in range(n_joints)])
    effort = size.effort
    if effort is not None and len(effort) == n_joints and n_joints > 2 and min(effort) > 0:
        shares[2:] = np.asarray(effort[2:], float) / effort[1]
    else:
        effort = None
    kind = "lightweight" if size.mass / size.reach < LIGHTWEIGHT_KG_PER_M else "industrial"
    f_c = F_ANCHOR * math.sqrt(R_ANCHOR / size.reach)
    used = RobotSize(size.mass, size.reach, None if effort is None else tuple(effort),
                     size.mass_source)
    return PlaceholderStiffness(tuple(float(k) for k in k2 * shares), used, moment, kind,
                                (f_c / BAND_FACTOR, f_c * BAND_FACTOR))
