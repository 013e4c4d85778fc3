"""The size of an imported robot: its placeholder joint stiffness from the size rule
(:mod:`flexarm.robot.placeholder_stiffness`) and one line comparing the URDF's
``<inertial>`` masses with the CAD and the datasheet."""

from __future__ import annotations

import dataclasses

from ..robot.description import Robot
from ..robot.placeholder_stiffness import (
    PlaceholderStiffness,
    RobotSize,
    placeholder_stiffness,
    reach,
)

__all__ = ["sized_placeholders", "mass_line"]


def sized_placeholders(robot: Robot, mass_kg: float, mass_source: str,
                       effort: tuple[float, ...] | None = None
                       ) -> tuple[Robot, PlaceholderStiffness | None]:
    """``robot`` with the gear torsion [N m/rad] of every placeholder joint set by the
    size rule for ``mass_kg`` [kg] and the robot's reach; joints with given stiffness
    keep theirs, and a placeholder stays marked as one.  An arm of fewer than three
    joints has no reach in the rule's sense: it is returned as it is, with None.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> same, rule = sized_placeholders(robot, 425.0, "datasheet")
    >>> same.joints[1].model.torsion == robot.joints[1].model.torsion  # given: kept
    True
    >>> round(rule.size.reach, 2), f"{rule.torsion[1]:.3g}"
    (2.05, '4.27e+06')
    """
    if len(robot.joints) < 3:
        return robot, None
    size = RobotSize(float(mass_kg), reach(robot.chain, robot.lower, robot.upper), effort,
                     mass_source)
    rule = placeholder_stiffness(size, len(robot.joints))
    joints = tuple(
        dataclasses.replace(j, model=dataclasses.replace(j.model, torsion=k))
        if j.model.is_placeholder else j
        for j, k in zip(robot.joints, rule.torsion, strict=True))
    return dataclasses.replace(robot, joints=joints), rule


def mass_line(inertial_kg: float | None, solid_kg: float, datasheet_kg: float | None) -> str:
    """One line: the URDF's ``<inertial>`` mass sum [kg] against the datasheet mass (or
    the CAD's when none is given), and the mass of the solid CAD [kg].

    Examples
    --------
    >>> mass_line(32.7, 149.2, 28.9)
    'mass: URDF <inertial> 32.7 kg, +13.1 % vs the datasheet 28.9 kg (used); solid CAD 149.2 kg'
    >>> mass_line(None, 931.1, 250.0)
    'mass: no URDF <inertial>; datasheet 250.0 kg (used); solid CAD 931.1 kg'
    """
    if datasheet_kg is None:
        used = ("URDF <inertial> sum used for the stiffness rule; the CAD keeps its densities"
                if inertial_kg is not None else "no datasheet mass: the CAD's is used")
        head = ("no URDF <inertial>" if inertial_kg is None else
                f"URDF <inertial> {inertial_kg:.1f} kg, "
                f"{100 * (inertial_kg / solid_kg - 1):+.1f} % vs the solid CAD")
        return f"mass: {head}; solid CAD {solid_kg:.1f} kg ({used})"
    if inertial_kg is None:
        return (f"mass: no URDF <inertial>; datasheet {datasheet_kg:.1f} kg (used); "
                f"solid CAD {solid_kg:.1f} kg")
    return (f"mass: URDF <inertial> {inertial_kg:.1f} kg, "
            f"{100 * (inertial_kg / datasheet_kg - 1):+.1f} % vs the datasheet "
            f"{datasheet_kg:.1f} kg (used); solid CAD {solid_kg:.1f} kg")
