"""Small-motion kinematics shared by every layer: cross-product matrices and rigid transport."""

from __future__ import annotations

import numpy as np

from .typing import ArrayLike, FloatArray

__all__ = ["skew", "rigid_transport"]


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
