"""Loaded circle test (LDBB, thesis §3.4.2/§4.2): TCP deviation under a bar force.

A loaded double ball bar joins the robot's load point (a ball on the flange or the
tool) to a fixed pivot.  While the robot runs a circle on the sphere about the pivot,
the bar pushes (or pulls) with a constant force ``F`` along itself:
``f = +F u`` (push) or ``-F u`` (pull), ``u = (p - pivot) / |p - pivot|``.  For circles
outside the pivot's plane (``Path_40``/``Path_50`` of appendix B) the force is not
horizontal.

The deviation of the load point is measured *relative to the unloaded run*:
``d(F) = s(F) - s(0)`` with ``s`` a static solver of the arm (so gravity sag and a
nonlinear preload cancel at 0 N, which is zero by definition).  The default solver is
linear (the TCP compliance at every IK pose, batched); a nonlinear solver with gravity
plugs in through ``solver=`` (:data:`StaticSolver`;
:func:`~flexarm.studies.contact.circle_models.nonlinear_solver`).

Reported per path sample: ``bar`` (the ball-bar reading, ``d . u``, what an ISO 230-4
polar plot shows), ``radial`` (in-plane radius change about the fitted circle centre;
equal to ``bar`` when the pivot is the centre), ``normal`` (along the circle normal)
and ``z`` (base z).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...assembly.analyses import tcp_compliance
from ...assembly.system import ArmModel
from ...fe.errors import ReadError
from ...fe.geometry import rigid_transport
from ...fe.typing import ArrayLike, FloatArray
from ...robot.ik_path import PathIK, UnreachableTargetError, ik_path
from ...robot.kinematics import tcp_frame
from ...robot.paths import fit_circle, fit_sphere, sample_procedure

__all__ = ["StaticSolver", "linear_solver", "CircleSetup", "circle_setup", "rapid_circle",
           "default_pivot", "CirclePrediction", "predict_circle", "load_point_compliance",
           "weak_directions", "measured_deviation", "circle_offsets"]

log = logging.getLogger(__name__)

#: ``solver(arm, q (n, 6), wrench (k, n, 6)) -> (k, n, 6)`` TCP displacement [m, rad] of the
#: arm's own TCP under a TCP wrench [N, N m], base frame.  A nonlinear solver includes
#: gravity and its preload; the result is used relative to the zero-wrench solve.
StaticSolver = Callable[[ArmModel, FloatArray, FloatArray], FloatArray]


def linear_solver(arm: ArmModel, q: FloatArray, wrench: FloatArray) -> FloatArray:
    """Linear :data:`StaticSolver`: ``u = C(q) w`` with :func:`tcp_compliance` (batched)."""
    return np.einsum("nij,knj->kni", tcp_compliance(arm, q), wrench)


def _transfer(lever: FloatArray) -> FloatArray:
    """(..., 3, 6) map TCP motion (u, theta) -> motion of a point at ``lever`` from the TCP.

    The translational rows ``[I, -skew(lever)]`` of :func:`~flexarm.fe.geometry.rigid_transport`.
    """
    return np.ascontiguousarray(rigid_transport(lever)[..., :3, :])


@dataclass(frozen=True, eq=False)
class CircleSetup:
    """A circle test: the arm's poses along the path and the bar geometry.

    Attributes
    ----------
    name : str
    ik : PathIK
        Joint angles ``ik.q`` (n, 6) [rad]; ``ik.tool`` is the load point's frame on the
        last body (the ball centre).
    points : (n, 3) float
        Nominal load-point positions, base frame [m].
    pivot : (3,) float
        Fixed ball of the bar [m].
    centre, normal : (3,) float
        Fitted circle centre [m] and unit normal (the path runs counter-clockwise about it).
    radius : float
        Fitted circle radius [m].
    """

    name: str
    ik: PathIK
    points: FloatArray
    pivot: FloatArray
    centre: FloatArray
    normal: FloatArray
    radius: float

    @property
    def bar_dirs(self) -> FloatArray:
        """(n, 3) unit vectors from the pivot to the load point."""
        d = self.points - self.pivot
        return d / np.linalg.norm(d, axis=1, keepdims=True)

    def along_bar(self, vectors: ArrayLike) -> FloatArray:
        """Components of vectors at the path samples along the bar (the ball-bar reading).

        Parameters
        ----------
        vectors : (..., n, 3) float
            A vector per path sample [m], base frame (e.g. load-point deviations).

        Returns
        -------
        (..., n) float
            Change of the bar length [m]; + lengthens the bar.

        Examples
        --------
        >>> import numpy as np
        >>> setup = CircleSetup("c", None, np.array([[1.0, 0, 0], [0, 2.0, 0]]), np.zeros(3),
        ...                     np.zeros(3), np.array([0, 0, 1.0]), 1.0)  # the bar alone, no IK
        >>> setup.along_bar([[0.5, 0.1, 0.0], [0.3, -0.2, 0.0]]).tolist()
        [0.5, -0.2]
        """
        return np.einsum("...ni,ni->...n", np.asarray(vectors, dtype=float), self.bar_dirs)

    @property
    def bar_length(self) -> FloatArray:
        """(n,) pivot-to-load-point distance [m]."""
        return np.linalg.norm(self.points - self.pivot, axis=1)

    @property
    def plane_axes(self) -> FloatArray:
        """(2, 3) in-plane axes: base x projected on the plane, then ``normal x e1``."""
        n = self.normal
        ref = np.eye(3)[0] if abs(n[0]) < 0.9 else np.eye(3)[1]
        e1 = ref - (ref @ n) * n
        e1 /= np.linalg.norm(e1)
        return np.array([e1, np.cross(n, e1)])

    @property
    def angles(self) -> FloatArray:
        """(n,) polar angle [rad] of each point about the centre, in ``plane_axes``."""
        r = (self.points - self.centre) @ self.plane_axes.T
        return np.arctan2(r[:, 1], r[:, 0])

    @property
    def radial_dirs(self) -> FloatArray:
        """(n, 3) in-plane unit vectors from the circle centre to each point."""
        r = self.points - self.centre
        r = r - np.outer(r @ self.normal, self.normal)
        return r / np.linalg.norm(r, axis=1, keepdims=True)


def circle_setup(robot, path, confs=None, pivot: ArrayLike | None = None,
                 tool="tool0", q_start: ArrayLike | None = None) -> CircleSetup:
    """Solve IK along a sampled path and attach the bar geometry.

    Parameters
    ----------
    robot : Robot
    path : SampledPath
        Load-point path in the base frame [mm].
    confs : (n_motions, 4) int, optional
        RAPID configurations (see :func:`~flexarm.robot.ik_path.ik_path`).
    pivot : (3,) float, optional
        Bar pivot [m]; by default a sphere fit of the path, or the circle centre when
        the path is planar.
    tool : {"tool0", "robot"} or (4, 4) float
        Load point (ball centre) on the last body; ``"tool0"`` = the flange centre.
    q_start : (6,) float, optional
        Branch seed when no configuration is given [rad].
    """
    sol = ik_path(robot.chain, path, confs, robot.lower, robot.upper, tool=tool,
                  q_start=q_start)
    pts = sol.frames[:, :3, 3]
    centre, normal, radius = fit_circle(pts)
    if pivot is None:
        try:
            pivot, _ = fit_sphere(pts)
        except ValueError:
            pivot = centre
    return CircleSetup(path.name, sol, pts, np.asarray(pivot, dtype=float), centre, normal,
                       radius)


def default_pivot(module, name: str) -> FloatArray:
    """(3,) bar pivot [m] of procedure ``name`` of a RAPID module.

    A non-planar path gives its own sphere.  A planar circle is grouped with the
    module's other circles that share its axis (parallel normal, centre on the axis,
    within 1 mm); two or more give the common sphere (appendix B: ``Path_30``,
    ``Path_40``, ``Path_50`` on a 155 mm sphere), a single one its own centre.
    """
    def pts(proc):
        return sample_procedure(proc, step_mm=20.0).points_mm

    own = pts(module.procedures[name])
    try:
        return fit_sphere(own)[0] * 1e-3
    except ValueError:
        pass
    c, n, _ = fit_circle(own)
    group = [own]
    for other, proc in module.procedures.items():
        if other == name:
            continue
        try:
            P = pts(proc)
            c2, n2, _ = fit_circle(P)
        except ValueError:
            continue
        planar = np.abs((P - c2) @ n2).max() < 1.0
        off = (c2 - c) - ((c2 - c) @ n) * n
        if planar and abs(abs(n2 @ n) - 1) < 1e-9 and np.linalg.norm(off) < 1.0:
            group.append(P)
    if len(group) == 1:
        return c * 1e-3
    return fit_sphere(np.concatenate(group))[0] * 1e-3


def rapid_circle(robot, module, name: str, pivot: ArrayLike | None = None, tool="tool0",
                 step_mm: float = 2.0) -> CircleSetup:
    """:class:`CircleSetup` of procedure ``name`` of a RAPID module (conf honoured).

    Examples
    --------
    >>> from importlib.resources import files
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> mod = read_rapid(files("flexarm") / "data/rapid/ldbb_thesis.mod")
    >>> s = rapid_circle(load_demo_robot(), mod, "Path_40", step_mm=20)
    >>> round(float(s.bar_length.mean()) * 1e3, 2), round(s.radius * 1e3, 3)
    (155.0, 118.427)
    """
    proc = module.procedures[name]
    path = sample_procedure(proc, step_mm=step_mm)
    piv = default_pivot(module, name) if pivot is None else pivot
    try:
        return circle_setup(robot, path, [m.to_point.conf for m in proc.motions], piv, tool)
    except UnreachableTargetError as exc:
        if not module.path:
            raise
        raise ReadError(f"{module.path}: {name}: {exc}") from None


def load_point_compliance(arm: ArmModel, setup: CircleSetup) -> FloatArray:
    """(n, 3, 3) translational compliance [m/N] at the load point (force there, motion there)."""
    q = setup.ik.q
    lever = setup.points - tcp_frame(arm.chain, q)[:, :3, 3]
    A = _transfer(lever)
    return A @ tcp_compliance(arm, q) @ np.swapaxes(A, -1, -2)


def weak_directions(arm: ArmModel, setup: CircleSetup) -> tuple[FloatArray, FloatArray]:
    """Largest principal compliance [m/N] (n,) and its unit direction (n, 3) at the load point."""
    lam, V = np.linalg.eigh(load_point_compliance(arm, setup))
    return lam[:, -1], V[:, :, -1]


@dataclass(frozen=True, eq=False)
class CirclePrediction:
    """Predicted load-point deviation along a circle at several bar forces.

    Attributes
    ----------
    setup : CircleSetup
    loads : (k,) float
        Bar force magnitudes [N].
    is_pull : bool
        The bar pulls the load point towards the pivot (else pushes it away).
    deviation : (k, n, 3) float
        Deviation from the unloaded run, base frame [m].
    method : str
        Name of the static solver.
    """

    setup: CircleSetup
    loads: FloatArray
    is_pull: bool
    deviation: FloatArray
    method: str

    @property
    def bar(self) -> FloatArray:
        """(k, n) change of the bar length [m] (ball-bar reading)."""
        return self.setup.along_bar(self.deviation)

    @property
    def radial(self) -> FloatArray:
        """(k, n) in-plane radius change about the circle centre [m]."""
        return np.einsum("kni,ni->kn", self.deviation, self.setup.radial_dirs)

    @property
    def normal(self) -> FloatArray:
        """(k, n) deviation along the circle normal [m]."""
        return self.deviation @ self.setup.normal

    @property
    def z(self) -> FloatArray:
        """(k, n) deviation along base z [m]."""
        return self.deviation[..., 2]


def predict_circle(arm: ArmModel, setup: CircleSetup, loads: ArrayLike, pull: bool = False,
                   solver: StaticSolver | None = None) -> CirclePrediction:
    """Deviation of the load point at every path sample and bar force.

    Parameters
    ----------
    arm : ArmModel
        E-model or flexible arm (any :class:`ArmModel`).
    setup : CircleSetup
    loads : (k,) float
        Bar force magnitudes [N] (>= 0).
    pull : bool
        Direction of the bar force (see the module docstring).
    solver : StaticSolver, optional
        Static solver; :func:`linear_solver` by default.

    Returns
    -------
    CirclePrediction
    """
    F = np.atleast_1d(np.asarray(loads, dtype=float))
    if F.ndim != 1 or np.any(F < 0):
        raise ValueError(f"loads must be (k,) magnitudes >= 0 [N], got {F}")
    solve = linear_solver if solver is None else solver
    log.info("loaded circle %s: %d samples x %d loads", setup.name, len(setup.points), len(F))
    q = setup.ik.q
    lever = setup.points - tcp_frame(arm.chain, q)[:, :3, 3]
    A = _transfer(lever)  # (n, 3, 6); its transpose carries a point force to a TCP wrench
    sign = -1.0 if pull else 1.0
    f = sign * F[:, None, None] * setup.bar_dirs[None]  # (k, n, 3)
    W = np.einsum("nij,kni->knj", A, f)
    u = solve(arm, q, W) - solve(arm, q, np.zeros((1,) + W.shape[1:]))
    dev = np.einsum("nij,knj->kni", A, u)
    name = getattr(solve, "__name__", type(solve).__name__)
    return CirclePrediction(setup, F, bool(pull), dev, name)


def circle_offsets(setup: CircleSetup, points: ArrayLike) -> FloatArray:
    """(m,) distance [m] of each point (m, 3) [m] from the programmed circle of ``setup``
    (its fitted centre, normal and radius).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> s = SimpleNamespace(centre=np.zeros(3), normal=np.array([0.0, 0, 1]), radius=0.1)
    >>> circle_offsets(s, [[0.1, 0, 0], [0.0, 0.13, 0.04]]).round(6).tolist()
    [0.0, 0.05]
    """
    d = np.asarray(points, dtype=float).reshape(-1, 3) - setup.centre
    h = d @ setup.normal
    r = np.linalg.norm(d - h[:, None] * setup.normal, axis=1)
    return np.hypot(r - setup.radius, h)


def measured_deviation(setup: CircleSetup, points: ArrayLike, force: ArrayLike):
    """Measured path data as (angle [rad], bar [m], normal [m], force [N]) arrays.

    ``points`` (m, 3) [m] are absolute load-point readings, ``force`` (m,) [N].  Bar and
    normal deviations are taken about the nominal sphere and circle plane; if some
    rows have 0 N, the 0-N reading interpolated at the same angle is subtracted
    (the same relative definition as :func:`predict_circle`).
    """
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    f = np.asarray(force, dtype=float).reshape(-1)
    if len(f) != len(P):
        raise ValueError(f"points (m, 3) and force (m,) differ: {P.shape}, {f.shape}")
    r = (P - setup.centre) @ setup.plane_axes.T
    ang = np.arctan2(r[:, 1], r[:, 0])
    bar = np.linalg.norm(P - setup.pivot, axis=1) - setup.bar_length.mean()
    nrm = (P - setup.centre) @ setup.normal
    zero = f == 0
    if zero.sum() >= 2:
        order = np.argsort(ang[zero])
        a0 = ang[zero][order]
        for arr in (bar, nrm):
            arr -= np.interp(ang, a0, arr[zero][order], period=2 * np.pi)
    return ang, bar, nrm, f
