"""Target correction by fixed-point iteration: command the pose the load pushes onto the program.

A target ``X_p`` (the programmed tool frame) loaded by the wrench ``w`` lands at
``X_p (+) d(q(X_p), w)``, with ``d`` the deflection of :func:`~.loaded.deflection` at the
joint angles ``q`` the controller computes for it.  The commanded frame ``X_c`` must
satisfy ``X_c (+) d(q(X_c), w) = X_p``; since ``d`` depends on the pose it is evaluated
at, it is a fixed point::

    X_c <- X_p (-) d(q(X_c), w)

Each iteration is one batched deflection evaluation over every target (one stack of
compliances, one of Jacobians) and one batched Newton IK warm-started from the previous
joint angles.  The map contracts by the deflection's slope over the pose (about
``|d| / reach``), so a few iterations reach round-off.

The force is the programmed one at the programmed pose (the load acts where the tool
ends up, which is the program at the fixed point), and the laws' extra joint rotations
come from the path's torque history (:func:`~.loaded.law_rotations`), which moves by
far less than the deflection when the pose moves by a deflection.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from dataclasses import replace as dc_replace

import numpy as np

from ....fe.typing import FloatArray
from ...tolerances import tol
from .ik_batch import displaced, newton_ik, pose_errors
from .loaded import LoadedArm, deflection, gravity_sag

__all__ = ["Correction", "correct_targets"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class Correction:
    """Commanded targets whose loaded pose is the programmed one.

    Attributes
    ----------
    frames : (n, 4, 4) float
        Commanded tool frames [m], base frame.
    q : (n, 6) float
        Their joint angles [rad].
    offsets : (n, 6) float
        Commanded minus programmed pose [m, rad] (:func:`~.ik_batch.pose_errors`).
    before : (n, 6) float
        Deviation of the uncorrected program: loaded minus programmed pose [m, rad].
    after : (n, 6) float
        The same for the commanded targets (round-off when converged).
    iterations : int
    is_converged : (n,) bool
    is_reached : (n,) bool
        The IK reached the commanded frame.
    """

    frames: FloatArray
    q: FloatArray
    offsets: FloatArray
    before: FloatArray
    after: FloatArray
    iterations: int
    is_converged: np.ndarray
    is_reached: np.ndarray


def correct_targets(la: LoadedArm, tool: FloatArray, frames: FloatArray, q0: FloatArray,
                    wrench: FloatArray, rotations: FloatArray | None = None) -> Correction:
    """Commanded frames whose loaded poses are ``frames`` (the fixed point above).

    Parameters
    ----------
    la : LoadedArm
    tool : (4, 4) float
        Programmed tool on the last body [m].
    frames : (n, 4, 4) float
        Programmed tool frames [m].
    q0 : (n, 6) float
        Joint angles reaching them [rad] (with the programmed configuration).
    wrench : (n, 6) float
        Process wrench at each target [N, N m], base frame.
    rotations : (n, n_joints) float, optional
        The laws' extra joint rotations at the targets [rad] (from the path's history);
        evaluated at the targets as one history when not given.

    Returns
    -------
    Correction

    Examples
    --------
    >>> from dataclasses import replace
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.kinematics import tcp_frame
    >>> from flexarm.studies.compensation.solve.loaded import loaded_arm
    >>> robot = load_demo_robot()
    >>> la = loaded_arm(robot)
    >>> q = np.array([robot.pose("P1")])
    >>> T = tcp_frame(replace(robot.chain, tool=np.eye(4)), q)
    >>> c = correct_targets(la, np.eye(4), T, q, np.array([[0, 800.0, 0, 0, 0, 0]]))
    >>> bool(np.abs(c.before[0, :3]).max() > 1e-3), bool(np.abs(c.after).max() < 1e-9)
    (True, True)
    """
    chain = dc_replace(la.arm.chain, tool=np.asarray(tool, dtype=float))
    frames = np.asarray(frames, dtype=float)
    q = np.array(q0, dtype=float)

    def sag_at(q):
        return gravity_sag(la.arm, q) if la.gravity else None

    # the sag is the costly part of a flexible arm's deflection (a full assembly per pose)
    # and moves least with the pose: it is refreshed only once the rest has converged
    sag = sag_at(q)
    d0 = deflection(la, q, wrench, tool, rotations, sag)
    d = d0
    change = np.full(len(q), np.inf)
    iterations = 0
    for iterations in range(1, tol.compensation_max_iter + 1):  # noqa: B007 (kept)
        q, err = newton_ik(chain, displaced(frames, -d), q)
        reached = err <= tol.ik_pose_error
        d_new = deflection(la, q, wrench, tool, rotations, sag)
        change = np.abs(d_new - d).max(axis=1)
        d = d_new
        if np.all(change[reached] <= tol.compensation_step):
            if not la.gravity:
                break
            sag = sag_at(q)
            d_new = deflection(la, q, wrench, tool, rotations, sag)
            change = np.abs(d_new - d).max(axis=1)
            d = d_new
            if np.all(change[reached] <= tol.compensation_step):
                break
    goal = displaced(frames, -d)
    q, err = newton_ik(chain, goal, q)
    reached = err <= tol.ik_pose_error
    after = pose_errors(frames, displaced(goal, deflection(la, q, wrench, tool, rotations, sag)))
    converged = change <= tol.compensation_step
    log.info("compensation: %d targets, %d iterations, %d unconverged", len(q), iterations,
             int((~converged).sum()))
    return Correction(goal, q, pose_errors(frames, goal), d0, after, iterations, converged,
                      reached)
