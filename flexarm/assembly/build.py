"""Build a robot's links: mesh (cached) -> interface regions -> Guyan/CB superelement (cached).

For every link the interface regions are taken from its description in a fixed order
(DESIGN §6, §7):

0. the *proximal* seat -- the joint from the parent, or the ``"base"`` region of the
   base link (its foundation seat; without one the base stays a rigid body);
1. the seats of the joints to its children, in joint order;
2. the ``"tcp"`` region on the TCP link when ``tcp="region"``; with ``tcp="rigid"``
   the TCP is carried rigidly by the flange's proximal interface node instead.

Every superelement goes into the package cache (:mod:`flexarm.fe.cache`) as
``superelements/<key>.h5`` with its build statistics as a file attribute; ``key`` covers
everything that changes the result (the link's tetrahedra themselves, from the tet cache,
material, regions, method, mode count, coupling, :data:`BUILD_VERSION`), so a
superelement always belongs to the mesh that the E-model's mass properties come from.
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

from ..fe.cache import Codec, cache_key, cached
from ..fe.files import digest
from ..fe.material import Material
from ..fe.mesh import TetMesh
from ..reduction import CylinderRegion, Superelement, reduce_with_stats
from ..reduction.formats import h5
from ..reduction.tie import tied_superelement
from ..robot.description import Link, Robot

__all__ = ["BUILD_VERSION", "BuildOptions", "LinkBuild", "link_regions", "link_mesh",
           "link_material", "link_mesh_id", "build_link", "build_robot", "builds_text", "Mesher",
           "SUPERELEMENT_CODEC"]

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
    masters : int or None
        Instead of ``coupling``, keep this many seat nodes per interface as 3-DOF masters
        during the reduction and tie them rigidly to the seat centre afterwards
        (:func:`~flexarm.reduction.tie.tied_superelement`): a bolt-like seat through
        ``masters`` points.
    """

    method: str = "cb"
    n_modes: int | None = None
    coupling: str = "rbe2"
    mesh_size: float | None = None
    order: int | None = None
    tcp: str = "region"
    stiffness_scale: float = 1.0
    masters: int | None = None

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
        if self.masters is not None and not int(self.masters) >= 3:
            raise ValueError(f"masters must be >= 3 seat nodes, got {self.masters}")
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

    @property
    def seat(self) -> str:
        """The interface representation: ``rbe2``, ``rbe3`` or ``k<masters>``."""
        return self.coupling if self.masters is None else f"k{self.masters}"


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
    build_seconds : float
        Wall time [s] of the build that made the superelement (also when it is read
        from the cache: the time that the cache saves).
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
    build_seconds: float = 0.0

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
    ``mesher`` is the robot's ``model.mesher`` (``"tetwild"`` or ``"gmsh"``).  A volume
    mesh the link names for ``mesh_size`` is read instead
    (:func:`~flexarm.robot.volume_meshes.pinned_mesh`).
    """
    from ..meshes import load_surface, tetrahedralizer
    from ..robot.volume_meshes import pinned_mesh

    pinned = pinned_mesh(link, mesh_size, order)
    if pinned is not None:
        return pinned
    if link.mesh is None:
        raise ValueError(f"links.{link.name}: no mesh to build a flexible link from")
    surface = load_surface(link.mesh, units=link.units)
    return tetrahedralizer(mesher)(surface, mesh_size, order=order, name=link.name,
                                   progress=progress)


def link_mesh_id(link: Link, mesher: str | Mesher = "tetwild", mesh_size: float = 0.0,
                 order: int = 1) -> str:
    """Digest of the link's tetrahedra at ``mesh_size`` [m] and ``order``: the key of every
    cache entry computed from them.

    ``mesher`` is the robot's ``model.mesher`` (the mesh comes from the tet cache, so a
    mesh made again, which pytetwild makes differently, gets new keys downstream) or a
    :data:`Mesher` callable.
    """
    mesh = (mesher(link, mesh_size, order) if callable(mesher) else
            link_mesh(link, mesh_size, order, mesher=mesher))
    return digest(mesh.points, mesh.tets)


def _save_build(path: Path, value) -> None:
    import h5py

    se, stats = value
    h5.write(path, se)
    with h5py.File(path, "a") as f:
        f.attrs["flexarm_build"] = json.dumps(stats)


def _load_build(path: Path):
    import h5py

    se = h5.read(path)
    with h5py.File(path, "r") as f:
        return se, json.loads(f.attrs["flexarm_build"])


#: A built superelement and its build statistics (``n_tets``, ``n_fe_dofs``, ``seconds``,
#: ``region_nodes``) in one HDF5 file that every superelement reader opens.
SUPERELEMENT_CODEC = Codec(".h5", _save_build, _load_build)


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
    mat = link_material(lk, opts.stiffness_scale)
    t0 = time.perf_counter()
    mesh = (mesher(lk, opts.mesh_size, opts.order) if mesher is not None else
            link_mesh(lk, opts.mesh_size, opts.order, progress=say,
                      mesher=robot.options.mesher))
    key = cache_key("superelements", BUILD_VERSION, digest(mesh.points, mesh.tets),
                    opts.mesh_size, opts.order, (mat.E, mat.nu, mat.rho),
                    repr([(n, dataclasses.astuple(lk.regions[n])) for n in names]),
                    opts.method, opts.n_modes, opts.coupling, opts.masters)

    def build():
        say(f"{lk.name}: reducing {mesh.n_dofs} DOF ({opts.label}, {opts.seat})")
        se, st = reduce_with_stats(mesh, mat, cylinder_regions(lk, names),
                                   "nodes" if opts.masters else opts.coupling, opts.method,
                                   opts.n_modes, n_masters=opts.masters)
        if opts.masters:
            se = tied_superelement(se)
        dt = time.perf_counter() - t0
        say(f"{lk.name}: {mesh.n_tets} tets, {mesh.n_dofs} -> {se.n_dofs} DOF in {dt:.1f} s")
        return se, {"n_tets": mesh.n_tets, "n_fe_dofs": mesh.n_dofs, "seconds": dt,
                    "region_nodes": st.region_nodes}

    entry = cached("superelements", key, build, SUPERELEMENT_CODEC, enabled=cache)
    se, st = entry.value
    if entry.is_hit:
        say(f"{lk.name}: superelement from cache ({se.n_dofs} DOF)")
    return LinkBuild(lk.name, se, names, st["n_tets"], st["n_fe_dofs"], se.n_dofs,
                     0.0 if entry.is_hit else time.perf_counter() - t0, entry.is_hit,
                     entry.path, float(st["seconds"]))


def builds_text(builds) -> str:
    """Table of built links: tets, FE DOF, reduced DOF (``rigid`` for a rigid base), build
    time [s] (``cache`` when read from the cache) and the first fixed-interface
    frequencies [Hz]."""
    lines = [f"{'link':<14} {'tets':>7} {'DOF':>7} {'reduced':>7} {'time_s':>7}  "
             f"fixed-interface f [Hz]"]
    for lb in builds:
        f = " ".join(f"{v:.0f}" for v in lb.freq_hz[:5]) or "-"
        src = "cache" if lb.is_cached else f"{lb.seconds:7.1f}"
        kind = "rigid" if lb.superelement is None else lb.n_reduced
        lines.append(f"{lb.name:<14} {lb.n_tets:>7} {lb.n_fe_dofs:>7} {kind:>7} {src:>7}  {f}")
    return "\n".join(lines)


def build_robot(robot: Robot, options: BuildOptions = BuildOptions(), cache: bool = True,
                mesher: Mesher | None = None,
                progress: Callable[[str], None] | None = None) -> tuple[LinkBuild, ...]:
    """:func:`build_link` for every link, base first (a rigid base gives ``superelement=None``)."""
    log.info("building %s (%s)", robot.name, options.method)
    out = tuple(build_link(robot, i, options, cache, mesher, progress)
                for i in range(len(robot.links)))
    log.info("built %s", robot.name)
    return out
