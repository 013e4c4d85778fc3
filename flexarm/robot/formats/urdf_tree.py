"""The URDF as a checked tree: its links (geometry elements, ``<inertial>``) and joints.

:func:`parse_tree` reads the ``<robot>`` element into plain frozen records and checks
what the rest of the import relies on, each with one error naming the link or joint:
unique names, joint types flexarm models (``revolute``, ``continuous``, ``fixed``),
joints whose parent and child exist, one root, no closed loop.  The joints come in
depth-first order from the root (a walk guarded by a visited set), so every parent is
listed before its children.  Frames are (4, 4) homogeneous transforms [m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...fe.typing import FloatArray
from ..kinematics import rpy_matrix

__all__ = ["Geometry", "Inertial", "UrdfLink", "UrdfJoint", "UrdfTree", "parse_tree", "frame",
           "xyz_rpy", "MOVING", "SHAPES"]

#: Joint types that move (flexarm arms turn about revolute joints); ``fixed`` merges.
MOVING = ("revolute", "continuous")
_FIXED = "fixed"
#: Geometry elements a link may carry.
SHAPES = ("mesh", "box", "cylinder", "sphere")
_XACRO = "ros.org/wiki/xacro}"  # the end of the namespace of xacro elements (www. or not)
_GIMBAL = 1e-9  # |cos(pitch)| below this: roll and yaw share one axis, yaw is set to 0


def frame(xyz, rpy) -> FloatArray:
    """(4, 4) transform of a URDF ``<origin>``: translation ``xyz`` [m], ``rpy`` [rad].

    Examples
    --------
    >>> frame([0, 0, 0.5], [0, 0, 0])[:3, 3].tolist()
    [0.0, 0.0, 0.5]
    """
    T = np.eye(4)
    T[:3, :3] = rpy_matrix(rpy)
    T[:3, 3] = xyz
    return T


def xyz_rpy(T) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Translation [m] and URDF roll-pitch-yaw [rad] of a (4, 4) transform (the inverse of
    :func:`frame`; at pitch +-90 deg, where roll and yaw turn about one axis, yaw is 0).

    Examples
    --------
    >>> xyz, rpy = xyz_rpy(frame([0.1, 0, 0], [0.3, -0.2, 1.0]))
    >>> [round(v, 12) for v in xyz + rpy]
    [0.1, 0.0, 0.0, 0.3, -0.2, 1.0]
    """
    T = np.asarray(T, dtype=float)
    R = T[:3, :3]
    pitch = math.asin(float(np.clip(-R[2, 0], -1.0, 1.0)))
    if abs(math.cos(pitch)) > _GIMBAL:
        roll, yaw = math.atan2(R[2, 1], R[2, 2]), math.atan2(R[1, 0], R[0, 0])
    elif pitch > 0:
        roll, yaw = math.atan2(R[0, 1], R[1, 1]), 0.0
    else:
        roll, yaw = math.atan2(-R[0, 1], R[1, 1]), 0.0
    # + 0.0 turns -0.0 (asin(-0.0), atan2(-0.0, 1)) into 0.0 for the files people read
    return (tuple(float(v) + 0.0 for v in T[:3, 3]),
            (roll + 0.0, pitch + 0.0, yaw + 0.0))


@dataclass(frozen=True, eq=False)
class Geometry:
    """One ``<visual>`` or ``<collision>`` element of a link.

    ``origin`` (4, 4) is the element in its link's frame; ``shape`` one of :data:`SHAPES`;
    a mesh has its ``filename`` as written and ``scale`` (3,); a box ``size`` (x, y, z),
    a cylinder (radius, length) along z, a sphere (radius,) [m].
    """

    kind: str
    origin: FloatArray
    shape: str
    filename: str | None = None
    scale: tuple = (1.0, 1.0, 1.0)
    size: tuple = ()


@dataclass(frozen=True, eq=False)
class Inertial:
    """A link's ``<inertial>``: ``mass`` [kg], its ``origin`` (4, 4) in the link frame
    (centre of mass, principal-axis rotation) and ``inertia`` (3, 3) [kg m^2] about the
    centre of mass in that rotated frame."""

    mass: float
    origin: FloatArray
    inertia: FloatArray


@dataclass(frozen=True, eq=False)
class UrdfLink:
    """A ``<link>``: its visual and collision elements in file order and its inertial."""

    name: str
    visuals: tuple[Geometry, ...] = ()
    collisions: tuple[Geometry, ...] = ()
    inertial: Inertial | None = None

    def geometry(self, kind: str) -> tuple[Geometry, ...]:
        """The ``"visual"`` or ``"collision"`` elements."""
        return self.visuals if kind == "visual" else self.collisions


@dataclass(frozen=True, eq=False)
class UrdfJoint:
    """A ``<joint>``: ``origin`` (4, 4) of the child frame in the parent link frame, unit
    ``axis`` (3,) in the child frame, limits [rad] (None when the file gives none), the
    joint it mimics (``mimic``; None: it moves on its own) and its torque limit
    ``effort`` [N m] (None when the file gives none or 0, as many do)."""

    name: str
    type: str
    parent: str
    child: str
    origin: FloatArray
    axis: FloatArray
    lower: float | None
    upper: float | None
    mimic: str | None = None
    effort: float | None = None

    @property
    def moves(self) -> bool:
        return self.type in MOVING


@dataclass(frozen=True, eq=False)
class UrdfTree:
    """A checked URDF: ``links`` by name, ``joints`` depth-first from ``root``."""

    name: str
    links: dict[str, UrdfLink]
    joints: tuple[UrdfJoint, ...]
    root: str


def _floats(text: str | None, n: int, default, where: str) -> FloatArray:
    if text is None:
        if default is None:
            raise ValueError(f"{where}: missing")
        return np.array(default, dtype=float)
    try:
        vals = [float(v) for v in text.split()]
    except ValueError:
        raise ValueError(f"{where}: expected {n} numbers, got '{text}'") from None
    if len(vals) != n or not np.all(np.isfinite(vals)):
        raise ValueError(f"{where}: expected {n} finite numbers, got '{text}'")
    return np.array(vals)


def _origin(el, where: str) -> FloatArray:
    if el is None:
        return np.eye(4)
    return frame(_floats(el.get("xyz"), 3, [0, 0, 0], f"{where} origin xyz"),
                 _floats(el.get("rpy"), 3, [0, 0, 0], f"{where} origin rpy"))


def _geometry(el, kind: str, link: str) -> Geometry:
    where = f"link '{link}': {kind}"
    geo = el.find("geometry")
    shapes = [] if geo is None else list(geo)
    if not shapes:
        raise ValueError(f"{where} element without a <geometry> shape")
    shape = shapes[0]
    origin = _origin(el.find("origin"), where)
    if shape.tag == "mesh":
        if not shape.get("filename"):
            raise ValueError(f"{where} <mesh> without a filename")
        scale = _floats(shape.get("scale"), 3, [1, 1, 1], f"{where} mesh scale")
        return Geometry(kind, origin, "mesh", shape.get("filename"), tuple(scale.tolist()))
    sizes = {"box": (("size", 3),), "cylinder": (("radius", 1), ("length", 1)),
             "sphere": (("radius", 1),)}
    if shape.tag not in sizes:
        raise ValueError(f"{where} geometry <{shape.tag}> is not supported "
                         f"({', '.join(SHAPES)})")
    size = np.concatenate([_floats(shape.get(a), n, None, f"{where} {shape.tag} {a}")
                           for a, n in sizes[shape.tag]])
    if np.any(size <= 0):
        raise ValueError(f"{where} {shape.tag} dimensions must be > 0, got {size.tolist()}")
    return Geometry(kind, origin, shape.tag, size=tuple(size.tolist()))


def _inertial(el, link: str) -> Inertial | None:
    if el is None:
        return None
    where = f"link '{link}': inertial"
    mass_el = el.find("mass")
    if mass_el is None:
        raise ValueError(f"{where} without <mass>")
    mass = float(_floats(mass_el.get("value"), 1, None, f"{where} mass")[0])
    if mass < 0:
        raise ValueError(f"{where} mass must be >= 0 kg, got {mass:g}")
    inertia = np.zeros((3, 3))
    i_el = el.find("inertia")
    if i_el is not None:
        keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
        ixx, ixy, ixz, iyy, iyz, izz = (
            float(_floats(i_el.get(k), 1, [0.0], f"{where} inertia {k}")[0]) for k in keys)
        inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    return Inertial(mass, _origin(el.find("origin"), where), inertia)


def _link(el) -> UrdfLink:
    name = el.get("name")
    if not name:
        raise ValueError("a <link> without a name")
    return UrdfLink(name,
                    tuple(_geometry(v, "visual", name) for v in el.findall("visual")),
                    tuple(_geometry(c, "collision", name) for c in el.findall("collision")),
                    _inertial(el.find("inertial"), name))


def _joint(el) -> UrdfJoint:
    name = el.get("name")
    if not name:
        raise ValueError("a <joint> without a name")
    where = f"joint '{name}'"
    kind = el.get("type", "")
    if kind not in MOVING and kind != _FIXED:
        raise ValueError(f"{where}: type '{kind}' is not supported (flexarm arms turn about "
                         f"revolute or continuous joints; fixed joints are merged)")
    ends = {}
    for end in ("parent", "child"):
        e = el.find(end)
        if e is None or not e.get("link"):
            raise ValueError(f"{where}: no <{end} link=\"...\"/>")
        ends[end] = e.get("link")
    axis_el = el.find("axis")
    axis = _floats(None if axis_el is None else axis_el.get("xyz"), 3, [1, 0, 0],
                   f"{where} axis")
    if kind in MOVING:
        if not np.linalg.norm(axis) > 0:
            raise ValueError(f"{where}: axis is the zero vector")
        axis = axis / np.linalg.norm(axis)
    lower = upper = effort = None
    lim = el.find("limit")
    if kind == "revolute" and lim is not None:
        lower = float(_floats(lim.get("lower"), 1, [0.0], f"{where} limit lower")[0])
        upper = float(_floats(lim.get("upper"), 1, [0.0], f"{where} limit upper")[0])
    if kind in MOVING and lim is not None:
        effort = float(_floats(lim.get("effort"), 1, [0.0], f"{where} limit effort")[0])
        effort = abs(effort) or None
    mimic = el.find("mimic")
    return UrdfJoint(name, kind, ends["parent"], ends["child"],
                     _origin(el.find("origin"), where), axis, lower, upper,
                     None if mimic is None else mimic.get("joint"), effort)


def _unique(names: list[str], what: str) -> None:
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ValueError(f"duplicate {what} name '{n}'")
        seen.add(n)


def parse_tree(root) -> UrdfTree:
    """The checked :class:`UrdfTree` of a parsed ``<robot>`` element.

    Raises
    ------
    ValueError
        One line naming the link or joint: duplicate names, an unsupported joint type
        (prismatic, floating, planar), a parent or child that does not exist, a closed
        loop, several roots, malformed numbers or geometry.

    Examples
    --------
    >>> import xml.etree.ElementTree as ET
    >>> tree = parse_tree(ET.fromstring(
    ...     '<robot name="r"><link name="a"/><link name="b"/><joint name="j" '
    ...     'type="revolute"><parent link="a"/><child link="b"/></joint></robot>'))
    >>> tree.root, [j.name for j in tree.joints]
    ('a', ['j'])
    """
    if root.tag != "robot":
        raise ValueError(f"not a URDF: the root element is <{root.tag}>, not <robot>")
    if any(_XACRO in el.tag for el in root.iter() if isinstance(el.tag, str)):
        raise ValueError("this is a xacro file, not a URDF: expand it first "
                         "(xacro robot.urdf.xacro > robot.urdf)")
    link_list = [_link(el) for el in root.findall("link")]
    joints = [_joint(el) for el in root.findall("joint")]
    _unique([lk.name for lk in link_list], "link")
    _unique([j.name for j in joints], "joint")
    links = {lk.name: lk for lk in link_list}
    if not links:
        raise ValueError("no <link> elements")
    parent_joint = _parent_joints(joints, links)
    roots = [n for n in links if n not in parent_joint]
    if not roots:
        raise ValueError(f"closed loop: {_cycle(next(iter(links)), parent_joint)}")
    if len(roots) > 1:
        raise ValueError(f"several root links ({', '.join(roots)}): every link but the base "
                         "must be the child of a joint")
    order = _walk(roots[0], joints)
    reached = {roots[0]} | {j.child for j in order}
    unreached = [n for n in links if n not in reached]
    if unreached:  # one parent each, never reaching the root: they hang on a cycle
        raise ValueError(f"closed loop: {_cycle(unreached[0], parent_joint)}")
    return UrdfTree(root.get("name", "robot"), links, tuple(order), roots[0])


def _parent_joints(joints: list[UrdfJoint], links: dict) -> dict[str, UrdfJoint]:
    """The joint above each child link; every end must exist, no link has two parents."""
    parent_joint: dict[str, UrdfJoint] = {}
    for j in joints:
        for end, link in (("parent", j.parent), ("child", j.child)):
            if link not in links:
                raise ValueError(f"joint '{j.name}': {end} link '{link}' does not exist")
        if j.parent == j.child:
            raise ValueError(f"closed loop: joint '{j.name}' joins link '{j.child}' to itself")
        if j.child in parent_joint:
            raise ValueError(f"closed loop: link '{j.child}' is the child of joints "
                             f"'{parent_joint[j.child].name}' and '{j.name}' (a URDF is a tree)")
        parent_joint[j.child] = j
    return parent_joint


def _walk(root: str, joints: list[UrdfJoint]) -> list[UrdfJoint]:
    """Joints depth-first (pre-order) from ``root``, siblings in file order.

    A visited set guards the walk: the checks before it leave no loop, but a walk must
    end whatever it is given.
    """
    by_parent: dict[str, list[UrdfJoint]] = {}
    for j in joints:
        by_parent.setdefault(j.parent, []).append(j)
    order: list[UrdfJoint] = []
    stack: list[tuple[str, UrdfJoint | None]] = [(root, None)]
    visited = {root}
    while stack:
        name, via = stack.pop()
        if via is not None:
            order.append(via)
        for j in reversed(by_parent.get(name, [])):
            if j.child in visited:
                raise ValueError(f"closed loop: joint '{j.name}' leads back to link '{j.child}'")
            visited.add(j.child)
            stack.append((j.child, j))
    return order


def _cycle(start: str, parent_joint: dict[str, UrdfJoint]) -> str:
    """``joints a -> b -> a`` of the loop that ``start`` hangs on."""
    seen: list[str] = []
    link = start
    while link not in seen:
        seen.append(link)
        link = parent_joint[link].parent
    loop = seen[seen.index(link):]
    names = " -> ".join(parent_joint[n].name for n in reversed(loop))
    return f"joints {names} form a cycle (a URDF is a tree)"
