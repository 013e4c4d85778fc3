"""Gravity sag at thousands of poses, for the target corrections and predicted paths.

:func:`~flexarm.assembly.analyses.gravity_sag` assembles the whole system (stiffness,
mass and constraint maps) at every pose, which costs seconds per thousand poses of a
flexible arm and gigabytes at path resolution.  When the stiffness does not depend on
the pose (rigid links, floating-frame superelements:
:func:`~flexarm.assembly.batched.has_constant_stiffness`) the sag is
``G_tcp(q) K^-1 f(q)``: ``K`` is factored once, ``G_tcp`` is
:func:`~flexarm.assembly.batched.tcp_map` and only the generalised weight ``f(q)`` is
needed, the weight of each body moved rigidly along gravity
(``sum_i T_i^T M_i U_i g``) carried to the independent coordinates by the motion of each
body's proximal node.  Other arms go through the full assembly, in chunks of poses.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ....assembly.analyses import GRAVITY
from ....assembly.analyses import gravity_sag as assembled_gravity_sag
from ....assembly.batched import POSE_CHUNK, constant_stiffness, has_constant_stiffness, tcp_map
from ....assembly.system import ArmModel, rotation_blocks
from ....fe.typing import ArrayLike, FloatArray
from ....robot.joints import joint_basis
from ....robot.kinematics import link_frames

__all__ = ["gravity_sag", "gravity_load"]


def gravity_load(arm: ArmModel, q: ArrayLike) -> FloatArray:
    """(n, n_x) generalised weight of every body at joint angles ``q`` (n, 6) [N, N m].

    For arms of one-node bodies (:func:`~flexarm.assembly.batched.has_constant_stiffness`):
    body ``i``'s proximal node moves with ``T_i`` (6, n_x) (its parent's attachment point,
    plus the joint's free DOFs), its elastic coordinates are its own columns of ``x``.

    Examples
    --------
    >>> from flexarm.assembly.arm import build_arm
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> arm = build_arm(load_demo_robot()).model  # the E-model
    >>> f = gravity_load(arm, np.radians([[0, 52, -19, 12, -15, -11]]))  # pose P1
    >>> j1, j2 = (arm.layout["joint"][j][0] for j in (0, 1))  # their torsion coordinates
    >>> bool(abs(f[0, j1]) < 1e-9 and f[0, j2] > 1e3)  # joint 2 carries the weight, 1 not
    True
    """
    chain, lay = arm.chain, arm.layout
    F = link_frames(chain, q)
    R = F[..., :3, :3]
    n = len(F)
    f = np.zeros((n, lay["n"]))
    g = np.zeros((n, 6))
    g[:, :3] = GRAVITY
    motion: list[FloatArray] = []
    for i, body in enumerate(arm.bodies):
        R6 = rotation_blocks(R[:, i], 6, 1)
        T = np.zeros((n, 6, lay["n"]))
        if i == 0 and arm.foundation is not None:
            T[:, :, lay["foundation"]] = np.eye(6)
        elif i > 0:
            j, p = i - 1, int(chain.parents[i - 1])
            Gp = arm.bodies[p].G(arm.joint_points[j])
            Rp = rotation_blocks(R[:, p], 6, 1)
            T += Rp @ Gp[:, :6] @ np.swapaxes(Rp, -1, -2) @ motion[p]
            T[:, :, lay["body"][p]] += Rp @ Gp[:, 6:]
            E = rotation_blocks(R[:, i] @ joint_basis(chain.axes[j]), 6, 1)
            T[:, :, lay["joint"][j]] += E[:, :, arm.joints[j].free_dofs]
        motion.append(T)
        local = np.einsum("nba,nb->na", R6, g)  # gravity in the link frame
        f += np.einsum("nax,na->nx", T, np.einsum("nab,bc,nc->na", R6, body.M[:6, :6], local))
        if len(lay["body"][i]):
            f[:, lay["body"][i]] += local @ body.M[6:, :6].T
    return f


def gravity_sag(arm: ArmModel, q: ArrayLike) -> FloatArray:
    """(n, 6) TCP displacement [m, rad] under the arm's own weight at poses ``q`` (n, 6).

    The same as :func:`flexarm.assembly.analyses.gravity_sag`, fast for arms of constant
    stiffness (see the module notes).

    Examples
    --------
    >>> from flexarm.assembly.analyses import gravity_sag as reference
    >>> from flexarm.assembly.emodel import emodel
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> arm = emodel(robot, method="surface")
    >>> q = np.array([robot.pose("P1"), robot.pose("P2")])
    >>> bool(np.allclose(gravity_sag(arm, q), reference(arm, q), rtol=1e-12, atol=1e-16))
    True
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    out = np.zeros((len(q), 6))
    if not (isinstance(arm, ArmModel) and has_constant_stiffness(arm)):
        for s in range(0, len(q), POSE_CHUNK):
            out[s:s + POSE_CHUNK] = assembled_gravity_sag(arm, q[s:s + POSE_CHUNK])
        return out
    if "_gravity_factor" not in arm.__dict__:  # the arm is frozen; K^-1 once per arm
        arm.__dict__["_gravity_factor"] = sla.cho_factor(constant_stiffness(arm))
    factor = arm.__dict__["_gravity_factor"]
    for s in range(0, len(q), POSE_CHUNK):
        qc = q[s:s + POSE_CHUNK]
        x = sla.cho_solve(factor, gravity_load(arm, qc).T).T
        out[s:s + POSE_CHUNK] = np.einsum("nix,nx->ni", tcp_map(arm, qc), x)
    return out
