"""Unit quaternions ``[w, x, y, z]`` (scalar first, as in RAPID): products, rotation
matrices, RAPID's ``RelTool`` angles and SLERP.

All functions broadcast over leading axes: quaternions are ``(..., 4)`` and rotation
matrices ``(..., 3, 3)``.
"""

from __future__ import annotations

import numpy as np

from ..fe.typing import ArrayLike, FloatArray
from .tolerances import tol

__all__ = [
    "quat_normalize",
    "quat_multiply",
    "quat_conjugate",
    "quat_to_matrix",
    "quat_from_matrix",
    "quat_from_intrinsic_xyz",
    "quat_angle",
    "slerp",
]


def quat_normalize(q: ArrayLike) -> FloatArray:
    """Unit quaternions.

    Parameters
    ----------
    q : (..., 4) float
        ``[w, x, y, z]``; must be non-zero.

    Examples
    --------
    >>> quat_normalize([2.0, 0, 0, 0]).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    q = np.asarray(q, dtype=np.float64)
    if q.shape[-1:] != (4,):
        raise ValueError(f"quaternions must be (..., 4), got {q.shape}")
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    if np.any(norm == 0.0):
        raise ValueError("cannot normalise a zero quaternion")
    return q / norm


def quat_multiply(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Hamilton product ``a * b`` (apply ``b`` first, then ``a``), (..., 4) w-first.

    Examples
    --------
    >>> quat_multiply([0, 1, 0, 0], [0, 1, 0, 0]).tolist()  # i * i = -1
    [-1.0, 0.0, 0.0, 0.0]
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    aw, av = a[..., :1], a[..., 1:]
    bw, bv = b[..., :1], b[..., 1:]
    w = aw * bw - np.sum(av * bv, axis=-1, keepdims=True)
    v = aw * bv + bw * av + np.cross(av, bv)
    return np.concatenate([w, v], axis=-1)


def quat_conjugate(q: ArrayLike) -> FloatArray:
    """Conjugate (the inverse rotation for unit quaternions), (..., 4)."""
    q = np.asarray(q, dtype=np.float64)
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def quat_to_matrix(q: ArrayLike) -> FloatArray:
    """Rotation matrices of (normalised) quaternions.

    Parameters
    ----------
    q : (..., 4) float
        ``[w, x, y, z]``.

    Returns
    -------
    (..., 3, 3) float
        ``R`` with ``v_frame = R @ v_tool``: its columns are the tool x, y, z axes.

    Examples
    --------
    >>> R = quat_to_matrix([0.5, 0.5, 0.5, -0.5])  # thesis Target_70 ... Target_210
    >>> R[:, 2].round(12).tolist()  # flange z axis points along -y of the frame
    [0.0, -1.0, 0.0]
    """
    w, x, y, z = np.moveaxis(quat_normalize(q), -1, 0)
    R = np.stack([
        1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
    ], axis=-1)
    return R.reshape(R.shape[:-1] + (3, 3))


def quat_from_matrix(R: ArrayLike) -> FloatArray:
    """Unit quaternions ``[w, x, y, z]`` (with ``w >= 0``) of rotation matrices (..., 3, 3).

    Shepperd's choice of the largest pivot keeps it accurate for every rotation.

    Examples
    --------
    >>> q = quat_from_matrix(quat_to_matrix([0.5, 0.5, 0.5, -0.5]))
    >>> np.round(q, 12).tolist()
    [0.5, 0.5, 0.5, -0.5]
    """
    R = np.asarray(R, dtype=np.float64)
    if R.shape[-2:] != (3, 3):
        raise ValueError(f"rotation matrices must be (..., 3, 3), got {R.shape}")
    r00, r11, r22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    pivots = np.stack([r00 + r11 + r22, r00, r11, r22], axis=-1)
    k = np.argmax(pivots, axis=-1)
    # 4 * (the largest component)^2 for each of the four choices
    big = np.stack([1 + r00 + r11 + r22, 1 + r00 - r11 - r22,
                    1 - r00 + r11 - r22, 1 - r00 - r11 + r22], axis=-1)
    s = np.sqrt(np.maximum(np.take_along_axis(big, k[..., None], -1)[..., 0], 0.0))  # 2|c|
    d21, d02, d10 = R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], \
        R[..., 1, 0] - R[..., 0, 1]
    s01, s02, s12 = R[..., 0, 1] + R[..., 1, 0], R[..., 0, 2] + R[..., 2, 0], \
        R[..., 1, 2] + R[..., 2, 1]
    cands = np.stack([
        np.stack([s * s, d21, d02, d10], -1),
        np.stack([d21, s * s, s01, s02], -1),
        np.stack([d02, s01, s * s, s12], -1),
        np.stack([d10, s02, s12, s * s], -1),
    ], axis=-2)  # each row = 2|c| * q
    q = np.take_along_axis(cands, k[..., None, None], -2)[..., 0, :]
    q = quat_normalize(q)
    return np.where(q[..., :1] < 0, -q, q)


def quat_from_intrinsic_xyz(angles_deg: ArrayLike) -> FloatArray:
    """Rotation about x, then the new y, then the new z (degrees), as RAPID's ``RelTool``.

    Examples
    --------
    >>> np.round(quat_from_intrinsic_xyz([0, 0, 90]), 12).tolist()
    [0.707106781187, 0.0, 0.0, 0.707106781187]
    """
    a = np.radians(np.asarray(angles_deg, dtype=np.float64))
    if a.shape[-1:] != (3,):
        raise ValueError(f"angles must be (..., 3), got {a.shape}")
    half = a / 2
    zeros = np.zeros_like(half[..., 0])
    qx = np.stack([np.cos(half[..., 0]), np.sin(half[..., 0]), zeros, zeros], -1)
    qy = np.stack([np.cos(half[..., 1]), zeros, np.sin(half[..., 1]), zeros], -1)
    qz = np.stack([np.cos(half[..., 2]), zeros, zeros, np.sin(half[..., 2])], -1)
    return quat_multiply(quat_multiply(qx, qy), qz)


def quat_angle(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Rotation angle [rad] between orientations (sign of the quaternions ignored).

    Examples
    --------
    >>> float(np.degrees(quat_angle([1, 0, 0, 0], [0, 0, 0, 1])))
    180.0
    """
    dot = np.abs(np.sum(quat_normalize(a) * quat_normalize(b), axis=-1))
    return 2.0 * np.arccos(np.clip(dot, 0.0, 1.0))


def slerp(q0: ArrayLike, q1: ArrayLike, t: ArrayLike) -> FloatArray:
    """Spherical linear interpolation along the shorter rotation.

    Parameters
    ----------
    q0, q1 : (..., 4) float
        End orientations ``[w, x, y, z]`` (normalised here).
    t : (...) float
        Fractions in [0, 1]; broadcast against the leading shape of ``q0``/``q1``.

    Returns
    -------
    (..., 4) float
        Unit quaternions; ``t = 0`` gives ``q0``, ``t = 1`` gives ``q1`` or ``-q1``
        (the same rotation), whichever is nearer to ``q0``.

    Examples
    --------
    >>> q = slerp([1, 0, 0, 0], [0, 0, 0, 1], [0.0, 0.5, 1.0])  # 0 -> 180 deg about z
    >>> np.round(q, 12).tolist()
    [[1.0, 0.0, 0.0, 0.0], [0.707106781187, 0.0, 0.0, 0.707106781187], [0.0, 0.0, 0.0, 1.0]]
    """
    q0 = quat_normalize(q0)
    q1 = quat_normalize(q1)
    t = np.asarray(t, dtype=np.float64)
    dot = np.sum(q0 * q1, axis=-1)
    q1 = np.where((dot < 0)[..., None], -q1, q1)
    theta = np.arccos(np.clip(np.abs(dot), -1.0, 1.0))  # half the rotation angle
    small = theta < tol.slerp_small_angle
    sin_theta = np.where(small, 1.0, np.sin(theta))
    w0 = np.where(small, 1.0 - t, np.sin((1.0 - t) * theta) / sin_theta)
    w1 = np.where(small, t, np.sin(t * theta) / sin_theta)
    return quat_normalize(w0[..., None] * q0 + w1[..., None] * q1)
