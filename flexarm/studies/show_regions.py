"""The interface regions of a robot's links, checked on the tet meshes the build uses.

For every link with a CAD mesh: its tetrahedral mesh at the mesh size (the build's cached
:func:`~flexarm.assembly.build.link_mesh`), the surface nodes each region selects
(:func:`~flexarm.reduction.interfaces.select_region`, as the reduction does), whether the
build would accept them (:func:`~flexarm.reduction.interfaces.interfaces`: enough nodes,
not collinear, no node shared by two regions), and the region measured on the CAD surface
sample (:func:`~flexarm.robot.seats.seat_report`: area, radius range, axial extent,
offsets of its centroid from the joint axis and origin); a region marked ``review = true``
says so.  Below, the two seats of every joint against each other
(:mod:`~flexarm.studies.show_pairs`: gap along the axis, radial overlap, FE nodes a side).
:meth:`RegionsResult.write` draws one picture per link (PyVista, off screen) and writes
``regions.csv``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..assembly.build import link_mesh, link_regions
from ..fe.errors import FlexarmError
from ..fe.files import atomic_path, writes_folder
from ..fe.typing import FloatArray, IntArray
from ..reduction.interfaces import CylinderRegion, check_spread, interfaces, select_region
from ..robot.description import Robot
from ..robot.seat_review import is_review
from ..robot.seats import SeatRow, link_sample, region_order, region_references, seat_row
from .show_pairs import PairRow, pair_rows, pairs_text

__all__ = ["RegionRow", "LinkRegions", "RegionsResult", "show_regions", "REVIEW"]

#: Status of a region the build takes that is marked ``review = true`` (a suggestion).
REVIEW = "review: suggested where no seat was found; confirm or replace it"

#: Region colours (matplotlib's tab10), in region order per link.
_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
            "#17becf")


@dataclass(frozen=True)
class RegionRow:
    """One region of one link.

    Attributes
    ----------
    fe_nodes : int
        Surface nodes of the link's tet mesh inside the region.
    seat : SeatRow
        The region on the CAD surface sample (area, radii, offsets; metres).
    status : str
        ``"ok"``, or why the build would refuse the region (too few or collinear nodes,
        overlap with another region, no region for a joint).
    """

    link: str
    region: str
    fe_nodes: int
    seat: SeatRow
    status: str = "ok"


@dataclass(frozen=True, eq=False)
class LinkRegions:
    """What a link's picture shows (link frame, metres).

    Attributes
    ----------
    name : str
    points : (n, 3) float
        Tet mesh nodes [m].
    faces : (f, 3) int
        Boundary triangles of the tet mesh.
    regions : dict
        Region name -> :class:`~flexarm.robot.description.Region`.
    nodes : dict
        Region name -> (k,) int, its surface nodes.
    axes : tuple
        ``(name, point (3,), unit axis (3,))`` of each joint (and the TCP) on the link.
    """

    name: str
    points: FloatArray
    faces: IntArray
    regions: dict
    nodes: dict
    axes: tuple


@dataclass(frozen=True, eq=False)
class RegionsResult:
    """Regions of every link at ``mesh_size`` [m]; ``files`` once written."""

    robot: str
    mesh_size: float
    rows: tuple[RegionRow, ...]
    links: tuple[LinkRegions, ...]
    files: tuple[Path, ...] = field(default=())
    pairs: tuple[PairRow, ...] = field(default=())

    @property
    def ok(self) -> bool:
        """True when the build would accept every region (one marked for review too)."""
        return all(r.status in ("ok", REVIEW) for r in self.rows)

    @property
    def pairs_ok(self) -> bool:
        """True when the two seats of every joint face each other with enough nodes."""
        return all(p.ok for p in self.pairs)

    def text(self) -> str:
        """Table per link and region: FE nodes at the mesh size, CAD area [cm^2], radius
        range, axial extent and centroid offsets from the joint axis / origin [mm]."""
        lines = [f"interface regions of {self.robot} (tet mesh at {1e3 * self.mesh_size:g} mm; "
                 "area, radii and offsets on the CAD surface)",
                 f"{'link':<14} {'region':<9} {'FE_nodes':>8} {'area_cm2':>8} {'r_mm':>9} "
                 f"{'axial_mm':>8} {'off_axis_mm':>11} {'off_origin_mm':>13}  status"]
        for row in self.rows:
            s = row.seat
            lines.append(f"{row.link:<14} {row.region:<9} {row.fe_nodes:>8} {1e4 * s.area:>8.1f} "
                         f"{1e3 * s.r_lo:>4.0f}-{1e3 * s.r_hi:<4.0f} {1e3 * s.axial:>8.1f} "
                         f"{1e3 * s.axis_offset:>11.1f} {1e3 * s.origin_offset:>13.1f}  "
                         f"{row.status}")
        if self.pairs:
            lines += ["", pairs_text(self.pairs)]
        return "\n".join(lines)

    @writes_folder("out_dir")
    def write(self, out_dir, window_size=(1024, 768)) -> list[Path]:
        """``regions.csv`` and ``regions_<link>.png`` per link in ``out_dir``."""
        from ..reduction.render import render_backend

        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        files = [self._write_csv(out / "regions.csv")]
        render_backend()  # a clear error, not a crashed process, without off-screen GL
        for lk in self.links:
            files.append(_picture(lk, out / f"regions_{lk.name}.png", self.robot,
                                  self.mesh_size, window_size))
        return files

    def _write_csv(self, path: Path) -> Path:
        regs = {(lk.name, n): r for lk in self.links for n, r in lk.regions.items()}
        cols = ["link", "region", "fe_nodes", "cad_points", "area_m2", "r_lo_m", "r_hi_m",
                "axial_m", "axis_offset_m", "origin_offset_m", "rank", "center_x_m",
                "center_y_m", "center_z_m", "axis_x", "axis_y", "axis_z", "r_min_m", "r_max_m",
                "half_width_m", "status"]
        lines = [",".join(cols)]
        for row in self.rows:
            s = row.seat
            g = regs.get((row.link, row.region))
            geo = ([*g.center, *g.axis, g.r_min, g.r_max, g.half_width] if g is not None
                   else [np.nan] * 9)
            vals = [row.fe_nodes, s.n_points, s.area, s.r_lo, s.r_hi, s.axial, s.axis_offset,
                    s.origin_offset, s.rank, *geo]
            lines.append(",".join([row.link, row.region] + [f"{v:.6g}" for v in vals]
                                  + ['"' + row.status.replace('"', "'") + '"']))
        with atomic_path(path) as tmp:
            tmp.write_text("\n".join(lines) + "\n")
        return path


def _link_axes(robot: Robot, index: int) -> tuple:
    """(name, point, axis) of the joints (and the TCP) on link ``index`` (its frame)."""
    refs = region_references(robot)
    name = robot.links[index].name
    out = []
    for jt in robot.joints:
        if name in (jt.parent, jt.child):
            p, a = refs[(name, jt.name)]
            out.append((jt.name, p, a))
    if robot.chain.tcp_body == index and (name, "tcp") in refs:
        p, a = refs[(name, "tcp")]
        out.append(("tcp", p, a))
    return tuple(out)


def show_regions(robot: Robot, out_dir=None, mesh_size: float | None = None,
                 progress: Callable[[str], None] | None = None,
                 links: Sequence[str] | None = None) -> RegionsResult:
    """Every link's regions on its tet mesh at ``mesh_size`` [m] (default: the robot's).

    Links without a CAD mesh are left out, and with ``links`` (names) all others too.
    With ``out_dir`` the pictures and CSV are written there (``RegionsResult.files``).

    Examples
    --------
    >>> from flexarm.robot import load_robot
    >>> res = show_regions(load_robot(), mesh_size=0.06, links=["turning_disc"])
    >>> [(r.region, r.status, r.fe_nodes > 50) for r in res.rows]
    [('joint_6', 'ok', True), ('tcp', 'ok', True)]
    """
    h = robot.options.mesh_size if mesh_size is None else float(mesh_size)
    say = progress or (lambda message: None)
    unknown = sorted(set(links or ()) - set(robot.link_index))
    if unknown:
        raise ValueError(f"links: unknown link '{unknown[0]}' (robot has "
                         f"{', '.join(robot.link_index)})")
    refs = region_references(robot)
    rows, shown = [], []
    for i, lk in enumerate(robot.links):
        if lk.mesh is None or (links is not None and lk.name not in links):
            continue
        mesh = link_mesh(lk, h, robot.options.element_order, progress=say,
                         mesher=robot.options.mesher)
        sample = link_sample(lk)
        names = region_order(robot, lk)
        cyl = {n: CylinderRegion(n, g.center, g.axis, g.r_min, max(g.r_max, g.r_min + 1e-12),
                                 g.half_width) for n, g in lk.regions.items()}
        nodes = {n: select_region(mesh, cyl[n]) for n in names}
        status = {n: _spread_status(n, mesh.points[nodes[n]]) for n in names}
        missing = [jt.name for jt in robot.joints
                   if lk.name in (jt.parent, jt.child) and jt.name not in lk.regions]
        if missing:
            say(f"{lk.name}: no region for {', '.join(missing)}")
        else:
            try:  # what the build checks: its regions together (no node in two of them)
                interfaces(mesh, [cyl[n] for n in link_regions(robot, i)])
            except FlexarmError as exc:
                named = [n for n in names if f"'{n}'" in str(exc)] or names
                for n in named:
                    if status[n] == "ok":
                        status[n] = str(exc).replace(f"region '{n}' ", "")
        for n in names:  # a suggestion the build takes is still to be confirmed
            if status[n] == "ok" and is_review(lk.regions[n]):
                status[n] = REVIEW
            rows.append(RegionRow(lk.name, n, int(nodes[n].size),
                                  seat_row(lk.name, n, lk.regions[n], sample.points,
                                           sample.weight, refs[(lk.name, n)]), status[n]))
        rows += [RegionRow(lk.name, n, 0, SeatRow(lk.name, n, 0, 0.0, 0.0, 0.0, 0.0, np.nan,
                                                  np.nan, 0), "missing: the build needs one")
                 for n in missing]
        shown.append(LinkRegions(lk.name, mesh.points, mesh.boundary_faces(),
                                 {n: lk.regions[n] for n in names}, nodes, _link_axes(robot, i)))
    shown_names = {lk.name for lk in shown}
    pairs = tuple(pr for pr in pair_rows(robot, rows)
                  if {pr.pair.parent, pr.pair.child} & shown_names)
    res = RegionsResult(robot.name, h, tuple(rows), tuple(shown), pairs=pairs)
    if out_dir is not None:
        res = dataclasses.replace(res, files=tuple(res.write(out_dir)))
    return res


def _spread_status(name: str, points: FloatArray) -> str:
    try:
        check_spread(name, points)
    except FlexarmError as exc:
        return str(exc).replace(f"region '{name}': ", "")
    return "ok"


def _picture(lk: LinkRegions, path: Path, title: str, mesh_size: float,
             window_size) -> Path:
    """The link's surface in grey, each region's nodes in its colour with its cylinder
    drawn faintly, the joint axes as arrows through the joint origins (spheres); a legend
    names the regions.  ``title``: the robot's name."""
    import pyvista as pv

    from ..reduction.render import save_picture

    diag = float(np.linalg.norm(np.ptp(lk.points, axis=0)))
    surf = pv.PolyData(lk.points, np.column_stack([np.full(len(lk.faces), 3), lk.faces]).ravel())
    p = pv.Plotter(off_screen=True, window_size=window_size)
    p.set_background("white")
    # edges help to read a coarse mesh's shape; on a fine one they only darken it
    p.add_mesh(surf, color="#d9d9d9", opacity=0.5, show_edges=len(lk.faces) < 6000,
               edge_color="#b3b3b3", line_width=0.5)
    legend = []
    colour = {}
    for k, (name, reg) in enumerate(lk.regions.items()):
        c = _COLOURS[k % len(_COLOURS)]
        colour[name] = c
        idx = lk.nodes[name]
        if idx.size:
            p.add_mesh(pv.PolyData(lk.points[idx]), color=c, point_size=11,
                       render_points_as_spheres=True)
        height = 2.0 * reg.half_width
        shell = pv.Cylinder(center=reg.center, direction=reg.axis, radius=reg.r_max,
                            height=max(height, 1e-4 * diag), resolution=48, capping=False)
        p.add_mesh(shell, color=c, opacity=0.18)
        legend.append((f"{name}: {idx.size} FE nodes, r {1e3 * reg.r_min:.0f}-"
                       f"{1e3 * reg.r_max:.0f} mm, width {2e3 * reg.half_width:.0f} mm", c))
    drawn = []
    for name, point, axis in lk.axes:
        c = colour.get(name, "black")
        point, a = np.asarray(point, dtype=float), np.asarray(axis, dtype=float)
        p.add_mesh(pv.Sphere(radius=0.012 * diag, center=point), color=c)
        if name not in lk.regions:
            legend.append((f"{name}: axis only (no region)", c))
        if any(abs(a @ b) > 1 - 1e-9 and np.linalg.norm(np.cross(point - q, b)) < 1e-6 * diag
               for q, b in drawn):
            continue  # the TCP on the flange axis: its point only
        drawn.append((point, a))
        start = point - 0.35 * diag * a
        p.add_mesh(pv.Line(start, start + 0.7 * diag * a), color=c, line_width=3)
        p.add_mesh(pv.Arrow(start=start + 0.62 * diag * a, direction=a, scale=0.08 * diag),
                   color=c)
    # title and legend as text lines at the top (VTK's legend box squeezes or clips long
    # entries); the robot's name on a line of its own, as it may be long
    height = window_size[1]
    p.add_text(f"{lk.name}: interface regions, tet mesh {1e3 * mesh_size:g} mm",
               position=(12, height - 30), font_size=13, color="black")
    p.add_text(title, position=(12, height - 54), font_size=10, color="#555555")
    for k, (text, c) in enumerate(legend):
        p.add_text(text, position=(12, height - 84 - 22 * k), font_size=11, color=c)
    p.add_axes(color="black", viewport=(0.86, 0.0, 1.0, 0.16))
    p.view_isometric()
    p.reset_camera()
    p.camera.zoom(1.15)
    return save_picture(p, path, 1, lambda phase: None)
