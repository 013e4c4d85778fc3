"""URDF import: joint origins, axes, limits and link meshes -> :class:`Robot`.

Only revolute (and continuous) joints move; links hanging off fixed joints
without a mesh (``tool0``, ``flange``) are dropped.  Mesh filenames may be
relative to the URDF or ``package://name/...`` (resolved against the folder
holding that package's ``package.xml``, searched upwards from the URDF).
Interface regions default to cylinders around each joint origin; a warning
names every region that catches too few mesh vertices.
"""

from __future__ import annotations

import logging
import math
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.material import MATERIALS
from ...fe.units import LENGTH_UNITS
from ..description import Joint, Link, Region, Robot, Tool
from ..joints import JointModel
from ..kinematics import rpy_matrix

__all__ = ["read", "DEFAULT_TORSION", "MIN_REGION_NODES"]

log = logging.getLogger(__name__)

#: Default gear torsion stiffness [N m/rad] of the main axes (1-3) and the wrist.
DEFAULT_TORSION = (1.0e6, 2.0e5)
#: A default region catching fewer mesh vertices than this gets a warning.
MIN_REGION_NODES = 8
_REGION_R, _REGION_HALF = 0.15, 0.08  # default seat cylinder [m]


def _floats(text: str | None, n: int, default) -> np.ndarray:
    if text is None:
        return np.array(default, dtype=float)
    vals = [float(v) for v in text.split()]
    if len(vals) != n:
        raise ValueError(f"expected {n} numbers, got '{text}'")
    return np.array(vals)


def _package_root(urdf: Path, package: str) -> Path:
    for folder in [urdf.parent, *urdf.parents]:
        px = folder / "package.xml"
        if px.is_file():
            name = ET.parse(px).getroot().findtext("name", "").strip()
            if name == package or folder.name == package:
                return folder
    raise ValueError(f"package://{package}: no package.xml named '{package}' above {urdf}")


def _mesh_path(urdf: Path, filename: str) -> Path:
    if filename.startswith("package://"):
        pkg, _, rel = filename[len("package://"):].partition("/")
        return _package_root(urdf, pkg) / rel
    if filename.startswith("file://"):
        return Path(filename[len("file://"):])
    return (urdf.parent / filename).resolve()


def _link_mesh(urdf: Path, el, kind: str, name: str) -> tuple[Path | None, str]:
    """Mesh of a link (STL only), preferring ``kind``; (path, units)."""
    order = [kind, "visual" if kind == "collision" else "collision"]
    for k in order:
        m = el.find(f"{k}/geometry/mesh")
        if m is None:
            continue
        path = _mesh_path(urdf, m.get("filename", ""))
        scale = _floats(m.get("scale"), 3, [1, 1, 1])
        if path.suffix.lower() != ".stl":
            warnings.warn(f"link '{name}': {k} mesh {path.name} is not STL; skipped",
                          stacklevel=3)
            continue
        if not np.allclose(scale, scale[0]):
            raise ValueError(f"link '{name}': non-uniform mesh scale {scale.tolist()}")
        units = {1.0: "m", 1e-3: "mm", 1e-2: "cm"}.get(float(scale[0]))
        if units is None:
            raise ValueError(f"link '{name}': unsupported mesh scale {scale[0]}")
        if k != kind:
            warnings.warn(f"link '{name}': no STL {kind} mesh, using the {k} one", stacklevel=3)
        return path, units
    return None, "m"


def _count_in(region: Region, mesh: Path | None, units: str) -> int:
    if mesh is None:
        return 0
    import trimesh

    v = np.asarray(trimesh.load(mesh, force="mesh").vertices) * LENGTH_UNITS[units]
    return int(region.contains(v).sum())


def read(path, meshes: str = "collision", material: str = "cast_iron") -> Robot:
    """Read a URDF as a :class:`Robot` (default joint models, regions, material).

    Parameters
    ----------
    path : path-like
    meshes : {"collision", "visual"}
        Which link meshes become the CAD (STL only; the other kind is a fallback).
    material : str
        Material name for every link.
    """
    path = Path(path)
    if meshes not in ("collision", "visual"):
        raise ValueError(f"meshes must be collision|visual, got '{meshes}'")
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise ReadError(f"{path}: {exc}") from None
    try:
        return _robot(path, root, meshes, material)
    except ValueError as exc:
        raise ReadError(f"{path}: {exc}") from None


def _robot(path: Path, root, meshes: str, material: str) -> Robot:
    links = {el.get("name"): el for el in root.findall("link")}
    joints = root.findall("joint")
    children = {j.find("child").get("link") for j in joints}
    roots = [n for n in links if n not in children]
    if len(roots) != 1:
        raise ValueError(f"expected one root link, found {roots}")
    # walk the tree from the root: movable joints in depth-first order
    by_parent: dict[str, list] = {}
    for j in joints:
        by_parent.setdefault(j.find("parent").get("link"), []).append(j)
    order, stack = [], [roots[0]]
    while stack:
        name = stack.pop()
        for j in reversed(by_parent.get(name, [])):
            order.append(j)
            stack.append(j.find("child").get("link"))
    movable = [j for j in order if j.get("type") in ("revolute", "continuous")]
    if not movable:
        raise ValueError("no revolute joints")
    for j in order:
        if j.get("type") not in ("revolute", "continuous", "fixed"):
            raise ValueError(f"joint '{j.get('name')}': type '{j.get('type')}' not supported")
        if j.get("type") == "fixed":
            child = j.find("child").get("link")
            el = links[child]
            if el.find("collision") is not None or el.find("visual") is not None:
                raise ValueError(f"fixed joint '{j.get('name')}' carries link '{child}' with "
                                 "geometry; merging fixed links is not supported")
    link_names = [roots[0]] + [j.find("child").get("link") for j in movable]
    mat = MATERIALS[material]
    mesh_of = {n: _link_mesh(path, links[n], meshes, n) for n in link_names}
    regions: dict[str, dict] = {n: {} for n in link_names}
    out_joints = []
    for k, j in enumerate(movable):
        name = j.get("name")
        origin = j.find("origin")
        xyz = _floats(None if origin is None else origin.get("xyz"), 3, [0, 0, 0])
        rpy = _floats(None if origin is None else origin.get("rpy"), 3, [0, 0, 0])
        axis_el = j.find("axis")
        axis = _floats(None if axis_el is None else axis_el.get("xyz"), 3, [1, 0, 0])
        axis = axis / np.linalg.norm(axis)
        lim = j.find("limit")
        if j.get("type") == "continuous" or lim is None:
            lo, hi = -2 * math.pi, 2 * math.pi
        else:
            lo, hi = float(lim.get("lower", -math.pi)), float(lim.get("upper", math.pi))
        parent, child = j.find("parent").get("link"), j.find("child").get("link")
        torsion = DEFAULT_TORSION[0] if k < 3 else DEFAULT_TORSION[1]
        out_joints.append(Joint(name, parent, child, tuple(xyz), tuple(axis), lo, hi,
                                JointModel(torsion=torsion), tuple(rpy)))
        axis_parent = rpy_matrix(rpy) @ axis
        for link, centre, ax in ((parent, xyz, axis_parent), (child, np.zeros(3), axis)):
            reg = Region(tuple(float(c) for c in centre), tuple(float(a) for a in ax), 0.0,
                         _REGION_R, _REGION_HALF)
            n_in = _count_in(reg, *mesh_of[link])
            if n_in < MIN_REGION_NODES:
                warnings.warn(f"link '{link}': default region of {name} catches only {n_in} "
                              f"mesh vertices (< {MIN_REGION_NODES})", stacklevel=3)
            regions[link][name] = reg
    out_links = tuple(Link(n, mesh_of[n][0], mat, mesh_of[n][1], (), regions[n])
                      for n in link_names)
    poses = {}
    zero = np.zeros(len(out_joints))
    if all(jt.lower <= 0 <= jt.upper for jt in out_joints):
        poses["home"] = zero.tolist()
    log.info("URDF %s: %d links, %d joints", path.name, len(out_links), len(out_joints))
    return Robot(root.get("name", path.stem), out_links, tuple(out_joints), tool=Tool(),
                 poses=poses, source=path.resolve())
