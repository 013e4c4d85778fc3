"""Robot description, kinematics, joint models and the assembled arm (E-model).

Layers: :mod:`kinematics`/:mod:`ik` (chains), :mod:`robot` + :mod:`formats`
(description files), :mod:`joints`/:mod:`bodies`/:mod:`system` (exact-elimination
assembly), :mod:`emodel` (rigid links), :mod:`analyses` and :mod:`maps`.
"""

from __future__ import annotations

from .analyses import (
    IdentificationReport,
    Modes,
    diagonal_compliance,
    frf,
    gravity_sag,
    identify_stiffness,
    modes,
    natural_frequencies,
    stiffness_from_load_cases,
    tcp_compliance,
)
from .bodies import Body, combine_mass_properties, point_mass_properties, rigid_body
from .build import BuildOptions, LinkBuild, build_link, build_robot
from .compare import ComparisonReport, compare_models
from .emodel import emodel, link_mass_properties, total_mass
from .flexible import flexible_arm, superelement_body
from .full_fe import full_fe_analysis, full_fe_bodies, full_fe_matrices
from .ik import IKConfig, ik, ik_analytic, ik_dls
from .joints import JointModel
from .kinematics import Chain, jacobian, joint_to_motor, link_frames, motor_to_joint, tcp_frame
from .maps import JointSpaceMap, stiffest, stiffness_map
from .robot import Robot, pose_from_string
from .system import ArmModel, SystemMatrices, rigid_tcp_map, system_matrices

__all__ = [
    "BuildOptions",
    "ComparisonReport",
    "LinkBuild",
    "build_link",
    "build_robot",
    "compare_models",
    "flexible_arm",
    "full_fe_analysis",
    "full_fe_bodies",
    "full_fe_matrices",
    "superelement_body",
    "ArmModel",
    "Body",
    "Chain",
    "IKConfig",
    "IdentificationReport",
    "JointModel",
    "JointSpaceMap",
    "Modes",
    "Robot",
    "SystemMatrices",
    "combine_mass_properties",
    "diagonal_compliance",
    "emodel",
    "frf",
    "gravity_sag",
    "identify_stiffness",
    "ik",
    "ik_analytic",
    "ik_dls",
    "jacobian",
    "joint_to_motor",
    "link_frames",
    "link_mass_properties",
    "modes",
    "motor_to_joint",
    "natural_frequencies",
    "point_mass_properties",
    "pose_from_string",
    "rigid_body",
    "rigid_tcp_map",
    "stiffest",
    "stiffness_from_load_cases",
    "stiffness_map",
    "system_matrices",
    "tcp_compliance",
    "tcp_frame",
    "total_mass",
]
