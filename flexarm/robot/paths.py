"""TCP paths from RAPID procedures: sampling and circle/sphere geometry.

A procedure read by :func:`flexarm.robot.formats.rapid.read_rapid` becomes a
:class:`SampledPath`: TCP positions [mm] and orientations (unit quaternions
``[w, x, y, z]``, scalar first as in RAPID) in the work-object frame of its
instructions, densely sampled by arc length.

Interpolation follows the programmed geometry:

* ``MoveL``: straight line, orientation by SLERP (shortest rotation).
* ``MoveC``: the circle through start, ``CirPoint`` and ``ToPoint`` computed exactly
  (:func:`circle_through`), sampled by arc length; orientation by SLERP start ->
  CirPoint -> ToPoint (RAPID's ``CirPathMode \\CirPointOri``; the default path-frame
  mode gives the same result when the programmed orientations turn with the circle or
  stay constant, as in the thesis module).
* ``MoveJ`` / ``MoveAbsJ``: a straight line *flagged* as joint-interpolated: the real
  TCP path is linear in joint space and needs the arm's kinematics (see ``notes``).

Corner zones (``z100`` ...) are not modelled: the path passes through every target.
Tolerances below are module constants until they move into ``fe.tolerances``.
The quaternion helpers live in :mod:`flexarm.robot.quaternions` and are
re-exported here.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..fe.typing import ArrayLike, BoolArray, FloatArray, IntArray
from .formats.rapid import JointTarget, Motion, Procedure, RobTarget
from .quaternions import (
    quat_angle,
    quat_conjugate,
    quat_from_intrinsic_xyz,
    quat_from_matrix,
    quat_multiply,
    quat_normalize,
    quat_to_matrix,
    slerp,
)
from .tolerances import tol

__all__ = [
    "SampledPath",
    "sample_procedure",
    "circle_through",
    "fit_circle",
    "fit_sphere",
    "quat_normalize",
    "quat_multiply",
    "quat_conjugate",
    "quat_to_matrix",
    "quat_from_matrix",
    "quat_from_intrinsic_xyz",
    "quat_angle",
    "slerp",
]

logger = logging.getLogger(__name__)


FK = Callable[[FloatArray], "tuple[ArrayLike, ArrayLike]"]


# ----------------------------------------------------------------------------- geometry

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
    normal : (..., 3) float
        Unit normal oriented so that p1 -> p2 -> p3 runs counter-clockwise about it.
    radius : (...) float

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
        n >= 3 points, ideally in traversal order (it fixes the sign of the normal).

    Returns
    -------
    centre : (3,) float
    normal : (3,) float
        Unit plane normal, oriented so the points run counter-clockwise about it.
    radius : float

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
        n >= 4 points, not all in one plane.

    Returns
    -------
    centre : (3,) float
    radius : float

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


# ----------------------------------------------------------------------------- sampling

@dataclass(frozen=True, eq=False)
class SampledPath:
    """A densely sampled TCP path.

    Parameters
    ----------
    name : str
        Procedure name.
    points_mm : (n, 3) float
        TCP positions [mm] in the work-object frame of the instructions.
    quats : (n, 4) float
        Unit orientations ``[w, x, y, z]``, sign-continuous along the path.
    segments : (n,) int
        Index of the motion (in ``Procedure.motions``) each sample belongs to; sample 0
        (the start) belongs to motion 0.
    kinds : tuple of str
        Instruction of every motion (``"MoveL"``, ``"MoveC"``, ...).
    arc_length_mm : (n,) float
        Exact TCP path length from the start [mm] (circle arcs as arcs, not chords).
    lines : tuple of int
        File line of every motion.
    notes : tuple of str
        Approximations made (joint moves drawn straight, corner zones ignored, ...).
    """

    name: str
    points_mm: FloatArray
    quats: FloatArray
    segments: IntArray
    kinds: tuple[str, ...]
    arc_length_mm: FloatArray
    lines: tuple[int, ...]
    notes: tuple[str, ...]

    def __post_init__(self) -> None:
        for attr, dtype in (("points_mm", np.float64), ("quats", np.float64),
                            ("segments", np.int64), ("arc_length_mm", np.float64)):
            arr = np.array(getattr(self, attr), dtype=dtype)
            arr.setflags(write=False)
            object.__setattr__(self, attr, arr)

    @property
    def n_points(self) -> int:
        return len(self.points_mm)

    @property
    def is_joint_interpolated(self) -> BoolArray:
        """(n,) bool: samples of ``MoveJ``/``MoveAbsJ`` motions (drawn as straight lines)."""
        joint = np.array([k in ("MoveJ", "MoveAbsJ") for k in self.kinds], dtype=bool)
        return joint[self.segments]

    @property
    def points_m(self) -> FloatArray:
        """(n, 3) positions [m] (SI, for the rest of flexarm)."""
        return self.points_mm * 1e-3


def _count(length: float, angle: float, step_mm: float, step_rad: float) -> int:
    return max(1, math.ceil(length / step_mm - 1e-12), math.ceil(angle / step_rad - 1e-12))


def _line(p0, q0, p1, q1, step_mm, step_rad):
    length = float(np.linalg.norm(p1 - p0))
    n = _count(length, float(quat_angle(q0, q1)), step_mm, step_rad)
    t = np.arange(1, n + 1) / n
    pts = p0 + t[:, None] * (p1 - p0)
    pts[-1] = p1
    return pts, slerp(q0, q1, t), t * length


def _arc(p0, q0, cir: RobTarget, to: RobTarget, step_mm, step_rad, line):
    pc, p1 = cir.pos_mm, to.pos_mm
    try:
        centre, normal, radius = circle_through(p0, pc, p1)
    except ValueError:
        raise ValueError(f"MoveC on line {line}: start, CirPoint '{cir.name}' and ToPoint "
                         f"'{to.name}' are collinear or coincide (no circle)") from None
    u = (p0 - centre) / radius
    v = np.cross(normal, u)

    def angle_of(p):
        d = p - centre
        return float(np.arctan2(d @ v, d @ u)) % (2 * np.pi)

    phi_c, phi_1 = angle_of(pc), angle_of(p1)
    out_p, out_q, out_s = [], [], []
    for (a0, a1, qa, qb, p_end) in ((0.0, phi_c, q0, cir.quat, pc),
                                    (phi_c, phi_1, cir.quat, to.quat, p1)):
        n = _count(radius * (a1 - a0), float(quat_angle(qa, qb)), step_mm, step_rad)
        t = np.arange(1, n + 1) / n
        phi = a0 + t * (a1 - a0)
        pts = centre + radius * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
        pts[-1] = p_end
        out_p.append(pts)
        out_q.append(slerp(qa, qb, t))
        out_s.append(radius * phi)
    return np.concatenate(out_p), np.concatenate(out_q), np.concatenate(out_s)


def sample_procedure(
    procedure: Procedure,
    start: RobTarget | None = None,
    step_mm: float = 1.0,
    step_deg: float = 1.0,
    fk: FK | None = None,
) -> SampledPath:
    """Sample the TCP path of a RAPID procedure.

    Parameters
    ----------
    procedure : Procedure
        From :func:`~flexarm.robot.formats.rapid.read_rapid`.
    start : RobTarget, optional
        Where the robot is before the first instruction.  Without it the path starts at
        the first instruction's destination (the approach move is not sampled), and a
        ``MoveC`` cannot come first.
    step_mm : float
        Largest distance between samples along the path [mm].
    step_deg : float
        Largest orientation change between samples [deg].
    fk : callable, optional
        ``fk(joints_deg (6,)) -> (pos_mm (3,), quat (4,))`` of the arm with its tool in
        the work-object frame; needed only for ``MoveAbsJ``.

    Returns
    -------
    SampledPath

    Examples
    --------
    >>> from importlib.resources import files
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> mod = read_rapid(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")
    >>> path = sample_procedure(mod.procedures["Path_30"], step_mm=5.0)
    >>> round(float(path.arc_length_mm[-1]), 6)  # one turn of a 155 mm circle
    973.893723
    """
    if not step_mm > 0 or not step_deg > 0:
        raise ValueError(f"step_mm and step_deg must be > 0, got {step_mm}, {step_deg}")
    logger.info("sampling RAPID procedure %s", procedure.name)
    step_rad = math.radians(step_deg)
    motions: tuple[Motion, ...] = procedure.motions
    if not motions:
        raise ValueError(f"procedure {procedure.name} has no motions")
    notes: list[str] = []

    def pose(m: Motion) -> tuple[FloatArray, FloatArray]:
        target = m.to_point
        if isinstance(target, JointTarget):
            if fk is None:
                raise ValueError(f"MoveAbsJ on line {m.line}: a joint target needs fk= "
                                 "(the arm's forward kinematics) to become a TCP pose")
            pos, quat = fk(np.asarray(target.joints_deg, dtype=np.float64))
            return np.asarray(pos, dtype=np.float64), quat_normalize(quat)
        return target.pos_mm, quat_normalize(target.quat)

    pts: list[FloatArray] = []
    quats: list[FloatArray] = []
    segs: list[IntArray] = []
    arcs: list[FloatArray] = []
    if start is None:
        if motions[0].kind == "MoveC":
            raise ValueError(f"MoveC on line {motions[0].line} starts the procedure: pass "
                             "start= (the robot's pose before it)")
        p, q = pose(motions[0])
        notes.append(f"path starts at {motions[0].kind} line {motions[0].line}'s destination "
                     "(the approach from the robot's previous pose is not sampled)")
        first = 1
    else:
        p, q = start.pos_mm, quat_normalize(start.quat)
        first = 0
    pts.append(p[None])
    quats.append(q[None])
    segs.append(np.zeros(1, dtype=np.int64))
    arcs.append(np.zeros(1))
    s0 = 0.0
    for k in range(first, len(motions)):
        m = motions[k]
        if m.kind == "MoveC":
            p1, q1 = pose(m)
            P, Q, S = _arc(p, q, m.cir_point, m.to_point, step_mm, step_rad, m.line)
        else:
            p1, q1 = pose(m)
            P, Q, S = _line(p, q, p1, q1, step_mm, step_rad)
            if m.kind in ("MoveJ", "MoveAbsJ"):
                notes.append(f"{m.kind} line {m.line} drawn as a straight line: the real TCP "
                             "path is linear in joint space (needs the arm's kinematics)")
        pts.append(P)
        quats.append(Q)
        segs.append(np.full(len(P), k, dtype=np.int64))
        arcs.append(s0 + S)
        s0 += float(S[-1])
        p, q = p1, q1
    notes += [f"{m.kind} line {m.line}: corner zone '{m.zone}' not modelled (the path passes "
              "through the target)" for m in motions if not m.is_fine]
    wobjs = sorted({m.wobj or "wobj0" for m in motions})
    tools = sorted({m.tool for m in motions})
    if len(wobjs) > 1:
        notes.append(f"instructions use several work objects ({', '.join(wobjs)}): positions "
                     "are mixed frames")
    if len(tools) > 1:
        notes.append(f"instructions use several tools ({', '.join(tools)})")
    Q = np.concatenate(quats)
    # sign-continuous quaternions: flip where a sample points away from its predecessor
    flips = np.r_[1.0, np.where(np.sum(Q[1:] * Q[:-1], axis=1) < 0, -1.0, 1.0)]
    Q = Q * np.cumprod(flips)[:, None]
    path = SampledPath(procedure.name, np.concatenate(pts), Q, np.concatenate(segs),
                       tuple(m.kind for m in motions), np.concatenate(arcs),
                       tuple(m.line for m in motions), tuple(notes))
    logger.info("sampled %s: %d points, %.1f mm", procedure.name, path.n_points, s0)
    return path
