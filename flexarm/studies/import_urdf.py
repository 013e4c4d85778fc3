"""A URDF robot made ready for flexarm: its description with densities scaled to the
datasheet mass (the CAD of a URDF is a solid hull of hollow castings), derived link
meshes next to the robot file, and a report of what came in and what is a placeholder."""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from ..assembly.emodel import total_mass, with_total_mass
from ..fe.typing import PathType
from ..robot.description import Robot
from ..robot.formats import urdf
from ..robot.hollowing import Hollowing, hollow_links
from ..robot.placeholder_stiffness import PlaceholderStiffness
from ..robot.seat_review import MissingSeat, with_seats
from ..robot.seats import find_seats
from .import_stiffness import mass_line, sized_placeholders
from .seat_check import pair_checks, pairs_line

__all__ = ["ImportedRobot", "import_urdf", "derived_meshes_dir"]


@dataclass(frozen=True, eq=False)
class ImportedRobot:
    """The imported ``robot``, the mass of its solid CAD as given [kg] and its mass after
    any density scaling [kg] (links and lumped masses, surface integrals), the URDF frame
    that set the tool (None: no ``tool0``/``flange``), the fixed links ``merged`` into
    each moving link and the ``derived`` meshes written per link; ``missing`` holds the
    :class:`~flexarm.robot.seat_review.MissingSeat` s (seats not found on the CAD, each
    with its suggested region written for review); ``mesh_estimate`` says how long
    ``flexarm build`` will mesh the hollowed links (empty without hollowing); ``pairs``
    holds the two seats of each joint checked against each other
    (:class:`~flexarm.studies.seat_check.PairCheck`)."""

    robot: Robot
    solid_mass: float
    mass: float
    tool_frame: str | None = None
    merged: dict = field(default_factory=dict)
    derived: dict = field(default_factory=dict)
    hollowing: Hollowing | None = None
    stiffness: PlaceholderStiffness | None = None
    mass_note: str = ""
    missing: tuple = ()
    mesh_estimate: str = ""
    pairs: tuple = ()

    @property
    def placeholder_joints(self) -> tuple[str, ...]:
        """Joints whose stiffness is an unmeasured default."""
        return tuple(j.name for j in self.robot.joints if j.model.is_placeholder)

    def summary(self) -> str:
        """``N links, M joints, X kg (solid CAD: Y kg)``."""
        n = len(self.robot.joints)
        return (f"{len(self.robot.links)} links, {n} joint{'s' if n > 1 else ''}, "
                f"{self.mass:.1f} kg (solid CAD: {self.solid_mass:.1f} kg)")

    def report(self, robot_file: PathType = "ROBOT.toml") -> list[str]:
        """Lines on the links, joints, tool frame and placeholder stiffness (the hint names
        ``robot_file``, the file the robot is written to)."""
        links = []
        for lk in self.robot.links:
            extra = self.merged.get(lk.name, ())
            links.append(lk.name + (f" (+ {', '.join(extra)})" if extra else ""))
        n_meshed = sum(lk.mesh is not None for lk in self.robot.links)
        n_hollow = 0 if self.hollowing is None else sum(
            not lk.is_solid for lk in self.hollowing.links)
        n_derived = len(set(self.derived) | {lk.name for lk in (
            self.hollowing.links if self.hollowing else ()) if not lk.is_solid})
        meshes = f"{n_meshed - n_derived} as published, {n_derived} derived"
        if n_hollow:
            meshes += f" ({n_hollow} hollowed)"
        folders = {Path(lk.mesh).parent for lk in self.robot.links
                   if lk.mesh is not None and (lk.name in self.derived or n_hollow)}
        if n_derived and len(folders) == 1:
            meshes += f" in {folders.pop()}"
        lines = [f"links: {', '.join(links)}; meshes: {meshes}",
                 f"joints: {', '.join(self.robot.joint_names)}", self._tool_line()]
        if self.hollowing is not None:  # shells take more elements: say how long they take
            lines += self.hollowing.text().splitlines()
            lines += [self.mesh_estimate] if self.mesh_estimate else []
        n_regions = sum(len(lk.regions) for lk in self.robot.links)
        if n_regions:
            n_review = sum(m.region is not None for m in self.missing)
            names = ", ".join(f"{m.link}:{m.joint}" for m in self.missing if m.region)
            found = (f"{n_regions} regions found on the link CAD" if not n_review else
                     f"{n_regions - n_review} regions found on the link CAD and {n_review} "
                     f"suggested (review = true: {names})")
            lines.append(f"bearing seats: {found}, written out for review (`flexarm "
                         f"show-regions --robot {robot_file} -o DIR`)")
            if self.pairs:
                lines.append(pairs_line(self.pairs))
        if self.mass_note:
            lines.append(self.mass_note)
        if self.placeholder_joints:
            lines.append(
                f"placeholder stiffness (a URDF has none) on {', '.join(self.placeholder_joints)}"
                f": identify it from measurements with `flexarm diagnose MEASURED.csv --robot "
                f"{robot_file} --apply -o IDENTIFIED.toml`")
            if self.stiffness is not None:
                lines.append(f"placeholder {self.stiffness.text()}")
        return lines

    def _tool_line(self) -> str:
        tool = self.robot.tool
        on = tool.link or self.robot.links[-1].name
        if self.tool_frame is None:
            return f"tool: no tool0 or flange frame in the URDF (TCP at the {on} frame)"
        xyz = ", ".join(f"{v:.4g}" for v in tool.xyz)
        rpy = ", ".join(f"{math.degrees(v):.4g}" for v in tool.rpy)
        return f"tool: {self.tool_frame} on {on}, xyz [{xyz}] m, rpy [{rpy}] deg"


def derived_meshes_dir(robot_file: PathType) -> Path:
    """The folder next to a robot TOML for its derived link meshes: ``DIR/<stem>_meshes``
    (so the TOML and its meshes move together).

    Examples
    --------
    >>> derived_meshes_dir("out/irb.toml").as_posix()
    'out/irb_meshes'
    """
    p = Path(robot_file)
    return p.parent / f"{p.stem}_meshes"


def import_urdf(path: PathType, meshes: str = "collision", mass_kg: float | None = None,
                derived_dir: PathType | None = None, wall: float | str | None = None,
                regions: bool = True, seats=()) -> ImportedRobot:
    """Read a URDF, optionally hollow its solid link hulls, find every bearing seat on the
    link CAD, and match the datasheet mass.

    Parameters
    ----------
    path : path-like
        The ``.urdf`` file (meshes resolved next to it or through ``package://``).
    meshes : {"collision", "visual"}
        Which URDF geometry becomes the link CAD.
    mass_kg : float, optional
        The robot's real mass [kg] (datasheet).  Without ``wall`` every link density is
        scaled by one factor (stiffness kept); with a given ``wall`` the densities of the
        shells are scaled; with ``wall="auto"`` the wall is chosen to match it.
    derived_dir : path-like, optional
        Folder for link meshes the import derives (merged elements, origins, scales,
        merged fixed links, shells); default the package cache.  Pass
        :func:`derived_meshes_dir` of the robot TOML to keep the TOML relocatable.
    wall : float or "auto", optional
        Hollow every link hull to walls this thick [m] (:mod:`flexarm.robot.hollowing`).
    regions : bool
        Find the bearing seats (:func:`flexarm.robot.seats.find_seats`); they are
        written into the robot file for review.  A seat not found gets a suggested region
        marked ``review = true`` and one warning naming the link, the joint and the fix
        (``ImportedRobot.missing``); the other seats are found all the same.
    seats : iterable of (link, joint, Region)
        Seats given by hand (:func:`flexarm.robot.seat_review.parse_seat`), kept as given
        [m, link frame]; the finder pairs the other link's seat with them.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "r.urdf").write_text(
    ...     '<robot name="r"><link name="a"><inertial><mass value="5"/></inertial></link>'
    ...     '<link name="b"><inertial><mass value="2"/></inertial></link>'
    ...     '<joint name="j1" type="continuous"><parent link="a"/><child link="b"/>'
    ...     '</joint></robot>')
    >>> imported = import_urdf(folder / "r.urdf")
    >>> imported.summary(), imported.placeholder_joints
    ('2 links, 1 joint, 7.0 kg (solid CAD: 7.0 kg)', ('j1',))
    """
    imported = urdf.load(path, meshes=meshes, derived_dir=derived_dir)
    robot = imported.robot
    solid = total_mass(robot, "surface")
    missing = ()
    if seats:
        robot = with_seats(robot, seats)
    if regions:  # on the outer CAD: a shell's cavity would read as bores and faces
        robot, missing = _seat_regions(robot, imported.sources)
    hollowing = None
    if wall is not None:
        robot, hollowing = hollow_links(robot, wall, mass_kg, derived_dir, imported.sources)
    if mass_kg is not None and wall != "auto":
        robot = with_total_mass(robot, mass_kg)
    mass = total_mass(robot, "surface")
    if mass_kg is not None:
        rule_mass, source = mass_kg, "datasheet"
    elif imported.inertial_mass is not None:
        rule_mass, source = imported.inertial_mass, "URDF inertials"
    else:
        rule_mass, source = mass, "CAD"
    robot, stiffness = sized_placeholders(robot, rule_mass, source, imported.effort)
    pairs = _checked_pairs(robot) if regions else ()
    return ImportedRobot(robot, solid, mass, imported.tool_frame, imported.merged,
                         imported.derived, hollowing, stiffness,
                         mass_line(imported.inertial_mass, solid, mass_kg), missing,
                         "" if hollowing is None else _mesh_estimate(robot), pairs)


def _checked_pairs(robot: Robot) -> tuple:
    """The seat pairs of the robot as written, one warning per pair that does not hold
    (a pair with a seat not found is the missing seat's warning already)."""
    from ..fe.errors import MeshError

    try:
        checks = pair_checks(robot)
    except MeshError:  # a CAD that cannot be read: said already, by the seat search
        return ()
    for c in checks:
        if c.problem and not c.pair.missing:
            warnings.warn(c.warning(), stacklevel=3)
    return checks


def _mesh_estimate(robot: Robot) -> str:
    """One line: about how many tetrahedra ``flexarm build`` makes at the robot's mesh size
    and how long that takes, one process per core (hollowed shells take more: their walls
    get a layer of elements however thin)."""
    from ..fe.errors import MeshError
    from ..fe.processes import default_jobs
    from ..meshes import load_surface
    from ..meshes.auto_mesher import mesh_time_estimate

    size, mesher = robot.options.mesh_size, robot.options.mesher
    estimates = []
    for lk in robot.links:
        try:
            surface = None if lk.mesh is None else load_surface(lk.mesh, units=lk.units)
        except MeshError:  # said already, by the seat search
            surface = None
        if surface is not None:
            estimates.append(mesh_time_estimate(surface, size, mesher))
    if not estimates:
        return ""
    jobs = min(default_jobs(), len(estimates))
    n = sum(e[0] for e in estimates)
    seconds = max(sum(e[1] for e in estimates) / jobs, max(e[1] for e in estimates))
    return (f"meshing estimate (`flexarm build`, {mesher}, {size * 1e3:g} mm edge): about "
            f"{n:,.0f} tetrahedra in about {seconds:.0f} s on {jobs} "
            f"process{'es' if jobs > 1 else ''}")


def _seat_regions(robot: Robot, sources: dict) -> tuple[Robot, tuple]:
    """``robot`` with its bearing seats found on the link CAD, and the seats not found
    (each with one warning naming the link, the joint and the fix).  A link whose CAD is
    not a closed surface (one warning naming its file as the URDF writes it, ``sources``)
    gets no seats: a seat needs the solid's outside, and a flexible model needs a closed
    surface anyway."""
    from ..fe.errors import MeshError
    from ..meshes import load_surface

    unreadable = {}
    for lk in robot.links:
        if lk.mesh is None:
            continue
        try:
            load_surface(lk.mesh, units=lk.units)
        except MeshError as exc:
            unreadable[lk.name] = why = urdf.published_names(str(exc), {lk.name: lk.mesh},
                                                             sources)
            warnings.warn(f"links.{lk.name}: no bearing seats looked for on {why}", stacklevel=3)
    searched = dataclasses.replace(robot, links=tuple(
        dataclasses.replace(lk, mesh=None) if lk.name in unreadable else lk
        for lk in robot.links))
    res = find_seats(searched)
    missing = list(res.missing) + [
        MissingSeat(lk, jt.name, f"the CAD of {bad} is not a closed surface")
        for jt in robot.joints for bad in (jt.parent, jt.child) if bad in unreadable
        for lk in (jt.parent, jt.child)]
    for m in missing:
        warnings.warn(m.warning(), stacklevel=3)
    links = tuple(dataclasses.replace(lk, regions=found.regions)
                  for lk, found in zip(robot.links, res.robot.links, strict=True))
    return dataclasses.replace(robot, links=links), tuple(missing)
