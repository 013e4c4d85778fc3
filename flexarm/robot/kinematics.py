"""Kinematics of a tree of revolute joints: FK, geometric Jacobian, motor angles.

Frames follow DESIGN §3: body 0 is the base (frame ``B``); body ``i >= 1`` is the
child of joint ``i - 1`` and carries the link frame ``L_i``.  Joint ``j`` sits at
``origins[j]`` (with a fixed rotation ``origin_R[j]``) in its parent's frame and
turns its child about ``axes[j]`` (a unit vector in the child frame, which equals
the parent frame at zero angle).  Everything is batched over a leading pose axis.

Inverse kinematics lives in :mod:`flexarm.robot.ik`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..fe.typing import ArrayLike, FloatArray

__all__ = [
    "Chain",
    "axis_angle_matrix",
    "rpy_matrix",
    "link_frames",
    "tcp_frame",
    "jacobian",
    "joint_to_motor",
    "motor_to_joint",
]


def rpy_matrix(rpy: ArrayLike) -> FloatArray:
    """(3, 3) rotation of URDF roll-pitch-yaw angles [rad]: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    r, p, y = np.asarray(rpy, dtype=float)
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def axis_angle_matrix(axis: ArrayLike, angles: ArrayLike) -> FloatArray:
    """(..., 3, 3) rotations by ``angles`` [rad] about the unit ``axis`` (Rodrigues)."""
    a = np.asarray(axis, dtype=float)
    t = np.asarray(angles, dtype=float)[..., None, None]
    S = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * S + (1 - np.cos(t)) * (S @ S)


@dataclass(frozen=True, eq=False)
class Chain:
    """Kinematic tree of ``n`` revolute joints and ``n + 1`` bodies.

    Parameters
    ----------
    origins : (n, 3) float
        Joint positions in the parent body frame [m].
    axes : (n, 3) float
        Unit joint axes in the child frame (= parent frame rotated by ``origin_R``).
    parents : (n,) int
        Parent body of each joint (0 = base); joint ``j``'s child is body ``j + 1``.
        Parents come before children (``parents[j] <= j``).
    origin_R : (n, 3, 3) float, optional
        Fixed rotation of each joint frame in its parent (URDF ``rpy``); identity by default.
    tool : (4, 4) float, optional
        TCP frame in the frame of body ``tcp_body`` [m].
    tcp_body : int, optional
        Body carrying the tool; the last body by default.
    gear_ratios : (n,) float, optional
        Motor angle per joint angle [-].
    wrist_coupling : (3, 3) float, optional
        Coupling of the last three joints' motors: ``motor = ratio * (C @ q)`` on that block.
    """

    origins: FloatArray
    axes: FloatArray
    parents: np.ndarray
    origin_R: FloatArray | None = None
    tool: FloatArray = field(default_factory=lambda: np.eye(4))
    tcp_body: int = -1
    gear_ratios: FloatArray | None = None
    wrist_coupling: FloatArray | None = None

    def __post_init__(self) -> None:
        origins = np.asarray(self.origins, dtype=float).reshape(-1, 3)
        n = len(origins)
        axes = np.asarray(self.axes, dtype=float).reshape(n, 3)
        parents = np.asarray(self.parents, dtype=np.int64).reshape(n)
        if np.any(parents > np.arange(n)) or np.any(parents < 0):
            raise ValueError(f"parents must satisfy 0 <= parents[j] <= j, got {parents.tolist()}")
        R0 = np.broadcast_to(np.eye(3), (n, 3, 3)) if self.origin_R is None else self.origin_R
        tcp = n if self.tcp_body < 0 else int(self.tcp_body)
        ratios = np.ones(n) if self.gear_ratios is None else np.asarray(self.gear_ratios, float)
        for name, val in (
            ("origins", origins),
            ("axes", axes),
            ("parents", parents),
            ("origin_R", np.array(R0, dtype=float)),
            ("tool", np.asarray(self.tool, dtype=float).reshape(4, 4)),
            ("gear_ratios", ratios.reshape(n)),
        ):
            val.setflags(write=False)
            object.__setattr__(self, name, val)
        object.__setattr__(self, "tcp_body", tcp)

    @property
    def n_joints(self) -> int:
        return len(self.origins)

    def ancestors(self, body: int) -> list[int]:
        """Joints between the base and ``body`` (base first)."""
        out = []
        while body > 0:
            out.append(body - 1)
            body = int(self.parents[body - 1])
        return out[::-1]


def link_frames(chain: Chain, q: ArrayLike) -> FloatArray:
    """Body frames in the base frame at joint angles ``q``.

    Parameters
    ----------
    chain : Chain
    q : (..., n) float
        Joint angles [rad].

    Returns
    -------
    (..., n + 1, 4, 4) float
        Homogeneous transforms base <- body; entry 0 is the identity (base).

    Examples
    --------
    >>> ch = Chain(origins=[[0, 0, 1.0], [1.0, 0, 0]], axes=[[0, 0, 1], [0, 1, 0]], parents=[0, 1])
    >>> link_frames(ch, [np.pi / 2, 0.0])[2, :3, 3].round(12).tolist()
    [0.0, 1.0, 1.0]
    """
    q = np.asarray(q, dtype=float)
    batch = q.shape[:-1]
    if q.shape[-1] != chain.n_joints:
        raise ValueError(f"q must be (..., {chain.n_joints}), got {q.shape}")
    F = np.zeros(batch + (chain.n_joints + 1, 4, 4))
    F[..., :, :, :] = np.eye(4)
    for j in range(chain.n_joints):
        P = F[..., chain.parents[j], :, :]
        Rj = chain.origin_R[j] @ axis_angle_matrix(chain.axes[j], q[..., j])
        F[..., j + 1, :3, :3] = P[..., :3, :3] @ Rj
        F[..., j + 1, :3, 3] = P[..., :3, :3] @ chain.origins[j] + P[..., :3, 3]
    return F


def tcp_frame(chain: Chain, q: ArrayLike, frames: FloatArray | None = None) -> FloatArray:
    """(..., 4, 4) TCP frame in the base frame at joint angles ``q`` [rad]."""
    F = link_frames(chain, q) if frames is None else frames
    return F[..., chain.tcp_body, :, :] @ chain.tool


def jacobian(chain: Chain, q: ArrayLike, frames: FloatArray | None = None) -> FloatArray:
    """Geometric Jacobian of the TCP in the base frame.

    Returns
    -------
    (..., 6, n) float
        Rows (v_x, v_y, v_z, omega_x, omega_y, omega_z) [m/rad, 1] per joint rate;
        zero columns for joints not between the base and the tool.
    """
    F = link_frames(chain, q) if frames is None else frames
    p_tcp = (F[..., chain.tcp_body, :, :] @ chain.tool)[..., :3, 3]
    J = np.zeros(F.shape[:-3] + (6, chain.n_joints))
    for j in chain.ancestors(chain.tcp_body):
        Fj = F[..., j + 1, :, :]
        z = Fj[..., :3, :3] @ chain.axes[j]
        J[..., :3, j] = np.cross(z, p_tcp - Fj[..., :3, 3])
        J[..., 3:, j] = z
    return J


def _motor_matrix(chain: Chain) -> FloatArray:
    n = chain.n_joints
    C = np.eye(n)
    if chain.wrist_coupling is not None:
        C[n - 3 :, n - 3 :] = np.asarray(chain.wrist_coupling, dtype=float)
    return chain.gear_ratios[:, None] * C


def joint_to_motor(chain: Chain, q: ArrayLike) -> FloatArray:
    """(..., n) motor angles [rad] of joint angles ``q`` (gear ratios, wrist coupling)."""
    return np.asarray(q, dtype=float) @ _motor_matrix(chain).T


def motor_to_joint(chain: Chain, theta_m: ArrayLike) -> FloatArray:
    """(..., n) joint angles [rad] of motor angles ``theta_m`` (inverse of joint_to_motor)."""
    return np.linalg.solve(_motor_matrix(chain), np.asarray(theta_m, dtype=float).T).T
