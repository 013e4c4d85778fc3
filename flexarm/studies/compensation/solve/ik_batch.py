"""Small rigid motions and inverse kinematics for many targets at once.

A compensated target differs from the programmed one by a deflection of a few
millimetres and milliradians, so one Newton step per target from the previous solution
nearly reaches it: :func:`newton_ik` solves every target of a program in one batched
loop (Jacobians stacked ``(n, 6, 6)``), which the closed form of
:func:`flexarm.robot.ik.ik_analytic` (one target, eight branches) cannot do at the
speed a thousand-target program needs.  The branch is the seed's: the caller seeds
from solutions with the programmed configuration.

Poses are ``(n, 4, 4)`` frames [m]; small motions are 6-vectors (translation [m],
rotation vector [rad]) in the base frame, as everywhere in flexarm.
"""

from __future__ import annotations

import numpy as np

from ....fe.geometry import skew
from ....fe.typing import ArrayLike, FloatArray
from ....robot.kinematics import Chain, jacobian, link_frames, tcp_frame
from ....robot.quaternions import quat_from_matrix
from ...tolerances import tol

__all__ = ["rotation_vectors", "rotation_matrices", "pose_errors", "displaced", "newton_ik"]


def rotation_vectors(R: ArrayLike) -> FloatArray:
    """(..., 3) rotation vectors [rad] of rotation matrices (..., 3, 3) (the log map).

    Through the quaternion, so that it is accurate for every angle up to pi.

    Examples
    --------
    >>> rotation_vectors(rotation_matrices([0.0, 0.0, 0.3])).round(12).tolist()
    [0.0, 0.0, 0.3]
    """
    q = quat_from_matrix(R)
    s = np.linalg.norm(q[..., 1:], axis=-1, keepdims=True)
    angle = 2.0 * np.arctan2(s, q[..., :1])
    # angle / s -> 2 as s -> 0 (w >= 0 from quat_from_matrix)
    factor = np.where(s > 0, angle / np.where(s > 0, s, 1.0), 2.0)
    return factor * q[..., 1:]


def rotation_matrices(v: ArrayLike) -> FloatArray:
    """(..., 3, 3) rotations by the rotation vectors ``v`` (..., 3) [rad] (Rodrigues).

    Examples
    --------
    >>> rotation_matrices([0.0, 0.0, np.pi / 2])[:, 0].round(12).tolist()
    [0.0, 1.0, 0.0]
    """
    v = np.asarray(v, dtype=float)
    t = np.linalg.norm(v, axis=-1)[..., None, None]
    S = skew(v)
    small = t < 1e-8
    a = np.where(small, 1.0 - t**2 / 6.0, np.sin(t) / np.where(small, 1.0, t))
    b = np.where(small, 0.5 - t**2 / 24.0, (1.0 - np.cos(t)) / np.where(small, 1.0, t**2))
    return np.eye(3) + a * S + b * (S @ S)


def pose_errors(T_from: ArrayLike, T_to: ArrayLike) -> FloatArray:
    """(..., 6) small motion taking frames ``T_from`` to ``T_to`` (..., 4, 4) [m, rad].

    Translation ``p_to - p_from`` and the rotation vector of ``R_to R_from^T``, both in
    the base frame: the inverse of :func:`displaced`.

    Examples
    --------
    >>> T = np.eye(4)
    >>> d = np.array([1e-3, 0, 0, 0, 0, 2e-3])
    >>> pose_errors(T, displaced(T, d)).round(15).tolist() == d.tolist()
    True
    """
    A = np.asarray(T_from, dtype=float)
    B = np.asarray(T_to, dtype=float)
    rot = rotation_vectors(B[..., :3, :3] @ np.swapaxes(A[..., :3, :3], -1, -2))
    return np.concatenate([B[..., :3, 3] - A[..., :3, 3], rot], axis=-1)


def displaced(T: ArrayLike, d: ArrayLike) -> FloatArray:
    """(..., 4, 4) frames ``T`` moved by small motions ``d`` (..., 6) [m, rad], base frame.

    ``p + d[:3]`` and ``exp(d[3:]) R``: how a deflection moves a tool frame.

    Examples
    --------
    >>> displaced(np.eye(4), [0.0, 0.0, -1e-3, 0, 0, 0])[:3, 3].tolist()
    [0.0, 0.0, -0.001]
    """
    T = np.array(T, dtype=float)
    d = np.asarray(d, dtype=float)
    T[..., :3, 3] += d[..., :3]
    T[..., :3, :3] = rotation_matrices(d[..., 3:]) @ T[..., :3, :3]
    return T


def newton_ik(chain: Chain, T: ArrayLike, q0: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Joint angles reaching every frame of ``T`` (n, 4, 4) [m], by batched Newton steps.

    Parameters
    ----------
    chain : Chain
        Kinematics whose ``tool`` is the frame ``T`` targets (6 joints on the TCP path).
    T : (n, 4, 4) float
        Target frames, base frame [m].
    q0 : (n, 6) float
        Seeds [rad]; the solution stays on the seed's branch.

    Returns
    -------
    q : (n, 6) float
        Joint angles [rad] (joint limits are the caller's to check).
    error : (n,) float
        Remaining pose error ``|(dp, dtheta)|`` [m, rad]; above
        :attr:`~flexarm.studies.tolerances.Tolerances.ik_pose_error` the target is out of
        reach (or singular) from that seed.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> ch = load_demo_robot().chain
    >>> q = np.radians([[0, 52, -19, 12, -15, -11], [10, 30, 0, 45, 40, 60]])
    >>> sol, err = newton_ik(ch, tcp_frame(ch, q), q + 0.05)
    >>> bool(np.allclose(sol, q) and err.max() < 1e-10)
    True
    """
    T = np.asarray(T, dtype=float)
    q = np.array(q0, dtype=float)
    err = np.full(len(q), np.inf)
    active = np.ones(len(q), dtype=bool)
    for _ in range(tol.ik_max_iter):
        idx = np.flatnonzero(active)
        if len(idx) == 0:
            break
        F = link_frames(chain, q[idx])
        e = pose_errors(tcp_frame(chain, q[idx], F), T[idx])
        err[idx] = np.linalg.norm(e, axis=-1)
        done = err[idx] < tol.ik_pose_error
        active[idx[done]] = False
        idx, e, F = idx[~done], e[~done], F[~done]
        if len(idx) == 0:
            break
        J = jacobian(chain, q[idx], F)
        JJt = J @ np.swapaxes(J, -1, -2) + tol.ik_damping * np.eye(6)
        dq = np.einsum("nji,nj->ni", J, np.linalg.solve(JJt, e[..., None])[..., 0])
        big = np.abs(dq).max(axis=-1, keepdims=True)
        q[idx] += dq * np.minimum(1.0, tol.ik_max_step / np.maximum(big, 1e-300))
    return q, err
