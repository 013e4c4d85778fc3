"""The arm at a pose: bodies (rigid or superelement), the exact-elimination system, the
E-model, the flexible and full-FE arms, and their analyses (modes, TCP compliance, FRF,
gravity sag, joint-space maps), static solves with nonlinear joint laws and the
application of named effects.

Imports :mod:`flexarm.robot` and the layers below it.
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
from .arm import Arm, ArmSpec, build_arm
from .bodies import Body, combine_mass_properties, point_mass_properties, rigid_body
from .build import BuildOptions, LinkBuild, RobotBuild, build_link, build_robot, robot_build
from .emodel import emodel, link_mass_properties, total_mass
from .flexible import flexible_arm, superelement_body
from .full_fe import full_fe_analysis, full_fe_bodies, full_fe_matrices
from .maps import JointSpaceMap, stiffest, stiffness_map
from .system import ArmModel, SystemMatrices, rigid_tcp_map, system_matrices

__all__ = [
    "Arm",
    "ArmSpec",
    "build_arm",
    "BuildOptions",
    "LinkBuild",
    "RobotBuild",
    "build_link",
    "build_robot",
    "robot_build",
    "flexible_arm",
    "full_fe_analysis",
    "full_fe_bodies",
    "full_fe_matrices",
    "superelement_body",
    "ArmModel",
    "Body",
    "IdentificationReport",
    "JointSpaceMap",
    "Modes",
    "SystemMatrices",
    "combine_mass_properties",
    "diagonal_compliance",
    "emodel",
    "frf",
    "gravity_sag",
    "identify_stiffness",
    "link_mass_properties",
    "modes",
    "natural_frequencies",
    "point_mass_properties",
    "rigid_body",
    "rigid_tcp_map",
    "stiffest",
    "stiffness_from_load_cases",
    "stiffness_map",
    "system_matrices",
    "tcp_compliance",
    "total_mass",
]
