"""A program run by a loaded arm: the tool path it really follows, and its deviation.

:func:`run_program` evaluates a :class:`~.loaded.LoadedArm` along every sample of a
:class:`~.program_path.ProgramPath` (the path the controller interpolates between the
commanded targets), with the process force where the tool really is and the joint laws
following the path's torque history.  :class:`PathRun` measures the loaded path against
the *programmed* one: the deviation from its nearest point and, for a circle, the
radial deviation about the programmed circle (what a ball bar reads).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ....fe.typing import FloatArray
from ....robot.paths import fit_circle
from ...tolerances import tol
from .forces import path_wrenches
from .ik_batch import displaced
from .loaded import LoadedArm, deflection, gravity_sag, law_rotations

__all__ = ["PathRun", "run_program", "path_deviation", "circle_of"]

def path_deviation(points: FloatArray, reference: FloatArray) -> FloatArray:
    """(n, 3) vector from the nearest point of the polyline ``reference`` (m, 3) to each
    of ``points`` (n, 3) [m].

    Examples
    --------
    >>> ref = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0]])
    >>> path_deviation(np.array([[0.5, 0.1, 0.0]]), ref).tolist()
    [[0.0, 0.1, 0.0]]
    """
    from scipy.spatial import cKDTree

    P = np.asarray(points, dtype=float)
    R = np.asarray(reference, dtype=float)
    _, i = cKDTree(R).query(P)
    best = P - R[i]
    for a, b in ((i - 1, i), (i, i + 1)):
        ok = (a >= 0) & (b < len(R))
        a, b = np.clip(a, 0, len(R) - 1), np.clip(b, 0, len(R) - 1)
        e = R[b] - R[a]
        ee = np.einsum("ij,ij->i", e, e)
        t = np.clip(np.einsum("ij,ij->i", P - R[a], e) / np.where(ee > 0, ee, 1.0), 0, 1)
        d = P - (R[a] + t[:, None] * e)
        better = ok & (np.einsum("ij,ij->i", d, d) < np.einsum("ij,ij->i", best, best))
        best = np.where(better[:, None], d, best)
    return best


def circle_of(points: FloatArray) -> tuple[FloatArray, FloatArray, float] | None:
    """(centre, normal, radius) [m] when ``points`` (n, 3) lie on one circle, else None.

    Examples
    --------
    >>> phi = np.linspace(0.0, 3.0, 20)
    >>> c = circle_of(np.c_[1 + 0.2 * np.cos(phi), 0.2 * np.sin(phi), np.zeros(20)])
    >>> round(c[2], 12), circle_of(np.c_[phi, phi ** 2, np.zeros(20)])
    (0.2, None)
    """
    try:
        c, n, r = fit_circle(points)
    except ValueError:
        return None
    d = points - c
    off = np.abs(np.linalg.norm(d - np.outer(d @ n, n), axis=1) - r).max()
    planar = np.abs(d @ n).max()
    return (c, n, r) if max(off, planar) <= tol.circle_share * r else None


@dataclass(frozen=True, eq=False)
class PathRun:
    """A procedure run under load.

    Attributes
    ----------
    name : str
    programmed : (m, 3) float
        The programmed path [m] (the reference).
    points : (n, 3) float
        Loaded tool positions [m].
    deviation : (n, 3) float
        From the nearest point of ``programmed`` [m].
    circle : (centre, normal, radius) or None
        The programmed circle [m], when the programmed path is one.
    is_jump : (n,) bool
        Samples of motions where a joint law jumps (no static offset helps there).
    """

    name: str
    programmed: FloatArray
    points: FloatArray
    deviation: FloatArray
    circle: tuple | None = None
    is_jump: np.ndarray | None = None

    @property
    def radial(self) -> FloatArray:
        """(n,) in-plane distance from the programmed circle's centre minus its radius [m]
        (the deviation's norm when the path is no circle)."""
        if self.circle is None:
            return np.linalg.norm(self.deviation, axis=1)
        c, n, r = self.circle
        d = self.points - c
        return np.linalg.norm(d - np.outer(d @ n, n), axis=1) - r

    def rms(self, where: np.ndarray | None = None) -> float:
        """RMS of :attr:`radial` [m] over the samples ``where`` (all by default)."""
        x = self.radial if where is None else self.radial[where]
        return float(np.sqrt(np.mean(x**2))) if len(x) else 0.0

    @property
    def peak(self) -> float:
        """Largest deviation from the programmed path [m]."""
        return float(np.linalg.norm(self.deviation, axis=1).max())


def run_program(la: LoadedArm, pp, force, pivot=None, reference=None,
                is_jump: np.ndarray | None = None) -> PathRun:
    """The loaded path of program path ``pp`` (:class:`~.program_path.ProgramPath`).

    Parameters
    ----------
    la : LoadedArm
    pp : ProgramPath
        The program as commanded (e.g. the compensated one).
    force : ForceSpec
        The process force (:mod:`.forces`), evaluated where the tool is under load.
    pivot : (3,) float, optional
        Ball-bar pivot [m].
    reference : ProgramPath, optional
        The programmed path to measure against (default: ``pp`` itself).
    is_jump : (n,) bool, optional
        Samples where a law jumps (:meth:`~.limits.Limits.jump_mask`).

    Returns
    -------
    PathRun

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.compensation.solve.forces import ConstantWrench
    >>> from flexarm.studies.compensation.solve.loaded import loaded_arm
    >>> from flexarm.studies.compensation.program import program_paths
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> robot = load_demo_robot()
    >>> (pp,) = program_paths(robot, read_rapid(THESIS_RAPID), ["Path_30"], step_mm=10)
    >>> run = run_program(loaded_arm(robot, gravity=False), pp, ConstantWrench())
    >>> bool(run.rms() < 1e-15), run.circle is not None  # no load, no gravity: on the circle
    (True, True)
    """
    ref = pp if reference is None else reference
    sag = gravity_sag(la.arm, pp.q) if la.gravity else None  # the same for both solves
    w = path_wrenches(force, pp, pivot=pivot)
    d = deflection(la, pp.q, w, pp.tool, law_rotations(la, pp.q, w, pp.tool), sag)
    # the force acts where the tool is under load (a ball bar turns with it)
    w = path_wrenches(force, pp, displaced(pp.frames, d), pivot)
    d = deflection(la, pp.q, w, pp.tool, law_rotations(la, pp.q, w, pp.tool), sag)
    points = pp.points + d[:, :3]
    return PathRun(pp.name, ref.points, points, path_deviation(points, ref.points),
                   circle_of(ref.points), is_jump)
