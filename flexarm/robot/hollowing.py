"""Links whose CAD is a solid hull of a hollow casting, hollowed to walls of one thickness.

A URDF's link meshes are solid hulls: in the link's material they weigh several times
the robot's datasheet mass and are far too stiff in bending.  Scaling the density fixes
the mass but not the stiffness; hollowing each hull to a shell (:mod:`flexarm.meshes.hollow`)
fixes both to first order.  The wall is given, or chosen so that the robot weighs its
datasheet mass (:func:`flexarm.meshes.wall.wall_for_mass`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..fe.typing import FloatArray, PathType
from ..meshes import load_surface
from ..meshes.hollow import hollow_surface
from ..meshes.tolerances import tol as tol_mesh
from ..meshes.wall import bending_ratio, wall_for_mass
from .description import Robot
from .formats.urdf import published_names
from .formats.urdf_meshes import write_derived

__all__ = ["HollowedLink", "Hollowing", "hollow_links"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class HollowedLink:
    """One link before and after hollowing: masses [kg] of its CAD in its material, the
    bending proxy per principal axis (shell over solid second moments of volume, [-]),
    and whether the wall left it solid."""

    name: str
    solid_mass: float
    shell_mass: float
    bending: FloatArray
    is_solid: bool


@dataclass(frozen=True)
class Hollowing:
    """The wall [m], how it was chosen, and every hollowed link."""

    wall: float
    matched_mass: float | None
    links: tuple[HollowedLink, ...]

    def text(self) -> str:
        """One line on the wall, then one per link: mass and bending proxy."""
        how = (f"the wall that makes the robot weigh {self.matched_mass:g} kg"
               if self.matched_mass is not None else "given")
        lines = [f"link CAD hollowed to {self.wall * 1e3:.1f} mm walls ({how}); bending "
                 "stiffness proxy = shell / solid second moment of volume per principal axis"]
        for lk in self.links:
            state = "stays solid (thinner than the wall)" if lk.is_solid else (
                "bending x " + "/".join(f"{b:.2f}" for b in lk.bending))
            lines.append(f"  {lk.name}: {lk.solid_mass:.1f} -> {lk.shell_mass:.1f} kg, {state}")
        return "\n".join(lines)


def hollow_links(robot: Robot, wall: float | str, mass_kg: float | None = None,
                 out_dir: PathType | None = None,
                 sources: dict | None = None) -> tuple[Robot, Hollowing]:
    """``robot`` with every meshed link's CAD hollowed to walls of ``wall`` [m].

    Parameters
    ----------
    robot : Robot
    wall : float or "auto"
        Wall thickness [m], or ``"auto"``: the one thickness at which the links and their
        lumped masses weigh ``mass_kg``.
    mass_kg : float, optional
        The robot's datasheet mass [kg] (needed for ``"auto"``).
    out_dir : path-like, optional
        Folder for the shell STLs (content-named; default: the package cache).
    sources : dict, optional
        Link name -> the files its (derived) mesh was made from, as the URDF writes them
        (:attr:`~flexarm.robot.formats.urdf.UrdfImport.sources`): a refusal names those,
        never flexarm's derived file.

    Returns
    -------
    (Robot, Hollowing)
        The robot with its links pointing at the shells (metres), and the report.

    Examples
    --------
    >>> import pathlib, tempfile, trimesh
    >>> from flexarm.robot import Link, Joint, JointModel, Robot
    >>> from flexarm.fe import MATERIALS
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> for name in "ab":
    ...     _ = trimesh.creation.box((0.2, 0.2, 0.2)).export(folder / f"{name}.stl")
    >>> links = tuple(Link(n, folder / f"{n}.stl", MATERIALS["steel"]) for n in "ab")
    >>> arm = Robot("boxes", links, (Joint("j1", "a", "b", (0, 0, 0.2), (0, 0, 1), -3, 3,
    ...                                     JointModel(1e5)),))
    >>> hollowed, report = hollow_links(arm, 0.01, out_dir=folder)
    >>> round(report.links[0].shell_mass, 3)  # 7850 * (0.2^3 - 0.18^3) [kg]
    17.019
    """
    meshed = [lk for lk in robot.links if lk.mesh is not None]
    if not meshed:
        raise ValueError("no link has a CAD mesh to hollow")
    label = {lk.name: _label(lk, sources or {}) for lk in meshed}
    surfaces = [_surface(lk, sources or {}) for lk in meshed]
    rho = np.array([lk.material.rho for lk in meshed])
    matched = None
    if wall == "auto":
        if mass_kg is None:
            raise ValueError("a wall matched to the mass needs the robot's mass (--total-mass)")
        lumped = sum(m.mass for lk in robot.links for m in lk.lumped)
        wall = wall_for_mass(surfaces, rho, float(mass_kg), lumped,
                             names=[label[lk.name] for lk in meshed])
        matched = float(mass_kg)
    wall = float(wall)
    if not np.isfinite(wall) or wall <= 0:
        raise ValueError(f"wall thickness must be a positive length [m], got {wall}")
    folder = Path(out_dir) if out_dir is not None else None
    new_links, rows = dict(), []
    for lk, surface, density in zip(meshed, surfaces, rho, strict=True):
        shell = hollow_surface(surface, wall, name=label[lk.name])
        # overlapping CAD bodies count once: the solid that was hollowed
        rows.append(HollowedLink(lk.name, density * float(shell.solid.volume),
                                 density * float(shell.volume),
                                 bending_ratio(shell.solid, shell),
                                 bool(shell.is_solid)))
        if not shell.is_solid:
            path = write_derived(shell.mesh, folder if folder else _default_dir(), lk.name)
            _check_written(path, shell.volume, label[lk.name], wall)
            new_links[lk.name] = replace(lk, mesh=path, units="m")
    log.info("links hollowed to %.1f mm walls", wall * 1e3)
    links = tuple(new_links.get(lk.name, lk) for lk in robot.links)
    return replace(robot, links=links), Hollowing(wall, matched, tuple(rows))


def _label(link, sources: dict) -> str:
    """``links.NAME (FILE)``: the link and the user's CAD file(s) of it."""
    files = sources.get(link.name) or (Path(link.mesh).name,)
    return f"links.{link.name} ({' + '.join(files)})"


def _surface(link, sources: dict):
    """The link's CAD surface; a refusal names the user's files, not a derived one."""
    from ..fe.errors import MeshError

    try:
        return load_surface(link.mesh, units=link.units)
    except MeshError as exc:
        raise MeshError(published_names(str(exc), {link.name: link.mesh}, sources)) from None


def _check_written(path: Path, volume: float, label: str, wall: float) -> None:
    """Read the shell back as ``flexarm build`` will and refuse, naming the link and its
    CAD file (``label``), a shell that does not come back closed with the volume it was
    written with."""
    from ..fe.errors import MeshError

    try:
        back = load_surface(path)
    except MeshError as exc:
        path.unlink(missing_ok=True)  # nothing half-written is left for the next import
        why = str(exc).replace(str(path), "the shell")
        raise MeshError(f"{label}: hollowed to {wall * 1e3:.1f} mm walls it does not read "
                        f"back closed ({why}); import it without --wall, or with a thicker "
                        "one") from None
    if abs(float(back.volume) / volume - 1) > tol_mesh.tet_volume_warn:
        path.unlink(missing_ok=True)
        raise MeshError(f"{label}: hollowed to {wall * 1e3:.1f} mm walls it reads back with "
                        f"{float(back.volume):.4g} m^3 instead of {volume:.4g} m^3")


def _default_dir() -> Path:
    from ..fe.cache import cache_root

    return cache_root() / "hollowed-links"
