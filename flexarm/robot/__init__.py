"""The robot layer: what a robot *is*, independent of any structural model.

The description (:class:`Robot`: links with their CAD and materials, joints with their
springs, base, tool, poses), kinematics and inverse kinematics, RAPID paths, named
physical joint effects, and the description file formats (TOML, URDF, RAPID).
Imports :mod:`flexarm.fe`, :mod:`flexarm.meshes` and :mod:`flexarm.reduction` only.
"""

from __future__ import annotations

from .description import (
    BaseSupport,
    Joint,
    Link,
    LumpedMass,
    ModelOptions,
    Region,
    Robot,
    Tool,
    pose_from_string,
)
from .ik import IKConfig, ik, ik_analytic, ik_dls
from .joints import JointModel
from .kinematics import Chain, jacobian, joint_to_motor, link_frames, motor_to_joint, tcp_frame
from .loader import load_robot

__all__ = [
    "BaseSupport", "Joint", "Link", "LumpedMass", "ModelOptions", "Region", "Robot", "Tool",
    "pose_from_string",
    "IKConfig", "ik", "ik_analytic", "ik_dls",
    "JointModel",
    "Chain", "jacobian", "joint_to_motor", "link_frames", "motor_to_joint", "tcp_frame",
    "load_robot",
]
