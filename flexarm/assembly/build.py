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
from ..reduction import CylinderRegion, Superelement, reduce_with_stats
from ..reduction.formats import h5
from ..reduction.tie import tied_superelement
from ..robot.description import Link, Robot
from .build_report import RobotBuild, builds_text
from .link_meshes import LinkMesh, Mesher, link_mesh, link_mesh_id, meshed_link

__all__ = ["BUILD_VERSION", "BuildOptions", "LinkBuild", "RobotBuild", "link_regions",
           "link_mesh", "link_material", "link_mesh_id", "build_link", "build_robot",
           "robot_build", "builds_text", "Mesher", "SUPERELEMENT_CODEC"]

log = logging.getLogger(__name__)

#: Version of the build recipe; part of every cache key.
BUILD_VERSION = 1


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
    mesher : str
        What made the tetrahedra (:attr:`~flexarm.assembly.link_meshes.LinkMesh.mesher`;
        empty for a rigid base), and ``mesher_note`` why ``"auto"`` fell back (to
        fTetWild, or to Gmsh's volume on its pre-mesh).
    mesh_seconds : float
        Wall time [s] of this build's meshing step (reading a cached mesh included).
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
    mesher: str = ""
    mesher_note: str = ""
    mesh_seconds: float = 0.0

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
        ``mesher(link, mesh_size, order) -> TetMesh`` instead of the robot's
        ``model.mesher`` (tests use structured box meshes); its meshes are keyed by their
        own node/element arrays.
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
    made: LinkMesh = meshed_link(lk, opts.mesh_size, opts.order, say,
                                 robot.options.mesher if mesher is None else mesher)
    mesh = made.mesh
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
                     entry.path, float(st["seconds"]), made.mesher, made.note, made.seconds)


def _meshing_work(robot: Robot, index: int, opts: BuildOptions, mesher) -> float | None:
    """None when building link ``index`` meshes nothing (a rigid base, a mesh file or a
    cached mesh), else the relative cost of meshing it (1 for a given mesher)."""
    from .link_meshes import meshing_work

    if not link_regions(robot, index, opts.tcp):
        return None
    if mesher is not None:
        return 1.0
    return meshing_work(robot.links[index], opts.mesh_size, opts.order, robot.options.mesher)


def _picklable(value) -> bool:
    import pickle

    try:
        pickle.dumps(value)
    except Exception:  # noqa: BLE001 - a lambda or a closure: it stays in this process
        return False
    return True


def robot_build(robot: Robot, options: BuildOptions = BuildOptions(), cache: bool = True,
                mesher: Mesher | None = None, progress: Callable[[str], None] | None = None,
                jobs: int | None = 1) -> RobotBuild:
    """:func:`build_link` for every link, base first, the links that have to be meshed in
    up to ``jobs`` worker processes (:func:`~flexarm.fe.processes.run_jobs`).

    Parameters
    ----------
    robot, options, cache, mesher, progress
        As for :func:`build_link`.
    jobs : int, optional
        Worker processes for the links without a mesh yet (None: one per core; 1: every
        link here, in order).  The other links are built here.

    Returns
    -------
    RobotBuild

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> built = robot_build(load_robot(), BuildOptions("guyan"))
    >>> [lb.mesher for lb in built.links][:3], built.is_reproducible
    (['file', 'file', 'file'], True)
    """
    from ..fe.processes import default_jobs, run_jobs

    opts = options.resolved(robot)
    jobs = default_jobs() if jobs is None else int(jobs)
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    log.info("building %s (%s)", robot.name, opts.method)
    start = time.perf_counter()
    n = len(robot.links)
    cold = []
    if jobs > 1 and (mesher is None or _picklable(mesher)):
        work = {i: _meshing_work(robot, i, opts, mesher) for i in range(n)}
        # the biggest first: the last link to finish is then a small one
        cold = sorted((i for i in work if work[i] is not None), key=lambda i: -work[i])
    if len(cold) < 2:
        cold, jobs = [], 1
    built = dict(zip(cold, run_jobs(build_link, [(robot, i, opts, cache, mesher) for i in cold],
                                    jobs, progress), strict=True))
    links = tuple(built[i] if i in built else build_link(robot, i, opts, cache, mesher, progress)
                  for i in range(n))
    log.info("built %s", robot.name)
    return RobotBuild(links, time.perf_counter() - start, min(jobs, max(len(cold), 1)))


def build_robot(robot: Robot, options: BuildOptions = BuildOptions(), cache: bool = True,
                mesher: Mesher | None = None, progress: Callable[[str], None] | None = None,
                jobs: int | None = 1) -> tuple[LinkBuild, ...]:
    """:func:`build_link` for every link, base first (a rigid base gives
    ``superelement=None``): the links of :func:`robot_build`."""
    return robot_build(robot, options, cache, mesher, progress, jobs).links
