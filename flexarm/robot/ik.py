"""Inverse kinematics: closed form for the spherical-wrist 6R family, DLS in general.

The closed form covers arms shaped like the IRB 4600 (DESIGN §4): joint 1 about the
base z axis, joints 2 and 3 parallel and perpendicular to it, every offset in the
plane of the arm, joint 4 along the forearm, and joints 4–6 meeting in one wrist
centre (axes x, y, x of the link frames at zero angles).  Anything else goes
through damped least squares from a start pose.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fe.errors import ConvergenceError
from ..fe.typing import ArrayLike, FloatArray
from .kinematics import Chain, axis_angle_matrix, jacobian, link_frames, tcp_frame

__all__ = ["IKConfig", "is_spherical_wrist_arm", "ik_analytic", "ik_dls", "ik", "pose_error"]

_EX, _EY, _EZ = np.eye(3)
_GEOM_TOL = 1e-12  # exact structural zeros of a description (not a numerical tolerance)


@dataclass(frozen=True)
class IKConfig:
    """Branch of the closed-form solution.

    Parameters
    ----------
    shoulder : {"front", "back"}
        Wrist centre in front of joint 1 (``q1`` points at it) or behind.
    elbow : {"up", "down"}
    wrist : {"noflip", "flip"}
        ``q5 >= 0`` (noflip) or ``q5 < 0`` (flip).
    """

    shoulder: str = "front"
    elbow: str = "up"
    wrist: str = "noflip"

    @staticmethod
    def all() -> list[IKConfig]:
        return [
            IKConfig(s, e, w)
            for s in ("front", "back")
            for e in ("up", "down")
            for w in ("noflip", "flip")
        ]


def is_spherical_wrist_arm(chain: Chain) -> bool:
    """True if the closed form of :func:`ik_analytic` applies to ``chain``."""
    if chain.n_joints != 6 or chain.tcp_body != 6 or np.any(chain.parents != np.arange(6)):
        return False
    if not np.allclose(chain.origin_R, np.eye(3), atol=_GEOM_TOL):
        return False
    want = np.array([_EZ, _EY, _EY, _EX, _EY, _EX])
    if not np.allclose(chain.axes, want, atol=_GEOM_TOL):
        return False
    o = chain.origins
    in_plane = np.abs(o[:, 1]).max() < _GEOM_TOL
    on_axes = abs(o[0, 0]) < _GEOM_TOL and np.abs(o[4:, 2]).max() < _GEOM_TOL
    return bool(in_plane and on_axes)


def _wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def ik_analytic(chain: Chain, target: ArrayLike, config: IKConfig = IKConfig()) -> FloatArray:
    """Closed-form joint angles reaching a TCP frame.

    Parameters
    ----------
    chain : Chain
        A spherical-wrist arm (:func:`is_spherical_wrist_arm`).
    target : (4, 4) float
        TCP frame in the base frame [m].
    config : IKConfig

    Returns
    -------
    (6,) float
        Joint angles [rad] in (-pi, pi]; NaN where the target is out of reach.
    """
    if not is_spherical_wrist_arm(chain):
        raise ValueError("ik_analytic needs a spherical-wrist 6R arm; use ik_dls")
    T = np.asarray(target, dtype=float)
    o = chain.origins
    R6 = T[:3, :3] @ chain.tool[:3, :3].T
    p6 = T[:3, 3] - R6 @ chain.tool[:3, 3]
    # joint 6's offset lies on its own axis, so it is the same in link 5 and 6 frames
    pw = p6 - R6 @ o[5]
    d1 = o[0, 2]
    a1 = o[1, 0]
    h_base = o[1, 2]
    # joints 2/3 in the arm plane; angles measured from z towards x (Ry adds angles)
    a2 = np.array([o[2, 0], o[2, 2]])
    w3 = np.array([o[3, 0] + o[4, 0], o[3, 2]])
    q1 = np.arctan2(pw[1], pw[0]) + (np.pi if config.shoulder == "back" else 0.0)
    c1, s1 = np.cos(q1), np.sin(q1)
    x = c1 * pw[0] + s1 * pw[1] - a1
    z = pw[2] - d1 - h_base
    L2, phi2 = np.hypot(*a2), np.arctan2(a2[0], a2[1])
    L3, phi3 = np.hypot(*w3), np.arctan2(w3[0], w3[1])
    cos_rel = (x * x + z * z - L2 * L2 - L3 * L3) / (2 * L2 * L3)
    if abs(cos_rel) > 1:
        return np.full(6, np.nan)
    rel = np.arccos(cos_rel) * (1.0 if config.elbow == "down" else -1.0)
    # wrist = L2 e(q2 + phi2) + L3 e(q2 + phi2 + rel), e(t) = (sin t, cos t)
    beta = np.arctan2(L3 * np.sin(rel), L2 + L3 * np.cos(rel))
    q2 = np.arctan2(x, z) - beta - phi2
    q3 = rel + phi2 - phi3
    R3 = axis_angle_matrix(_EZ, q1) @ axis_angle_matrix(_EY, q2 + q3)
    W = R3.T @ R6  # = Rx(q4) Ry(q5) Rx(q6)
    sb = np.hypot(W[1, 0], W[2, 0])
    if config.wrist == "flip":
        sb = -sb
    q5 = np.arctan2(sb, W[0, 0])
    if abs(sb) < 1e-12:  # wrist singularity: only q4 + q6 is defined; keep q4 = 0
        q4, q6 = 0.0, np.arctan2(-W[1, 2], W[1, 1])
    else:
        q4 = np.arctan2(W[1, 0] / sb, -W[2, 0] / sb)
        q6 = np.arctan2(W[0, 1] / sb, W[0, 2] / sb)
    return _wrap(np.array([q1, q2, q3, q4, q5, q6]))


def pose_error(current: FloatArray, target: FloatArray) -> FloatArray:
    """(6,) small-motion error (translation [m], rotation vector [rad]) from current to target."""
    dp = target[:3, 3] - current[:3, 3]
    Rerr = target[:3, :3] @ current[:3, :3].T
    angle = np.arccos(np.clip((np.trace(Rerr) - 1) / 2, -1.0, 1.0))
    v = np.array([Rerr[2, 1] - Rerr[1, 2], Rerr[0, 2] - Rerr[2, 0], Rerr[1, 0] - Rerr[0, 1]])
    s = np.sin(angle)
    rot = v / 2 if s < 1e-12 else v * angle / (2 * s)
    return np.concatenate([dp, rot])


def ik_dls(
    chain: Chain,
    target: ArrayLike,
    q0: ArrayLike,
    damping: float = 1e-3,
    tol: float = 1e-12,
    max_iter: int = 200,
) -> FloatArray:
    """Damped least-squares IK from the start angles ``q0`` [rad].

    Iterates ``dq = J^T (J J^T + damping^2 I)^-1 e`` on the 6-D pose error ``e``
    until ``|e| < tol``; raises :class:`ConvergenceError` otherwise.
    """
    T = np.asarray(target, dtype=float)
    q = np.array(q0, dtype=float)
    for _ in range(max_iter):
        F = link_frames(chain, q)
        e = pose_error(tcp_frame(chain, q, F), T)
        if np.linalg.norm(e) < tol:
            return q
        J = jacobian(chain, q, F)
        q = q + J.T @ np.linalg.solve(J @ J.T + damping**2 * np.eye(6), e)
    raise ConvergenceError(f"ik_dls: pose error {np.linalg.norm(e):.3g} after {max_iter} steps")


def ik(
    chain: Chain,
    target: ArrayLike,
    config: IKConfig | None = None,
    q_near: ArrayLike | None = None,
    lower: ArrayLike | None = None,
    upper: ArrayLike | None = None,
) -> FloatArray:
    """Joint angles [rad] reaching the TCP frame ``target`` (4, 4).

    Closed form where it applies (``config``, or the reachable branch nearest
    ``q_near`` within ``lower``/``upper``), polished by a DLS step; otherwise DLS from
    ``q_near`` (zeros by default).

    Examples
    --------
    >>> ch = Chain(origins=[[0, 0, .495], [.175, 0, 0], [0, 0, .9], [0, 0, .175],
    ...                     [.96, 0, 0], [.135, 0, 0]],
    ...            axes=[[0, 0, 1], [0, 1, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]],
    ...            parents=range(6))
    >>> q = np.array([0.1, 0.5, -0.3, 0.2, 0.7, -0.4])
    >>> bool(np.allclose(ik(ch, tcp_frame(ch, q), q_near=q), q))
    True
    """
    T = np.asarray(target, dtype=float)
    n = chain.n_joints
    near = np.zeros(n) if q_near is None else np.asarray(q_near, dtype=float)
    if not is_spherical_wrist_arm(chain):
        return ik_dls(chain, T, near)
    lo = np.full(n, -np.inf) if lower is None else np.asarray(lower, dtype=float)
    hi = np.full(n, np.inf) if upper is None else np.asarray(upper, dtype=float)
    configs = [config] if config is not None else IKConfig.all()
    best, best_cost = None, np.inf
    for c in configs:
        q = ik_analytic(chain, T, c)
        if np.any(np.isnan(q)):
            continue
        # joints 4 and 6 may turn more than a revolution: take the turn nearest q_near
        for j in (3, 5):
            q[j] += 2 * np.pi * np.round((near[j] - q[j]) / (2 * np.pi))
        if np.any(q < lo) or np.any(q > hi):
            continue
        cost = float(np.sum((q - near) ** 2))
        if cost < best_cost:
            best, best_cost = q, cost
    if best is None:
        raise ValueError("target TCP frame is out of reach (or outside the joint limits)")
    return best
