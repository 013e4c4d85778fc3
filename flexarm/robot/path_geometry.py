"""Geometry of TCP path segments: circles and spheres through points, and the sampling
of one straight or circular move.

Everything here is independent of RAPID: positions are plain arrays [mm, or any length
unit where noted] and orientations unit quaternions ``[w, x, y, z]``.  The procedure
sampler in :mod:`flexarm.robot.paths` strings segments together and re-exports the
public circle and sphere functions.
"""

from __future__ import annotations

import math

import numpy as np

from ..fe.typing import ArrayLike, FloatArray
from .quaternions import quat_angle, slerp
from .tolerances import tol

__all__ = ["circle_through", "fit_circle", "fit_sphere", "sample_line", "sample_arc"]


# ----------------------------------------------------------------------------- circles

def circle_through(p1: ArrayLike, p2: ArrayLike, p3: ArrayLike) -> tuple[FloatArray, FloatArray,
                                                                          FloatArray]:
    """The circle through three points, exactly.

    Parameters
    ----------
    p1, p2, p3 : (..., 3) float
        Points [any length unit], e.g. a ``MoveC``'s start, ``CirPoint`` and ``ToPoint``.

    Returns
    -------
    centre : (..., 3) float
        Centre [unit of the points].
    normal : (..., 3) float
        Unit normal oriented so that p1 -> p2 -> p3 runs counter-clockwise about it.
    radius : (...) float
        Radius [unit of the points].

    Raises
    ------
    ValueError
        If the points are (nearly) collinear or coincide.

    Examples
    --------
    >>> c, n, r = circle_through([1, 0, 5], [0, 1, 5], [-1, 0, 5])
    >>> c.tolist(), n.tolist(), float(r)
    ([0.0, 0.0, 5.0], [0.0, 0.0, 1.0], 1.0)
    """
    p1, p2, p3 = (np.asarray(p, dtype=np.float64) for p in (p1, p2, p3))
    a = p1 - p3
    b = p2 - p3
    axb = np.cross(a, b)
    area2 = np.sum(axb * axb, axis=-1)
    la = np.linalg.norm(a, axis=-1)
    lb = np.linalg.norm(b, axis=-1)
    if np.any(np.sqrt(area2) <= tol.collinear * la * lb) or np.any(la * lb == 0):
        raise ValueError("the three points are collinear or coincide: no unique circle")
    aa = np.sum(a * a, axis=-1)[..., None]
    bb = np.sum(b * b, axis=-1)[..., None]
    centre = p3 + np.cross(aa * b - bb * a, axb) / (2.0 * area2[..., None])
    radius = np.linalg.norm(p1 - centre, axis=-1)
    # p1 -> p2 -> p3 counter-clockwise about n: n along (p2 - p1) x (p3 - p2) = a x b
    normal = axb / np.sqrt(area2)[..., None]
    return centre, normal, radius


def _as_points(points: ArrayLike, n_min: int) -> FloatArray:
    P = np.asarray(points, dtype=np.float64)
    if P.ndim != 2 or P.shape[1] != 3 or len(P) < n_min:
        raise ValueError(f"points must be (n, 3) with n >= {n_min}, got {P.shape}")
    return P


def fit_circle(points: ArrayLike) -> tuple[FloatArray, FloatArray, float]:
    """Least-squares circle in 3-D: best plane (SVD), then an algebraic circle fit in it.

    Parameters
    ----------
    points : (n, 3) float
        n >= 3 points [any length unit], ideally in traversal order (it fixes the sign of
        the normal).

    Returns
    -------
    centre : (3,) float
        Centre [unit of the points].
    normal : (3,) float
        Unit plane normal, oriented so the points run counter-clockwise about it.
    radius : float
        Radius [unit of the points].

    Notes
    -----
    In-plane the fit solves ``x^2 + y^2 = 2 a x + 2 b y + k`` in the linear least-squares
    sense (Kasa fit; exact for points on a circle), ``r^2 = k + a^2 + b^2``.  Points are
    centred first for conditioning.

    Examples
    --------
    >>> phi = np.linspace(0, 1.5 * np.pi, 7)
    >>> pts = np.c_[3 + 2 * np.cos(phi), -1 + 2 * np.sin(phi), np.full(7, 4.0)]
    >>> c, n, r = fit_circle(pts)
    >>> np.round(c, 12).tolist(), np.round(n, 12).tolist(), round(r, 12)
    ([3.0, -1.0, 4.0], [0.0, 0.0, 1.0], 2.0)
    """
    P = _as_points(points, 3)
    mean = P.mean(axis=0)
    X = P - mean
    _, S, Vt = np.linalg.svd(X, full_matrices=False)
    if S[1] <= tol.collinear * S[0]:
        raise ValueError("the points are collinear: no unique circle")
    e1, normal = Vt[0], Vt[2]
    e2 = np.cross(normal, e1)
    u, v = X @ e1, X @ e2
    A = np.c_[2 * u, 2 * v, np.ones(len(P))]
    (a, b, k), *_ = np.linalg.lstsq(A, u * u + v * v, rcond=None)
    radius = float(np.sqrt(k + a * a + b * b))
    centre = mean + a * e1 + b * e2
    turn = np.sum(np.cross(P[:-1] - centre, P[1:] - centre) @ normal)
    if turn < 0:
        normal = -normal
    return centre, normal, radius


def fit_sphere(points: ArrayLike) -> tuple[FloatArray, float]:
    """Linear least-squares sphere: ``|p|^2 = 2 c . p + k``, ``r^2 = k + |c|^2``.

    Parameters
    ----------
    points : (n, 3) float
        n >= 4 points [any length unit], not all in one plane.

    Returns
    -------
    centre : (3,) float
        Centre [unit of the points].
    radius : float
        Radius [unit of the points].

    Examples
    --------
    >>> pts = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, -1.0]]) * 2 + 5
    >>> c, r = fit_sphere(pts)
    >>> np.round(c, 12).tolist(), round(r, 12)
    ([5.0, 5.0, 5.0], 2.0)
    """
    P = _as_points(points, 4)
    mean = P.mean(axis=0)
    X = P - mean
    S = np.linalg.svd(X, compute_uv=False)
    if S[2] <= tol.collinear * S[0]:
        raise ValueError("the points are coplanar: no unique sphere")
    A = np.c_[2 * X, np.ones(len(P))]
    sol, *_ = np.linalg.lstsq(A, np.sum(X * X, axis=1), rcond=None)
    c, k = sol[:3], sol[3]
    return mean + c, float(np.sqrt(k + c @ c))


# ----------------------------------------------------------------------------- segments

def _count(length: float, angle: float, step_mm: float, step_rad: float) -> int:
    # the 1e-12 slack keeps a length that is a whole number of steps up to rounding from
    # getting one needless extra sample
    return max(1, math.ceil(length / step_mm - 1e-12), math.ceil(angle / step_rad - 1e-12))


def sample_line(p0: FloatArray, q0: FloatArray, p1: FloatArray, q1: FloatArray,
                step_mm: float, step_rad: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Samples of a straight move, position linear and orientation by SLERP.

    Parameters
    ----------
    p0, p1 : (3,) float
        Start and end positions [mm].
    q0, q1 : (4,) float
        Start and end orientations ``[w, x, y, z]``.
    step_mm : float
        Largest distance between samples [mm].
    step_rad : float
        Largest orientation change between samples [rad].

    Returns
    -------
    points : (n, 3) float
        Positions [mm] after the start; the last one is ``p1`` exactly.
    quats : (n, 4) float
        Unit orientations.
    arc : (n,) float
        Distance from ``p0`` [mm].

    Examples
    --------
    >>> P, Q, s = sample_line(np.zeros(3), np.array([1.0, 0, 0, 0]), np.array([3.0, 0, 4]),
    ...                       np.array([1.0, 0, 0, 0]), 2.0, 1.0)
    >>> len(P), np.round(s, 6).tolist(), P[-1].tolist()  # 5 mm in 2 mm steps
    (3, [1.666667, 3.333333, 5.0], [3.0, 0.0, 4.0])
    """
    length = float(np.linalg.norm(p1 - p0))
    n = _count(length, float(quat_angle(q0, q1)), step_mm, step_rad)
    t = np.arange(1, n + 1) / n
    pts = p0 + t[:, None] * (p1 - p0)
    pts[-1] = p1
    return pts, slerp(q0, q1, t), t * length


def sample_arc(circle: tuple[FloatArray, FloatArray, FloatArray],
               p0: FloatArray, q0: FloatArray, pc: FloatArray, qc: FloatArray,
               p1: FloatArray, q1: FloatArray,
               step_mm: float, step_rad: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Samples of a circular move through a circle point, orientation by SLERP via it.

    Parameters
    ----------
    circle : tuple of (3,) float, (3,) float, float
        ``(centre [mm], unit normal, radius [mm])`` of the circle through ``p0``, ``pc``
        and ``p1``, as :func:`circle_through` gives it (the normal fixes the direction).
    p0, pc, p1 : (3,) float
        Start, circle point and end positions [mm].
    q0, qc, q1 : (4,) float
        Orientations ``[w, x, y, z]`` at the three positions.
    step_mm : float
        Largest distance along the arc between samples [mm].
    step_rad : float
        Largest orientation change between samples [rad].

    Returns
    -------
    points : (n, 3) float
        Positions [mm] after the start; ``pc`` and ``p1`` (the last) are kept exactly.
    quats : (n, 4) float
        Unit orientations.
    arc : (n,) float
        Arc length from ``p0`` [mm].
    """
    centre, normal, radius = circle
    u = (p0 - centre) / radius
    v = np.cross(normal, u)

    def angle_of(p):
        d = p - centre
        return float(np.arctan2(d @ v, d @ u)) % (2 * np.pi)

    phi_c, phi_1 = angle_of(pc), angle_of(p1)
    out_p, out_q, out_s = [], [], []
    # two sub-arcs so the orientation passes through the circle point's (CirPointOri)
    for (a0, a1, qa, qb, p_end) in ((0.0, phi_c, q0, qc, pc),
                                    (phi_c, phi_1, qc, q1, p1)):
        n = _count(radius * (a1 - a0), float(quat_angle(qa, qb)), step_mm, step_rad)
        t = np.arange(1, n + 1) / n
        phi = a0 + t * (a1 - a0)
        pts = centre + radius * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
        pts[-1] = p_end
        out_p.append(pts)
        out_q.append(slerp(qa, qb, t))
        out_s.append(radius * phi)
    return np.concatenate(out_p), np.concatenate(out_q), np.concatenate(out_s)
