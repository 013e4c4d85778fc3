"""Command line: a thin layer over the Python API (modelled on meshio's ``_cli``).

Each subcommand is a pair ``_add_<name>(parser)`` / ``_run_<name>(args) -> int``
registered in ``COMMANDS``.  Domain errors become one clear line on stderr and
exit code 2; no traceback (``FLEXARM_DEBUG=1`` shows it).
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
from typing import Callable

import numpy as np

__all__ = ["main"]

log = logging.getLogger("flexarm")


def _print(*args) -> None:
    print(*args)  # noqa: T201 - the CLI is where printing belongs


# ----------------------------------------------------------------------------- registry
# name -> (help, add_args, run)
COMMANDS: dict[str, tuple[str, Callable, Callable]] = {}


def command(name: str, help: str, add_args: Callable):
    """Decorator registering a run function with its argument builder.

    Usage::

        def _add_mesh(p): p.add_argument(...)

        @command("mesh", "tetrahedralise a CAD surface", _add_mesh)
        def _run_mesh(args) -> int: ...
    """

    def register(run):
        COMMANDS[name] = (help, add_args, run)
        return run

    return register


# ----------------------------------------------------------------------------- commands
# (subcommands are appended below this line, one block each)


class _Progress:
    """Start/finish lines with elapsed time on stderr; a ticking timer on a terminal."""

    def __init__(self, what: str):
        self.what = what

    def __enter__(self):
        import threading
        import time

        self.t0 = time.perf_counter()
        self._stop = threading.Event()
        sys.stderr.write(f"{self.what} ...")
        sys.stderr.flush()
        if sys.stderr.isatty():

            def tick():
                while not self._stop.wait(1.0):
                    dt = time.perf_counter() - self.t0
                    sys.stderr.write(f"\r{self.what} ... {dt:5.0f} s")
                    sys.stderr.flush()

            self._thread = threading.Thread(target=tick, daemon=True)
            self._thread.start()
        return self

    def note(self, text: str) -> None:
        sys.stderr.write(f"\n  {text}")
        sys.stderr.flush()

    def __exit__(self, exc_type, exc, tb):
        import time

        self._stop.set()
        dt = time.perf_counter() - self.t0
        status = "done" if exc_type is None else "failed"
        sys.stderr.write(f"\r{self.what} ... {status} in {dt:.1f} s\n")
        sys.stderr.flush()
        return False


def _table(headers: list[str], rows: list[list], floatfmt: str = "{:.6g}") -> str:
    """A plain fixed-width text table."""
    cells = [[floatfmt.format(c) if isinstance(c, float) else str(c) for c in r] for r in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h)
              for i, h in enumerate(headers)]
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in cells]
    return "\n".join(out)


# --- mesh ------------------------------------------------------------------------------
def _add_mesh(p: argparse.ArgumentParser) -> None:
    p.add_argument("surface", help="CAD surface: STL, OBJ or PLY")
    p.add_argument("--units", default="m", help="length unit of the CAD file: m, mm, cm, in")
    p.add_argument("--size", type=float, required=True, help="target edge length [m]")
    p.add_argument("--order", type=int, choices=(1, 2), default=1, help="1 = Tet4, 2 = Tet10")
    p.add_argument("--no-optimize", action="store_true", help="skip fTetWild optimisation")
    p.add_argument("--no-cache", action="store_true", help="ignore the tetrahedralisation cache")
    p.add_argument("-o", "--output", required=True, help="volume mesh: .vtu, .msh, .npz")


@command("mesh", "tetrahedralise a CAD surface (pytetwild) and report mesh quality", _add_mesh)
def _run_mesh(args) -> int:
    from .meshes import mesh_part, write_volume_mesh

    if args.size <= 0:
        raise ValueError(f"--size must be a positive edge length in metres, got {args.size}")
    with _Progress(f"meshing {args.surface} (edge {args.size * 1e3:g} mm, Tet{4 if args.order == 1 else 10})") as pr:
        mesh, quality = mesh_part(
            args.surface, units=args.units, size=args.size, order=args.order,
            optimize=not args.no_optimize, cache=not args.no_cache, progress=pr.note,
        )
    write_volume_mesh(args.output, mesh)
    _print(quality.table())
    _print(f"wrote {args.output}")
    return 0


# --- modal -----------------------------------------------------------------------------
def _add_modal(p: argparse.ArgumentParser) -> None:
    p.add_argument("mesh", help="volume mesh: .vtu, .msh, .npz")
    p.add_argument("--material", default="steel",
                   help="steel | cast_iron | aluminium | nafems | 'E,nu,rho' in SI units")
    p.add_argument("--fix", default=None,
                   help="clamped nodes, e.g. 'x=min', 'z<0.01', a node-set name; "
                        "omit for a free part")
    p.add_argument("-n", "--modes", type=int, default=10, help="number of modes (elastic)")
    p.add_argument("--backend", default=None, help="sparse solver: pardiso | cholmod | splu")
    p.add_argument("--csv", default=None, help="also write the table to this CSV file")


@command("modal", "natural frequencies of one part (free or clamped)", _add_modal)
def _run_modal(args) -> int:
    from .fe import (assemble, dof_split, material_from_string, modes, node_dofs,
                     select_nodes, shift_invert)
    from .fe.files import atomic_path
    from .meshes import read_volume_mesh

    material = material_from_string(args.material)
    if args.modes < 1:
        raise ValueError(f"-n must be >= 1, got {args.modes}")
    mesh = read_volume_mesh(args.mesh).check(args.mesh)
    with _Progress(f"assembling {mesh.n_tets} Tet{4 if mesh.order == 1 else 10} ({mesh.n_dofs} DOF)"):
        K, M = assemble(mesh, material)
    if args.fix:
        try:
            nodes = select_nodes(mesh, args.fix)
        except ValueError as exc:
            raise ValueError(f"{args.mesh}: --fix {exc}") from None
        split = dof_split(mesh.n_dofs, node_dofs(nodes))
        K, M = split.condense(K), split.condense(M)
        n, solver = args.modes, shift_invert(0.0, backend=args.backend)
    else:
        nodes = np.zeros(0)
        n, solver = args.modes + 6, shift_invert(None, backend=args.backend)
    with _Progress(f"eigen-solve: {n} modes of {K.shape[0]} DOF"):
        result = modes(K, M, n, eigensolver=solver)
    rows = [[i + 1, float(f), "rigid" if r else ""] for i, (f, r) in
            enumerate(zip(result.freq_hz, result.is_rigid))]
    mass = float(M.sum()) / 3 if not args.fix else None
    _print(f"{args.mesh}: {mesh.n_tets} tets, {mesh.n_dofs} DOF, material {material.name} "
           f"(E {material.E:.4g} Pa, nu {material.nu:g}, rho {material.rho:g} kg/m^3)")
    _print(f"support: {'clamped ' + str(len(nodes)) + ' nodes (' + args.fix + ')' if args.fix else 'free'}"
           + (f"; mass {mass:.6g} kg" if mass else ""))
    if not args.fix:
        _print(f"rigid-body modes: {result.n_rigid} (a free part has 6)")
    _print(_table(["mode", "freq [Hz]", ""], rows))
    if args.csv:
        with atomic_path(args.csv) as tmp:
            tmp.write_text("mode,freq_Hz,rigid\n" + "".join(
                f"{r[0]},{r[1]:.10g},{int(bool(r[2]))}\n" for r in rows))
    return 0



# --- demo ------------------------------------------------------------------------------
def _add_demo(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", default="flexarm-demo", help="output folder")


@command("demo", "the main job on the built-in robot: tables and pictures in flexarm-demo/",
         _add_demo)
def _run_demo(args) -> int:
    from .demo import run_demo

    report = run_demo(args.output, progress=lambda s: print(s, file=sys.stderr))  # noqa: T201
    for key, value in report.figures.items():
        _print(f"{key:>28s}  {value:.6g}")
    _print(f"demo finished in {report.seconds:.1f} s: open {report.folder / 'index.md'}")
    return 0


# --- arm analyses (E-model): modes | compliance | frf | map | import-urdf ----------------
def _add_arm_common(p: argparse.ArgumentParser, pose: bool = True) -> None:
    p.add_argument("--robot", default=None, help="robot TOML or URDF (default: built-in demo arm)")
    p.add_argument("--model", default="emodel", choices=["emodel"], help="arm model")
    if pose:
        p.add_argument("--pose", default="P1", help="named pose (P1, P2, P3) or q1,...,q6 [deg]")
    p.add_argument("--mass", default="tets", choices=["tets", "surface"],
                   help="link mass properties from tet meshes (default) or CAD surfaces")
    p.add_argument("-o", "--output", default=None, help="folder for PNG/CSV output")


def _arm_from_args(args):
    from .assembly.emodel import emodel
    from .assembly.formats import read
    from .meshes.demo_arm import load_demo_robot

    robot = load_demo_robot() if args.robot is None else read(args.robot)
    return robot, emodel(robot, method=args.mass, mesh_size=robot.options.mesh_size)


def _pose_from_args(robot, args):
    from .assembly.robot import pose_from_string

    return pose_from_string(robot, args.pose)


def _add_modes(p: argparse.ArgumentParser) -> None:
    _add_arm_common(p)


@command("modes", "eigenfrequencies and joint energy shares of the arm at a pose", _add_modes)
def _run_modes(args) -> int:
    from .assembly.analyses import modes

    robot, arm = _arm_from_args(args)
    md = modes(arm, _pose_from_args(robot, args))
    names = robot.joint_names
    _print(f"{'mode':>4s} {'freq_Hz':>10s} {'zeta':>7s}  " + " ".join(f"{n[-7:]:>7s}" for n in names))
    for r, f in enumerate(md.freq_hz):
        shares = " ".join(f"{e:7.3f}" for e in md.energy[:, r])
        _print(f"{r + 1:4d} {f:10.3f} {md.damping[r]:7.4f}  {shares}")
    if args.output:
        from .assembly.plots import plot_mode_energy

        p = plot_mode_energy(os.path.join(args.output, "mode_energy.png"), md.freq_hz,
                             md.energy, names)
        _print(f"wrote {p}")
    return 0


def _add_compliance(p: argparse.ArgumentParser) -> None:
    _add_arm_common(p)
    p.add_argument("--force", type=float, default=800.0, help="load per direction [N]")


@command("compliance", "TCP compliance, full vs diagonal stiffness, identification (eq. 3.12)",
         _add_compliance)
def _run_compliance(args) -> int:
    import numpy as np

    from .assembly.analyses import gravity_sag, identify_stiffness, tcp_compliance

    robot, arm = _arm_from_args(args)
    q = _pose_from_args(robot, args)
    C = tcp_compliance(arm, q)
    _print("TCP compliance, translations [mm/kN] (base frame):")
    for i, d in enumerate("xyz"):
        _print(f"  {d}  " + " ".join(f"{C[i, j] * 1e6:10.4f}" for j in range(3)))
    _print(f"deflection under {args.force:g} N [mm]: "
           + "  ".join(f"{d}={args.force * C[i, i] * 1e3:.3f}" for i, d in enumerate("xyz")))
    _print(f"least stiff direction: {'xyz'[int(np.argmax(np.diag(C)[:3]))]}")
    rep = identify_stiffness(arm, q, args.force * np.eye(3))
    _print("stiffness [N/mm]: full (eq. 3.12)            diagonal (eq. 3.9)")
    for i in range(3):
        _print("  " + " ".join(f"{rep.K_full[i, j] * 1e-3:9.1f}" for j in range(3)) + "    "
               + " ".join(f"{rep.K_diag[i, j] * 1e-3:9.1f}" for j in range(3)))
    _print("diagonal-model error per load case [%]: "
           + "  ".join(f"{d}+={e * 100:.1f}" for d, e in zip("xyz", rep.error_diag)))
    sag = gravity_sag(arm, q)
    _print("gravity sag of the TCP [mm]: " + "  ".join(f"{d}={sag[i] * 1e3:.3f}"
                                                      for i, d in enumerate("xyz")))
    return 0


def _add_frf(p: argparse.ArgumentParser) -> None:
    _add_arm_common(p)
    p.add_argument("--fmax", type=float, default=100.0, help="highest frequency [Hz]")


@command("frf", "TCP receptance (Bode) per direction with modal damping", _add_frf)
def _run_frf(args) -> int:
    import numpy as np

    from .assembly.analyses import frf

    robot, arm = _arm_from_args(args)
    q = _pose_from_args(robot, args)
    f = np.geomspace(0.5, args.fmax, 600)
    H = frf(arm, q, np.concatenate([[0.0], f]))
    _print("direction  static_gain_mm_per_kN  peak_Hz  peak_mm_per_kN")
    for d, name in enumerate("xyz"):
        k = int(np.argmax(np.abs(H[1:, d, d])))
        _print(f"{name:>9s}  {H[0, d, d].real * 1e6:21.4f}  {f[k]:7.2f}  "
               f"{abs(H[1 + k, d, d]) * 1e6:14.4f}")
    if args.output:
        from .assembly.plots import plot_frf

        p = plot_frf(os.path.join(args.output, "frf_bode.png"), f, H[1:],
                     f"TCP receptance at {args.pose}")
        _print(f"wrote {p}")
    return 0


def _add_map(p: argparse.ArgumentParser) -> None:
    _add_arm_common(p)
    p.add_argument("--n", type=int, default=60, help="grid points per joint")
    p.add_argument("--no-frequencies", action="store_true", help="skip the first eigenfrequency")


@command("map", "TCP stiffness Kxx, Kyy, Kzz and f1 over joints 2 and 3 (CSV, PNG)", _add_map)
def _run_map(args) -> int:
    import numpy as np

    from .assembly.maps import plot_map, stiffest, stiffness_map, write_csv

    robot, arm = _arm_from_args(args)
    q = _pose_from_args(robot, args)
    lo, hi = robot.lower, robot.upper
    m = stiffness_map(arm, q, np.linspace(lo[1], hi[1], args.n), np.linspace(lo[2], hi[2], args.n),
                      frequencies=not args.no_frequencies)
    share = np.bincount(m.least_stiff.ravel(), minlength=3) / m.least_stiff.size
    _print("least stiff direction share: "
           + "  ".join(f"{d}={s * 100:.1f}%" for d, s in zip("xyz", share)))
    for d, (a, b, k) in stiffest(m).items():
        _print(f"stiffest in {d}: q2={np.degrees(a):7.1f} deg q3={np.degrees(b):7.1f} deg "
               f"K{d}{d}={k * 1e-3:.0f} N/mm")
    if args.output:
        _print(f"wrote {write_csv(os.path.join(args.output, 'map.csv'), m)}")
        for p in plot_map(m, args.output):
            _print(f"wrote {p}")
    return 0


def _add_import_urdf(p: argparse.ArgumentParser) -> None:
    p.add_argument("urdf", help="robot.urdf")
    p.add_argument("-o", "--output", required=True, help="robot.toml to write")
    p.add_argument("--meshes", default="collision", choices=["collision", "visual"],
                   help="which URDF meshes become the link CAD")


@command("import-urdf", "write a robot TOML from a URDF (origins, axes, limits, STL meshes)",
         _add_import_urdf)
def _run_import_urdf(args) -> int:
    from .assembly.formats import toml as robot_toml
    from .assembly.formats import urdf

    robot = urdf.read(args.urdf, meshes=args.meshes)
    robot_toml.write(args.output, robot)
    _print(f"wrote {args.output}: {len(robot.links)} links, {len(robot.joints)} joints")
    return 0


# --- reduce | show | study-part (reduction) ---------------------------------------------
def _add_reduce(p: argparse.ArgumentParser) -> None:
    p.add_argument("mesh", help="volume mesh of one link: .vtu, .msh, .npz (link frame, m)")
    p.add_argument("--interface", action="append", default=[], metavar="NAME:cx,cy,cz,ax,ay,az,r,w",
                   help="cylinder region [m]: centre, axis, outer radius r, half-width w "
                        "(or ...,r_min,r_max,w); repeat per interface, in DOF order")
    p.add_argument("--node-set", action="append", default=[], metavar="NAME",
                   help="a node set of the mesh as an interface (after the cylinders)")
    p.add_argument("--coupling", default="rbe2", choices=["rbe2", "rbe3", "nodes"],
                   help="rbe2 = rigid spider, rbe3 = weighted average, nodes = keep region nodes")
    p.add_argument("--masters", type=int, default=None,
                   help="with --coupling nodes: region nodes kept per interface (default all)")
    p.add_argument("--method", default="cb", choices=["guyan", "cb"])
    p.add_argument("--modes", type=int, default=20, help="fixed-interface modes (cb)")
    p.add_argument("--diagonal", action="store_true",
                   help="modal block exactly M = I, K = diag(omega^2)")
    p.add_argument("--material", default="steel",
                   help="steel | cast_iron | aluminium | nafems | 'E,nu,rho' in SI units")
    p.add_argument("--volume-nodes", action="store_true",
                   help="regions may hold interior nodes (default: surface nodes only)")
    p.add_argument("--backend", default=None, help="sparse solver: pardiso | cholmod | splu")
    p.add_argument("-o", "--output", required=True, help="superelement file (.h5 default)")
    p.add_argument("--format", default=None, choices=["h5", "npz", "mtx", "dmig"],
                   help="file format (default: from the extension)")


@command("reduce", "reduce a meshed link to a superelement (RBE2/RBE3, Guyan/Craig-Bampton)",
         _add_reduce)
def _run_reduce(args) -> int:
    from .fe import material_from_string
    from .meshes import read_volume_mesh
    from .reduction import NodeSetRegion, formats, parse_cylinder, reduce_with_stats

    regions = [parse_cylinder(t) for t in args.interface]
    regions += [NodeSetRegion(n) for n in args.node_set]
    if not regions:
        raise ValueError("give at least one --interface NAME:cx,cy,cz,ax,ay,az,r,w or --node-set")
    material = material_from_string(args.material)
    formats.format_of(args.output, args.format)  # a bad extension fails before the work
    mesh = read_volume_mesh(args.mesh).check(args.mesh)
    with _Progress(f"reducing {mesh.n_dofs} DOF ({args.coupling}, {args.method})"):
        se, st = reduce_with_stats(
            mesh, material, regions, args.coupling, args.method, args.modes,
            n_masters=args.masters, diagonal=args.diagonal,
            surface_only=not args.volume_nodes, backend=args.backend)
    formats.write(args.output, se, args.format)
    _print(f"{args.mesh}: {mesh.n_tets} Tet{4 if mesh.order == 1 else 10}, material "
           f"{material.name}, mass {se.mass:.6g} kg, COM {np.round(se.center_of_mass, 6)} m")
    _print(_table(["", "DOF"], [["full FE model", st["n_full"]],
                                ["coupled", st["n_coupled"]],
                                ["superelement", st["n_reduced"]]]))
    _print(_table(["interface", "region nodes", "position [m]"],
                  [[n, st["region_nodes"][n], np.array2string(p, precision=4)]
                   for n, p in zip(se.interface_names, se.interface_positions, strict=True)]))
    if se.n_modes:
        _print(_table(["mode", "fixed-interface freq [Hz]"],
                      [[i + 1, float(f)] for i, f in enumerate(se.freq_hz)]))
    steps = [k for k in ("assemble_couple", "factorise", "constraint_modes", "eigen", "projection",
                         "total") if k in st]
    _print(_table(["step", "time [s]"], [[k, float(st[k])] for k in steps], "{:.3f}"))
    _print(f"wrote {args.output}")
    return 0


def _add_show(p: argparse.ArgumentParser) -> None:
    p.add_argument("superelement", help="superelement file (.h5 or .npz for pictures)")
    p.add_argument("--mode", type=int, default=None, help="mode number to draw (1-based)")
    p.add_argument("--boundary", default=None, choices=["fixed", "free"],
                   help="fixed-interface (default when available) or free-free modes")
    p.add_argument("-o", "--output", default=None, help="picture: .png or .gif (animation)")
    p.add_argument("--frames", type=int, default=24, help="GIF frames per period")
    p.add_argument("--interactive", action="store_true", help="open a window (needs a display)")


@command("show", "summarise a superelement and draw its mode shapes (PNG, GIF, window)",
         _add_show)
def _run_show(args) -> int:
    from .reduction import formats

    se = formats.read(args.superelement)
    _print(f"{args.superelement}: {se.method} ({se.coupling}), {se.n_dofs} DOF = "
           f"{se.n_boundary} interface + {se.n_modes} modal; mass {se.mass:.6g} kg, "
           f"COM {np.round(se.center_of_mass, 6)} m")
    _print(_table(["interface", "nodes", "position [m]"],
                  [[n, int(np.sum(se.node_interface == i)),
                    np.array2string(se.interface_positions[i], precision=4)]
                   for i, n in enumerate(se.interface_names)]))
    if se.n_modes:
        _print("fixed-interface frequencies [Hz]: "
               + ", ".join(f"{f:.6g}" for f in se.freq_hz))
    if args.mode is None:
        if args.output or args.interactive:
            raise ValueError("--mode N is needed to draw a picture")
        return 0
    from .reduction.render import render_mode

    out = render_mode(se, args.mode, args.output, args.boundary, n_frames=args.frames,
                      interactive=args.interactive)
    if out is not None:
        _print(f"wrote {out}")
    return 0


def _add_study_part(p: argparse.ArgumentParser) -> None:
    p.add_argument("--mesh", default=None,
                   help="volume mesh to study (default: built-in steel bars along x)")
    p.add_argument("--interface", action="append", default=[],
                   metavar="NAME:cx,cy,cz,ax,ay,az,r,w",
                   help="two regions with --mesh; the first one is clamped")
    p.add_argument("--divisions", default="12x2x2,24x3x3",
                   help="built-in bar meshes (cells along x, y, z), comma-separated")
    p.add_argument("--modes", default="0,5,10,20,40", help="CB mode counts (0 = Guyan)")
    p.add_argument("--representations", default="rbe2,rbe3,k4,k8,k16,all",
                   help="interface representations: rbe2, rbe3, k4, k8, k16, all")
    p.add_argument("--material", default="steel")
    p.add_argument("-o", "--output", default="study-part", help="output folder")


@command("study-part", "accuracy of reduced links vs the full FE model (CSV and log-log PNG)",
         _add_study_part)
def _run_study_part(args) -> int:
    from .fe import material_from_string
    from .reduction import parse_cylinder
    from .reduction.study import bar_link, plot_study, study_part, write_csv

    material = material_from_string(args.material)
    try:
        counts = [int(v) for v in args.modes.split(",")]
    except ValueError:
        raise ValueError(f"--modes must be comma-separated integers, got '{args.modes}'") from None
    reps = [r.strip() for r in args.representations.split(",") if r.strip()]
    if args.mesh:
        from .meshes import read_volume_mesh

        if len(args.interface) != 2:
            raise ValueError("with --mesh give exactly two --interface regions")
        meshes = [(os.path.basename(args.mesh), read_volume_mesh(args.mesh).check(args.mesh),
                   [parse_cylinder(t) for t in args.interface])]
    else:
        meshes = []
        for d in args.divisions.split(","):
            try:
                div = tuple(int(v) for v in d.lower().split("x"))
            except ValueError:
                div = ()
            if len(div) != 3:
                raise ValueError(f"--divisions entries must look like 12x2x2, got '{d}'")
            meshes.append((f"bar {d}", *bar_link(divisions=div)))
    with _Progress(f"study: {len(meshes)} meshes x {len(reps)} representations x "
                   f"{len(counts)} mode counts"):
        rows = study_part(material, meshes, reps, counts)
    _print(_table(["mesh", "repr", "modes", "DOF", "freq err", "compl err", "time [s]"],
                  [[r.mesh, r.representation, r.n_modes, r.n_reduced, r.freq_error,
                    r.compliance_error, r.reduce_seconds] for r in rows], "{:.3g}"))
    _print(f"wrote {write_csv(os.path.join(args.output, 'study.csv'), rows)}")
    _print(f"wrote {plot_study(os.path.join(args.output, 'study.png'), rows)}")
    return 0


# ----------------------------------------------------------------------------- main
def _parser() -> argparse.ArgumentParser:
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="flexarm",
        description="FE substructuring and modal reduction for industrial robot arms.",
    )
    parser.add_argument("--version", action="version", version=f"flexarm {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (help_, add_args, run) in COMMANDS.items():
        p = sub.add_parser(name, help=help_, description=help_)
        add_args(p)
        p.set_defaults(_run=run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the process exit code."""
    from .fe.errors import FlexarmError

    parser = _parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    if not getattr(args, "_run", None):
        parser.print_help()
        return 1
    try:
        return int(args._run(args) or 0)
    except (FlexarmError, ValueError, FileNotFoundError, PermissionError) as exc:
        if os.environ.get("FLEXARM_DEBUG"):
            raise
        msg = str(exc)
        if isinstance(exc, FileNotFoundError) and exc.filename and str(exc.filename) not in msg:
            msg = f"{exc.filename}: {msg}"
        print(f"flexarm {args.command}: error: {msg}", file=sys.stderr)  # noqa: T201
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)  # noqa: T201
        return 130


if __name__ == "__main__":
    sys.exit(main())
