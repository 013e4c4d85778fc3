"""Build a robot's links: mesh (cached) -> interface regions -> Guyan/CB superelement (cached).

For every link the interface regions are taken from its description in a fixed order
(DESIGN §6, §7):

0. the *proximal* seat -- the joint from the parent, or the ``"base"`` region of the
   base link (its foundation seat; without one the base stays a rigid body);
1. the seats of the joints to its children, in joint order;
2. the ``"tcp"`` region on the TCP link when ``tcp="region"``; with ``tcp="rigid"``
   the TCP is carried rigidly by the flange's proximal interface node instead.

Every superelement is written to ``cache_dir()/superelements/<key>.h5`` (atomically)
with a JSON side file of its build statistics; ``key`` is a digest of everything that
changes the result (surface bytes, units, mesh size, element order, material, regions,
method, mode count, coupling, :data:`BUILD_VERSION`).
"""

from __future__ import annotations

import dataclasses
import json
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..fe.files import atomic_path, cache_dir, digest, file_digest
from ..fe.material import Material
from ..fe.mesh import TetMesh
from ..reduction import CylinderRegion, Superelement, reduce_with_stats
from ..reduction.formats import h5
from ..robot.description import Link, Robot

__all__ = ["BUILD_VERSION", "BuildOptions", "LinkBuild", "link_regions", "link_mesh",
           "link_material", "build_link", "build_robot", "Mesher"]

log = logging.getLogger(__name__)

#: Version of the build recipe; part of every cache key.
BUILD_VERSION = 1

#: ``mesher(link, mesh_size [m], order) -> TetMesh`` in the link frame [m].
Mesher = Callable[[Link, float, int], TetMesh]


@dataclass(frozen=True)
class BuildOptions:
    """How the links are reduced.

    Parameters
    ----------
    method : {"cb", "guyan"}
    n_modes : int or None
        Fixed-interface modes per link for CB (None: the robot's ``cb_modes``).
    coupling : {"rbe2", "rbe3"}
        Coupling of every interface region onto its 6-DOF node.
    mesh_size : float or None
        Tet edge length [m] (None: the robot's ``mesh_size``).
    order : int or None
        1 (Tet4) or 2 (Tet10) (None: the robot's ``element_order``).
    tcp : {"region", "rigid"}
        TCP on its own interface node of the ``"tcp"`` region, or rigidly carried by
        the flange's proximal node (also used when the link has no ``"tcp"`` region).
    stiffness_scale : float
        Factor on Young's modulus [-] (``1e6`` gives the rigid-link limit).
    """

    method: str = "cb"
    n_modes: int | None = None
    coupling: str = "rbe2"
    mesh_size: float | None = None
    order: int | None = None
    tcp: str = "region"
    stiffness_scale: float = 1.0

    def resolved(self, robot: Robot) -> BuildOptions:
        """The options with the robot's defaults filled in (and checked)."""
        if self.method not in ("cb", "guyan"):
            raise ValueError(f"method must be cb|guyan, got '{self.method}'")
        if self.coupling not in ("rbe2", "rbe3"):
            raise ValueError(f"coupling must be rbe2|rbe3, got '{self.coupling}'")
        if self.tcp not in ("region", "rigid"):
            raise ValueError(f"tcp must be region|rigid, got '{self.tcp}'")
        if not self.stiffness_scale > 0:
            raise ValueError(f"stiffness_scale must be > 0, got {self.stiffness_scale}")
        o = robot.options
        n = o.cb_modes if self.n_modes is None else int(self.n_modes)
        return dataclasses.replace(
            self, n_modes=0 if self.method == "guyan" else n,
            mesh_size=o.mesh_size if self.mesh_size is None else float(self.mesh_size),
            order=o.element_order if self.order is None else int(self.order))

    @property
    def label(self) -> str:
        """Short name for tables: ``Guyan``, ``CB(10)``."""
        return "Guyan" if self.method == "guyan" else f"CB({self.n_modes})"


@dataclass(frozen=True, eq=False)
class LinkBuild:
    """One built link.

    Attributes
    ----------
    name : str
    superelement : Superelement or None
        None for a base without a ``"base"`` region (rigid body).
    regions : tuple of str
        Interface names in DOF order (proximal first).
    n_tets, n_fe_dofs, n_reduced : int
        Elements, FE DOFs (3 per node) and reduced DOFs.
    seconds : float
        Wall time of meshing + reduction [s] (0 when read from the cache).
    is_cached : bool
    path : Path or None
        The superelement file.
    """

    name: str
    superelement: Superelement | None
    regions: tuple[str, ...]
    n_tets: int = 0
    n_fe_dofs: int = 0
    n_reduced: int = 0
    seconds: float = 0.0
    is_cached: bool = False
    path: Path | None = None

    @property
    def freq_hz(self) -> np.ndarray:
        """(n_modes,) fixed-interface frequencies [Hz] (empty for Guyan / rigid)."""
        return np.zeros(0) if self.superelement is None else self.superelement.freq_hz


def link_regions(robot: Robot, index: int, tcp: str = "region") -> tuple[str, ...]:
    """Names of link ``index``'s interface regions in DOF order (proximal first).

    Returns ``()`` for a base link without a ``"base"`` region (rigid base).
    """
    lk = robot.links[index]
    chain = robot.chain
    if index == 0:
        if "base" not in lk.regions:
            return ()
        names = ["base"]
    else:
        names = [robot.joints[index - 1].name]
    names += [jt.name for j, jt in enumerate(robot.joints) if int(chain.parents[j]) == index]
    if index == chain.tcp_body and tcp == "region" and "tcp" in lk.regions:
        names.append("tcp")
    missing = [n for n in names if n not in lk.regions]
    if missing:
        raise ValueError(f"links.{lk.name}.regions: no region for {', '.join(missing)} "
                         f"(has {sorted(lk.regions)})")
    return tuple(names)


def cylinder_regions(link: Link, names) -> list[CylinderRegion]:
    """The link's :class:`CylinderRegion` s named ``names`` (link frame, metres)."""
    return [CylinderRegion(n, r.center, r.axis, r.r_min, r.r_max, r.half_width)
            for n, r in ((n, link.regions[n]) for n in names)]


def link_material(link: Link, stiffness_scale: float = 1.0) -> Material:
    """The link's material with Young's modulus times ``stiffness_scale``."""
    return dataclasses.replace(link.material, E=link.material.E * stiffness_scale)


def link_mesh(link: Link, mesh_size: float, order: int = 1, progress=None,
              mesher: str = "tetwild") -> TetMesh:
    """Tetrahedral mesh of the link's CAD [m], link frame (cached on disk).

    The same call as the E-model's mass properties, so both see the same solid;
    ``mesher`` is the robot's ``model.mesher`` (``"tetwild"`` or ``"gmsh"``).
    """
    from ..meshes import load_surface, tetrahedralizer

    if link.mesh is None:
        raise ValueError(f"links.{link.name}: no mesh to build a flexible link from")
    surface = load_surface(link.mesh, units=link.units)
    return tetrahedralizer(mesher)(surface, mesh_size, order=order, name=link.name,
                                   progress=progress)


def mesh_identity(link: Link, mesher: str = "tetwild") -> str:
    """What a link's cached results are keyed by: its CAD file, and the mesher unless
    it is the default (so existing pytetwild cache entries stay valid)."""
    return file_digest(link.mesh) if mesher == "tetwild" else digest(file_digest(link.mesh),
                                                                      mesher)


def _key(link: Link, names, opts: BuildOptions, mesh_id: str) -> str:
    regs = [(n, dataclasses.astuple(link.regions[n])) for n in names]
    mat = link_material(link, opts.stiffness_scale)
    return digest("flexarm-build", BUILD_VERSION, mesh_id, link.units, opts.mesh_size,
                  opts.order, (mat.E, mat.nu, mat.rho), repr(regs), opts.method, opts.n_modes,
                  opts.coupling)


def build_link(robot: Robot, index: int, options: BuildOptions = BuildOptions(),
               cache: bool = True, mesher: Mesher | None = None,
               progress: Callable[[str], None] | None = None) -> LinkBuild:
    """Mesh and reduce link ``index`` of ``robot`` (see the module docstring).

    Parameters
    ----------
    robot : Robot
    index : int
        Link index (0 = base).
    options : BuildOptions
    cache : bool
        Read / write the superelement cache.
    mesher : callable, optional
        ``mesher(link, mesh_size, order) -> TetMesh`` instead of pytetwild (tests use
        structured box meshes); its meshes are keyed by their own node/element arrays.
    progress : callable (str) -> None, optional
    """
    opts = options.resolved(robot)
    lk = robot.links[index]
    names = link_regions(robot, index, opts.tcp)
    say = progress or (lambda message: None)
    if not names:
        say(f"{lk.name}: rigid (no 'base' region)")
        return LinkBuild(lk.name, None, ())
    mesh = None
    if mesher is not None:
        mesh = mesher(lk, opts.mesh_size, opts.order)
        mesh_id = digest(mesh.points, mesh.tets)
    else:
        mesh_id = mesh_identity(lk, robot.options.mesher)
    key = _key(lk, names, opts, mesh_id)
    path = cache_dir() / "superelements" / f"{key}.h5"
    meta = path.with_suffix(".json")
    if cache and path.is_file() and meta.is_file():
        se = h5.read(path)
        st = json.loads(meta.read_text())
        say(f"{lk.name}: superelement from cache ({se.n_dofs} DOF)")
        return LinkBuild(lk.name, se, names, st["n_tets"], st["n_fe_dofs"], se.n_dofs, 0.0,
                         True, path)
    t0 = time.perf_counter()
    say(f"{lk.name}: meshing (edge {opts.mesh_size * 1e3:.0f} mm)")
    if mesh is None:
        mesh = link_mesh(lk, opts.mesh_size, opts.order, mesher=robot.options.mesher)
    say(f"{lk.name}: reducing {mesh.n_dofs} DOF ({opts.label}, {opts.coupling})")
    se, st = reduce_with_stats(mesh, link_material(lk, opts.stiffness_scale),
                               cylinder_regions(lk, names), opts.coupling, opts.method,
                               opts.n_modes)
    dt = time.perf_counter() - t0
    if cache:
        h5.write(path, se)
        with atomic_path(meta) as tmp:
            tmp.write_text(json.dumps({"n_tets": mesh.n_tets, "n_fe_dofs": mesh.n_dofs,
                                       "seconds": dt, "region_nodes": st["region_nodes"]}))
    say(f"{lk.name}: {mesh.n_tets} tets, {mesh.n_dofs} -> {se.n_dofs} DOF in {dt:.1f} s")
    return LinkBuild(lk.name, se, names, mesh.n_tets, mesh.n_dofs, se.n_dofs, dt, False,
                     path if cache else None)


def build_robot(robot: Robot, options: BuildOptions = BuildOptions(), cache: bool = True,
                mesher: Mesher | None = None,
                progress: Callable[[str], None] | None = None) -> tuple[LinkBuild, ...]:
    """:func:`build_link` for every link, base first (a rigid base gives ``superelement=None``)."""
    log.info("building %s (%s)", robot.name, options.method)
    out = tuple(build_link(robot, i, options, cache, mesher, progress)
                for i in range(len(robot.links)))
    log.info("built %s", robot.name)
    return out
