"""Equivalent joint stiffness of the rigid-link E-model from the links' superelements.

The robot file holds the *physical* joint stiffness (gear torsion, bearing tilt), which
the flexible arm uses as is.  The E-model has rigid links, so the links' out-of-plane
bending has to be lumped into its joints, as in the thesis's E-model with 3-D springs:
each joint with finite bearing tilt gets the bearing in series with the bending
compliance of the links it carries, about its two tilt axes,

    ``1 / k_eq,k = 1 / k_bearing + t_k^T (sum_b R_b C_rr,b R_b^T) t_k``,   k = 1, 2,

where ``t_k`` are the tilt axes (joint frame, columns 2 and 3 of
:func:`~flexarm.robot.joints.joint_basis`) and the sum runs over the *segment* of
the joint: the bodies on the path to the TCP from the joint's child up to (not
including) the child of the next joint with finite tilt.  ``C_rr,b`` is body ``b``'s
Guyan static rotational compliance [rad/(N m)] at its exit point (the next joint on the
path, or the TCP) relative to its proximal joint point, i.e. the relative rotation of
its two interfaces under a moment passed through the link; ``R_b`` turns it into the
joint's child frame at zero joint angles.  Under a moment transmitted along the arm
this rotation is exact; under a force its lumping at the joint slightly overstates the
lever (conservative).  Joints with rigid bearings keep their model.

:func:`equivalent_joint_models` needs the superelements (a build); the demo arm stores
the result once in its robot file as ``[joints.emodel]`` (see
:mod:`flexarm.robot.demo_arm`), so the E-model itself stays free of FE work.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..fe.typing import FloatArray
from ..robot.joints import JointModel, joint_basis
from ..robot.kinematics import link_frames
from .system import ArmModel

__all__ = ["link_rotational_compliance", "joint_segments", "equivalent_joint_models"]


def link_rotational_compliance(arm: ArmModel, body: int, point: str) -> FloatArray:
    """(3, 3) rotational compliance [rad/(N m)] of a body's ``point`` (link frame).

    The proximal joint point is held (the body's first six coordinates are zero); the
    elastic coordinates carry the statically condensed (Guyan) stiffness.  Zero for a
    rigid body.
    """
    b = arm.bodies[body]
    Ge = b.G(point)[3:, 6:]
    if Ge.shape[1] == 0 or not np.any(b.K):
        return np.zeros((3, 3))
    C = Ge @ np.linalg.solve(b.K[6:, 6:], Ge.T)
    return 0.5 * (C + C.T)


def joint_segments(arm: ArmModel) -> dict[int, list[tuple[int, str]]]:
    """Joint index -> [(child body, exit point)] for the joints with finite tilt.

    Each such joint on the path to the TCP takes the bending of its child link, from
    the joint to the child's exit point (the next joint on the path, or the TCP).
    """
    chain = arm.chain
    path = chain.ancestors(chain.tcp_body)
    exits = {int(chain.parents[j]): arm.joint_points[j] for j in path}
    exits[chain.tcp_body] = arm.tcp_point
    return {j: [(j + 1, exits[j + 1])] for j in path if np.isfinite(arm.joints[j].tilt)}


def equivalent_joint_models(arm: ArmModel) -> tuple[JointModel, ...]:
    """E-model joint models of a flexible ``arm``: bearing tilt in series with link bending.

    Parameters
    ----------
    arm : ArmModel
        The flexible arm (:func:`~flexarm.assembly.flexible.flexible_arm`) with the
        physical joint models.

    Returns
    -------
    tuple of JointModel
        One per joint: ``tilt`` and ``tilt2`` [N m/rad] replaced where the joint has a
        finite bearing tilt, everything else unchanged.
    """
    F = link_frames(arm.chain, np.zeros(arm.chain.n_joints))
    models = list(arm.joints)
    for j, segment in joint_segments(arm).items():
        i = j + 1
        C = np.zeros((3, 3))
        for b, point in segment:
            R = F[i, :3, :3].T @ F[b, :3, :3]
            C += R @ link_rotational_compliance(arm, b, point) @ R.T
        B = joint_basis(arm.chain.axes[j])
        jm = models[j]
        c1, c2 = (float(B[:, k] @ C @ B[:, k]) for k in (1, 2))
        models[j] = dataclasses.replace(jm, tilt=1.0 / (1.0 / jm.tilt + c1),
                                        tilt2=1.0 / (1.0 / jm.tilt_2 + c2))
    return tuple(models)
