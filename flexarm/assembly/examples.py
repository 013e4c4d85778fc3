"""Tiny canonical arms for examples and tests (like meshio's ``tests/helpers.py``)."""

from __future__ import annotations

import numpy as np

from ..fe.mass_properties import MassProperties
from ..robot.joints import JointModel
from ..robot.kinematics import Chain
from .bodies import rigid_body
from .system import ArmModel

__all__ = ["two_link_arm"]


def two_link_arm(k1: float = 1e4, k2: float = 2e4, length: float = 1.0, mass: float = 10.0):
    """Planar two-link arm: joints about z at the origin and at ``length`` [m] along x.

    Each link is a slender rod of ``mass`` [kg] along x (centre at ``length / 2``),
    the TCP at the tip of link 2; torsion-only joints ``k1``, ``k2`` [N m/rad].

    Examples
    --------
    >>> arm = two_link_arm()
    >>> arm.layout["n"]
    2
    """
    L = float(length)
    chain = Chain(origins=[[0, 0, 0], [L, 0, 0]], axes=[[0, 0, 1], [0, 0, 1]], parents=[0, 1],
                  tool=np.array([[1, 0, 0, L], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]))
    rod = MassProperties(mass, np.array([L / 2, 0, 0]), np.diag([0, 1, 1]) * mass * L**2 / 12)
    base = MassProperties(1.0, np.zeros(3), np.eye(3))
    bodies = (
        rigid_body("base", base, [0, 0, 0], {"joint_1": [0, 0, 0]}),
        rigid_body("link_1", rod, [0, 0, 0], {"joint_2": [L, 0, 0]}),
        rigid_body("link_2", rod, [0, 0, 0], {"tcp": [L, 0, 0]}),
    )
    joints = (JointModel(torsion=k1), JointModel(torsion=k2))
    return ArmModel(chain, bodies, joints, ("joint_1", "joint_2"), "tcp")
