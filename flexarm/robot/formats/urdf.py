"""URDF import: a published robot description -> :class:`Robot`.

What becomes what:

* **Moving links.**  The root and every child of a revolute or continuous joint is a
  :class:`Link`.  Its CAD is its ``<collision>`` (or ``<visual>``) elements: one mesh at
  the link frame is used as published (STL, OBJ, PLY, DAE; a uniform ``scale`` becomes
  the units); anything else is merged into one derived STL in the link frame
  (:mod:`~flexarm.robot.formats.urdf_meshes`).  A link with no geometry of that kind
  takes the other kind (a warning names it).
* **Fixed joints** are merged: the child link's geometry and ``<inertial>`` join the
  moving link it is fixed to, placed by the fixed joint's origin.  A fixed child without
  geometry or inertial is a pure frame; ``tool0`` (else ``flange``) sets
  :attr:`Robot.tool` on its moving link.
* **Mass.**  A link's CAD gets the material's density; a link (or merged fixed child)
  without geometry contributes its ``<inertial>`` as a :class:`LumpedMass`.  The
  ``<inertial>`` of a link that has geometry is not used (its mass is the CAD's).  A
  moving link with neither is an error.
* **Joints** keep their origin (in the parent's link frame, fixed offsets folded in),
  axis and limits (continuous: +-360 deg); a ``<mimic>`` is not modelled (a warning
  names the joint).  A URDF carries no stiffness: every joint gets
  the default gear torsion :data:`DEFAULT_TORSION` and rigid bearings, marked
  ``source="placeholder"`` until identified (``flexarm diagnose --apply``);
  :func:`flexarm.studies.import_urdf.import_urdf` scales it to the robot's size
  (:mod:`~flexarm.robot.placeholder_stiffness`), from the ``<limit effort>`` and
  ``<inertial>`` masses the import keeps (:class:`UrdfImport`).
* **Regions** (interface seats) are left empty: the link's seats are found from its CAD
  by the caller.

Anything that cannot be imported faithfully (prismatic, planar or floating joints,
closed loops, missing links or mesh files, duplicate names) is one error naming the file
and the joint or link; nothing is dropped silently.
"""

from __future__ import annotations

import logging
import math
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.material import MATERIALS
from ..description import Joint, Link, LumpedMass, ModelOptions, Robot, Tool
from ..joints import JointModel
from .urdf_meshes import Piece, merged_mesh, published, write_derived
from .urdf_tree import UrdfTree, parse_tree, xyz_rpy

__all__ = ["read", "load", "UrdfImport", "DEFAULT_TORSION", "TOOL_FRAMES", "default_derived_dir",
           "published_names"]

log = logging.getLogger(__name__)

#: Placeholder gear torsion stiffness [N m/rad] of the main axes (1-3) and the wrist.
DEFAULT_TORSION = (1.0e6, 2.0e5)
#: Frames that set the tool, in order of preference.
TOOL_FRAMES = ("tool0", "flange")
_MESH_KINDS = ("collision", "visual")
_CONTINUOUS = 2 * math.pi  # limits [rad] of a continuous joint (and of one without <limit>)


def default_derived_dir() -> Path:
    """Where derived link meshes go unless the caller says: the package cache's
    ``urdf-meshes`` folder."""
    from ...fe.cache import cache_root

    return cache_root() / "urdf-meshes"


@dataclass(frozen=True, eq=False)
class UrdfImport:
    """A URDF read as a :class:`Robot` plus what the import did.

    ``tool_frame`` is the URDF frame that set the tool (``"tool0"``, ``"flange"`` or
    None); ``merged`` maps a moving link to the fixed links merged into it (frames
    included); ``derived`` maps a link to the derived STL written for it (links absent
    use their published mesh or have none); ``inertial_mass`` [kg] is the sum of every
    ``<inertial>`` mass in the file (None: it gives none) and ``effort`` [N m] the torque
    limit of each moving joint (None unless the file gives every joint one).  ``sources``
    maps a link with a derived mesh to what it was made from, as the URDF writes it (mesh
    filenames, ``<box>``/``<cylinder>``/``<sphere>``): the names a message about the link's
    CAD gives the user.
    """

    robot: Robot
    tool_frame: str | None
    merged: dict
    derived: dict
    inertial_mass: float | None = None
    effort: tuple[float, ...] | None = None
    sources: dict = field(default_factory=dict)

    @property
    def placeholder_joints(self) -> tuple[str, ...]:
        """Joints whose stiffness is a placeholder (all of them, for a URDF)."""
        return tuple(j.name for j in self.robot.joints if j.model.is_placeholder)


def load(path, meshes: str = "collision", material: str = "cast_iron",
         derived_dir=None) -> UrdfImport:
    """Read a URDF as an :class:`UrdfImport` (the robot and what the import did).

    Parameters
    ----------
    path : path-like
        The ``.urdf`` file.
    meshes : {"collision", "visual"}
        Which geometry elements become the link CAD (a link without them takes the other).
    material : str
        Material name of every link (:data:`~flexarm.fe.material.MATERIALS`).
    derived_dir : path-like, optional
        Folder for derived link meshes (default :func:`default_derived_dir`).

    Raises
    ------
    ReadError
        One line naming the file and the joint or link that cannot be imported.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "r.urdf").write_text(
    ...     '<robot name="r"><link name="a"><inertial><mass value="5"/></inertial></link>'
    ...     '<link name="b"><inertial><origin xyz="0.5 0 0"/><mass value="2"/></inertial>'
    ...     '</link><link name="tool0"/><joint name="j1" type="revolute"><parent link="a"/>'
    ...     '<child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>'
    ...     '<joint name="f" type="fixed"><origin xyz="0.6 0 0"/><parent link="b"/>'
    ...     '<child link="tool0"/></joint></robot>')
    >>> imp = load(folder / "r.urdf")
    >>> imp.robot.links[1].lumped[0].mass, imp.tool_frame, imp.robot.tool.xyz
    (2.0, 'tool0', (0.6, 0.0, 0.0))
    >>> imp.placeholder_joints
    ('j1',)
    """
    return _read_warned(path, meshes, material, derived_dir)


def read(path, meshes: str = "collision", material: str = "cast_iron",
         derived_dir=None) -> Robot:
    """Read a URDF as a :class:`Robot`; see :func:`load` (this is its ``robot``).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "r.urdf").write_text(
    ...     '<robot name="r"><link name="a"><inertial><mass value="5"/></inertial></link>'
    ...     '<link name="b"><inertial><mass value="2"/></inertial></link>'
    ...     '<joint name="j1" type="continuous"><parent link="a"/><child link="b"/>'
    ...     '</joint></robot>')
    >>> read(folder / "r.urdf").joint_names
    ('j1',)
    """
    return _read_warned(path, meshes, material, derived_dir).robot


def _read_warned(path, meshes: str, material: str, derived_dir) -> UrdfImport:
    """The import; its notes are warnings pointing at the caller of :func:`load` or
    :func:`read`."""
    imported, notes = _read(Path(path), meshes, material, derived_dir)
    for note in notes:
        warnings.warn(note, stacklevel=3)
    return imported


def _read(path: Path, meshes: str, material: str, derived_dir) -> tuple[UrdfImport, list[str]]:
    """The import and its warnings (each naming the file and the link)."""
    if meshes not in _MESH_KINDS:
        raise ValueError(f"meshes must be collision|visual, got '{meshes}'")
    if material not in MATERIALS:
        raise ValueError(f"unknown material '{material}' (known: {'|'.join(MATERIALS)})")
    folder = default_derived_dir() if derived_dir is None else Path(derived_dir)
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise ReadError(f"{path}: {exc}") from None
    notes: list[str] = []
    try:
        imported = _import(path, parse_tree(root), meshes, material, folder, notes)
    except ValueError as exc:
        raise ReadError(f"{path}: {exc}") from None
    return imported, [f"{path.name}: {n}" for n in notes]


def _bodies(tree: UrdfTree) -> tuple[dict[str, str], dict[str, np.ndarray]]:
    """The moving link every URDF link belongs to and its frame (4, 4) in that link."""
    body_of, T = {tree.root: tree.root}, {tree.root: np.eye(4)}
    for j in tree.joints:  # parents come first
        if j.moves:
            body_of[j.child], T[j.child] = j.child, np.eye(4)
        else:
            body_of[j.child], T[j.child] = body_of[j.parent], T[j.parent] @ j.origin
    return body_of, T


def _import(path: Path, tree: UrdfTree, meshes: str, material: str, folder: Path,
            notes: list[str]) -> UrdfImport:
    body_of, T = _bodies(tree)
    moving = [j for j in tree.joints if j.moves]
    if not moving:
        raise ValueError("no revolute or continuous joints (nothing moves)")
    names = [tree.root] + [j.child for j in moving]
    members = {b: [n for n in tree.links if body_of[n] == b] for b in names}
    # members in walk order: the moving link first, then its fixed children as walked
    walk = [tree.root] + [j.child for j in tree.joints]
    members = {b: sorted(m, key=walk.index) for b, m in members.items()}
    links, derived, sources = [], {}, {}
    for b in names:
        link, mesh_file = _link(path, tree, b, members[b], T, meshes, material, folder, notes)
        links.append(link)
        if mesh_file is not None:
            derived[b] = mesh_file
            sources[b] = _sources(tree, members[b], meshes)
    joints = []
    for k, j in enumerate(moving):
        xyz, rpy = xyz_rpy(T[j.parent] @ j.origin)
        lo, hi = (-_CONTINUOUS, _CONTINUOUS) if j.lower is None else (j.lower, j.upper)
        if not lo < hi:
            raise ValueError(f"joint '{j.name}': limit lower={lo:g} must be below "
                             f"upper={hi:g} rad")
        if j.mimic is not None:
            notes.append(f"joint '{j.name}': <mimic joint=\"{j.mimic}\"> not modelled "
                         "(it turns on its own)")
        model = JointModel(torsion=DEFAULT_TORSION[0] if k < 3 else DEFAULT_TORSION[1],
                           source="placeholder")
        joints.append(Joint(j.name, body_of[j.parent], j.child, xyz,
                            tuple(float(a) for a in j.axis), lo, hi, model, rpy))
    tool_frame, tool = _tool(tree, body_of, T)
    poses = {"home": [0.0] * len(joints)} if all(j.lower <= 0 <= j.upper
                                                   for j in joints) else {}
    # "auto": Gmsh wherever the published CAD allows, so the same URDF gives the same model
    robot = Robot(tree.name, tuple(links), tuple(joints), tool=tool, poses=poses,
                  options=ModelOptions(mesher="auto"), source=path.resolve())
    merged = {b: tuple(members[b][1:]) for b in names if len(members[b]) > 1}
    log.info("URDF %s: %d links, %d joints, %d derived meshes", path.name, len(links),
             len(joints), len(derived))
    inertials = [lk.inertial.mass for lk in tree.links.values() if lk.inertial is not None]
    effort = tuple(j.effort for j in moving)
    return UrdfImport(robot, tool_frame, merged, derived,
                      float(sum(inertials)) if inertials else None,
                      effort if all(e is not None for e in effort) else None, sources)


def published_names(text: str, meshes: dict, sources: dict) -> str:
    """``text`` with the derived mesh path of each link in ``meshes`` (link name -> path)
    replaced by what the URDF made it from (``sources``: link name -> names, as
    :attr:`UrdfImport.sources`), so that a message names the user's files.

    Examples
    --------
    >>> published_names("/cache/forearm_link-1f.stl: not a closed surface",
    ...                 {"forearm_link": "/cache/forearm_link-1f.stl"},
    ...                 {"forearm_link": ("package://ur/forearm.stl",)})
    'package://ur/forearm.stl: not a closed surface'
    """
    for link, path in meshes.items():
        if path is not None and sources.get(link):
            text = text.replace(str(path), " + ".join(sources[link]))
    return text


def _sources(tree: UrdfTree, members: list[str], meshes: str) -> tuple[str, ...]:
    """What a derived link mesh is made of, as the URDF writes it (filenames, shapes)."""
    names = [g.filename if g.filename else f"<{g.shape}>" for name in members
             for g in _geometry(tree, name, meshes, [])]
    return tuple(dict.fromkeys(names))


def _geometry(tree: UrdfTree, name: str, meshes: str, notes: list[str]):
    lk = tree.links[name]
    other = "visual" if meshes == "collision" else "collision"
    if lk.geometry(meshes) or not lk.geometry(other):
        return lk.geometry(meshes)
    notes.append(f"link '{name}': no {meshes} geometry, using the {other} one")
    return lk.geometry(other)


def _lumped(tree: UrdfTree, name: str, T: np.ndarray) -> LumpedMass:
    """The ``<inertial>`` of link ``name`` as a lumped mass in the frame ``T`` places it."""
    inertial = tree.links[name].inertial
    F = T @ inertial.origin
    R = F[:3, :3]
    inertia = R @ inertial.inertia @ R.T
    return LumpedMass(f"{name} (URDF inertial)", inertial.mass,
                      tuple(float(v) for v in F[:3, 3]), tuple(map(tuple, inertia.tolist())))


def _link(path: Path, tree: UrdfTree, body: str, members: list[str], T: dict, meshes: str,
          material: str, folder: Path, notes: list[str]) -> tuple[Link, Path | None]:
    """The :class:`Link` of moving link ``body`` with its fixed ``members`` merged in, and
    the derived mesh written for it (None when it uses a published one or has none)."""
    pieces, lumped = [], []
    for name in members:
        geometry = _geometry(tree, name, meshes, notes)
        if geometry:
            pieces += [Piece(g, T[name] @ g.origin, name) for g in geometry]
            if tree.links[name].inertial is not None:
                log.info("link %s: <inertial> not used (the mass comes from the CAD)", name)
        elif tree.links[name].inertial is not None:
            lumped.append(_lumped(tree, name, T[name]))
    if not pieces and not sum(m.mass for m in lumped) > 0:
        what = "the base" if body == tree.root else "a moving link"
        raise ValueError(f"link '{body}' ({what}) has no mesh and no <inertial> mass: give it "
                         "a <collision> or <visual> mesh or an <inertial>")
    mesh, units, written = None, "m", None
    if len(pieces) == 1:
        as_published = published(pieces[0], path)
        if as_published is not None:
            mesh, units = as_published
    if pieces and mesh is None:
        written = write_derived(merged_mesh(pieces, path, body), folder, body)
        mesh = written
    return Link(body, mesh, MATERIALS[material], units, tuple(lumped), {}), written


def _tool(tree: UrdfTree, body_of: dict, T: dict) -> tuple[str | None, Tool]:
    """The tool frame (``tool0``, else ``flange``) fixed to a moving link, and its Tool."""
    for name in TOOL_FRAMES:
        if name in tree.links and body_of[name] != name:
            xyz, rpy = xyz_rpy(T[name])
            return name, Tool(xyz, rpy, body_of[name])
    return None, Tool()
