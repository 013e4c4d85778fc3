"""A URDF robot made ready for flexarm: its description with densities scaled to the
datasheet mass (the CAD of a URDF is a solid hull of hollow castings)."""

from __future__ import annotations

from dataclasses import dataclass

from ..assembly.emodel import total_mass, with_total_mass
from ..fe.typing import PathType
from ..robot.description import Robot
from ..robot.formats import urdf

__all__ = ["ImportedRobot", "import_urdf"]


@dataclass(frozen=True, eq=False)
class ImportedRobot:
    """The imported ``robot``, the mass of its solid CAD as given [kg] and its mass after
    any density scaling [kg] (links and lumped masses, surface integrals)."""

    robot: Robot
    solid_mass: float
    mass: float

    def summary(self) -> str:
        """``N links, M joints, X kg (solid CAD: Y kg)``."""
        return (f"{len(self.robot.links)} links, {len(self.robot.joints)} joints, "
                f"{self.mass:.1f} kg (solid CAD: {self.solid_mass:.1f} kg)")


def import_urdf(path: PathType, meshes: str = "collision",
                mass_kg: float | None = None) -> ImportedRobot:
    """Read a URDF and, given ``mass_kg`` [kg], scale every link density by one factor so
    the robot weighs that much (stiffness is kept).

    Parameters
    ----------
    path : path-like
        The ``.urdf`` file (meshes resolved next to it or through ``package://``).
    meshes : {"collision", "visual"}
        Which URDF meshes become the link CAD.
    mass_kg : float, optional
        The robot's real mass [kg] (datasheet).
    """
    robot = urdf.read(path, meshes=meshes)
    solid = total_mass(robot, "surface")
    if mass_kg is not None:
        robot = with_total_mass(robot, mass_kg)
    return ImportedRobot(robot, solid, total_mass(robot, "surface"))
