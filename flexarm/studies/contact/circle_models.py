"""Static solvers for the loaded circle test with gravity and nonlinear joints.

The arm is any :class:`~flexarm.assembly.system.ArmModel` of
:func:`~flexarm.assembly.arm.build_arm`: the E-model (rigid links) or the flexible arm
(links as superelements) have the same kinematics, joints and base, so they differ only
in link flexibility.

:func:`nonlinear_solver` is a :data:`~flexarm.studies.contact.ball_bar.StaticSolver`
with gravity and nonlinear joint laws (backlash, hardening, hysteresis of
:mod:`flexarm.assembly.nonlinear`).  The joint torque ``tau_j`` about each joint axis
is statically exact (:func:`~flexarm.assembly.statics.joint_moments`: the weight of
the distal bodies plus the bar wrench), so a law's extra rotation ``delta_j(tau_j)``
moves the TCP rigidly by the Jacobian column ``J_j delta_j`` on top of the linear
response ``C(q) w`` (the reasoning of :mod:`flexarm.assembly.statics`).  The torque
history a law sees is the path order at one bar force (the robot runs the circle
under a constant load), so a hysteresis loop is traversed along the path.  Gravity
cancels in the linear part of ``d(F) = s(F) - s(0)`` but sets where a backlash
switches: where the bar's torque reverses a joint's gravity torque.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ...assembly.statics import joint_moments
from ...assembly.system import ArmModel
from ...fe.typing import FloatArray
from ...robot.kinematics import jacobian
from .ball_bar import StaticSolver, linear_solver

__all__ = ["nonlinear_solver", "circle_joint_torques"]


def circle_joint_torques(arm: ArmModel, q: FloatArray, wrench: FloatArray,
                         gravity: bool = True) -> FloatArray:
    """(k, n, n_joints) torque about each joint axis [N m] under TCP wrenches (*batched*).

    Parameters
    ----------
    arm : ArmModel
    q : (n, n_joints) float
        Joint angles along the path [rad].
    wrench : (k, n, 6) float
        Force [N] and moment [N m] at the arm's TCP, base frame.
    gravity : bool
        Add the weight of the bodies (the preload).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> circle_joint_torques(two_link_arm(), np.zeros((3, 2)), np.zeros((1, 3, 6))).shape
    (1, 3, 2)
    """
    q = np.asarray(q, dtype=float)
    wrench = np.asarray(wrench, dtype=float)
    if wrench.ndim != 3 or wrench.shape[1:] != (len(q), 6):
        raise ValueError(f"wrench must be (k, {len(q)}, 6), got {wrench.shape}")
    Q = np.broadcast_to(q, wrench.shape[:2] + q.shape[1:])
    return joint_moments(arm, Q, wrench[..., :3], wrench[..., 3:], gravity=gravity)[..., 0]


def nonlinear_solver(laws: Mapping[int, Sequence] | None, gravity: bool = True) -> StaticSolver:
    """:data:`StaticSolver` with gravity preload and nonlinear joint laws.

    Parameters
    ----------
    laws : mapping joint index -> sequence of laws
        E.g. the second result of :func:`flexarm.assembly.effects.apply_effects`;
        each law has ``deflection(tau (..., n)) -> (..., n)`` [rad] with the torque
        history on the last axis (here: along the path).
    gravity : bool
        Include the bodies' weight in the joint torques (the operating point).

    Returns
    -------
    StaticSolver
        ``solve(arm, q (n, 6), wrench (k, n, 6)) -> (k, n, 6)`` TCP displacement [m, rad]:
        the linear ``C(q) w`` plus ``J_j delta_j(tau_j)`` for every joint with laws.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> from flexarm.assembly.nonlinear import Backlash
    >>> arm = two_link_arm()
    >>> solve = nonlinear_solver({0: [Backlash(1e-3)]}, gravity=False)
    >>> w = np.zeros((2, 1, 6))
    >>> w[:, 0, 1] = [-1.0, 1.0]  # a small -y / +y force at the tip (joints about z)
    >>> u = solve(arm, np.zeros((1, 2)), w)
    >>> bool(abs(u[1, 0, 1] - u[0, 0, 1]) > 1e-3)  # crossing the 1 mrad dead band (2 m arm)
    True
    """
    laws = dict(laws or {})

    def solve(arm: ArmModel, q: FloatArray, wrench: FloatArray) -> FloatArray:
        u = linear_solver(arm, q, wrench)
        if not laws:
            return u
        tau = circle_joint_torques(arm, q, wrench, gravity)
        J = jacobian(arm.chain, q)  # (n, 6, n_joints)
        for j, js in laws.items():
            extra = np.zeros(tau.shape[:2])
            for law in js:
                extra = extra + law.deflection(tau[..., j])
            u = u + J[None, :, :, j] * extra[..., None]
        return u

    solve.__name__ = "nonlinear_solver" if laws else "linear_solver"
    return solve
