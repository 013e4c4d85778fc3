"""Small-motion kinematics shared by every layer: cross-product matrices and rigid transport."""

from __future__ import annotations

import numpy as np

from .typing import ArrayLike, FloatArray

__all__ = ["skew", "cross", "rigid_transport"]


def skew(r: ArrayLike) -> FloatArray:
    """(..., 3, 3) cross-product matrix: ``skew(r) @ v == cross(r, v)``.

    Examples
    --------
    >>> skew([1.0, 0.0, 0.0]) @ [0.0, 1.0, 0.0]
    array([0., 0., 1.])
    """
    r = np.asarray(r, dtype=float)
    S = np.zeros(r.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2] = -r[..., 2], r[..., 1]
    S[..., 1, 0], S[..., 1, 2] = r[..., 2], -r[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -r[..., 1], r[..., 0]
    return S


def cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """(..., 3) ``a x b`` of two stacks of 3-vectors (broadcast), as ``np.cross`` gives it
    without its axis handling, which costs more than the product on the small stacks of a
    pose loop.

    Examples
    --------
    >>> cross(np.array([1.0, 0.0, 0.0]), np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]))
    array([[ 0.,  0.,  1.],
           [ 0., -2.,  0.]])
    """
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def rigid_transport(r: ArrayLike) -> FloatArray:
    """(..., 6, 6) small motion of a point at offset ``r`` [m] from a 6-DOF reference node.

    ``[u_p; theta_p] = [[I, -S(r)], [0, I]] [u; theta]`` (u_p = u + theta x r).
    The first three rows alone are the translation of the point.

    Examples
    --------
    >>> rigid_transport([1.0, 0.0, 0.0])[:3] @ [0, 0, 0, 0, 0, 1.0]
    array([0., 1., 0.])
    """
    r = np.asarray(r, dtype=float)
    A = np.zeros(r.shape[:-1] + (6, 6))
    A[..., :3, :3] = np.eye(3)
    A[..., 3:, 3:] = np.eye(3)
    A[..., :3, 3:] = -skew(r)
    return A
