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
from collections.abc import Callable

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
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=False)) for r in cells]
    return "\n".join(out)


# --- mesh ------------------------------------------------------------------------------
def _add_mesh(p: argparse.ArgumentParser) -> None:
    p.add_argument("surface", help="CAD surface: STL, OBJ or PLY")
    p.add_argument("--units", default="m", help="length unit of the CAD file: m, mm, cm, in")
    p.add_argument("--size", type=float, required=True, help="target edge length [m]")
    p.add_argument("--order", type=int, choices=(1, 2), default=1, help="1 = Tet4, 2 = Tet10")
    p.add_argument("--no-optimize", action="store_true", help="skip fTetWild optimisation")
    p.add_argument("--no-cache", action="store_true", help="ignore the tetrahedralisation cache")
    p.add_argument("--mesher", choices=("tetwild", "gmsh"), default="tetwild",
                   help="tetwild (robust on dirty CAD) or gmsh (deterministic; pip install gmsh)")
    p.add_argument("-o", "--output", required=True, help="volume mesh: .vtu, .msh, .npz")


@command("mesh", "tetrahedralise a CAD surface (pytetwild) and report mesh quality", _add_mesh)
def _run_mesh(args) -> int:
    from .meshes import mesh_part, write_volume_mesh

    if args.size <= 0:
        raise ValueError(f"--size must be a positive edge length in metres, got {args.size}")
    with _Progress(f"meshing {args.surface} (edge {args.size * 1e3:g} mm, "
                   f"Tet{4 if args.order == 1 else 10})") as pr:
        mesh, quality = mesh_part(
            args.surface, units=args.units, size=args.size, order=args.order,
            optimize=not args.no_optimize, cache=not args.no_cache, progress=pr.note,
            mesher=args.mesher,
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
    from .fe import (
        assemble,
        dof_split,
        material_from_string,
        modes,
        node_dofs,
        select_nodes,
        shift_invert,
    )
    from .fe.files import atomic_path
    from .meshes import read_volume_mesh

    material = material_from_string(args.material)
    if args.modes < 1:
        raise ValueError(f"-n must be >= 1, got {args.modes}")
    mesh = read_volume_mesh(args.mesh).check(args.mesh)
    with _Progress(f"assembling {mesh.n_tets} Tet{4 if mesh.order == 1 else 10} "
                   f"({mesh.n_dofs} DOF)"):
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
            enumerate(zip(result.freq_hz, result.is_rigid, strict=True))]
    mass = float(M.sum()) / 3 if not args.fix else None
    _print(f"{args.mesh}: {mesh.n_tets} tets, {mesh.n_dofs} DOF, material {material.name} "
           f"(E {material.E:.4g} Pa, nu {material.nu:g}, rho {material.rho:g} kg/m^3)")
    support = f"clamped {len(nodes)} nodes ({args.fix})" if args.fix else "free"
    _print(f"support: {support}" + (f"; mass {mass:.6g} kg" if mass else ""))
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
    p.add_argument("--part", action="store_true",
                   help="also run the single-part pipeline (full FE modes of one cast link)")
    p.add_argument("-j", "--jobs", type=int, default=2,
                   help="processes (default 2: the E-model and measurement steps run beside the "
                        "flexible arm; 1: every step in order, in this process)")


@command("demo", "the main job on the built-in robot: tables and pictures in flexarm-demo/",
         _add_demo)
def _run_demo(args) -> int:
    from .studies.demo import run_demo

    report = run_demo(args.output, progress=lambda s: print(s, file=sys.stderr),  # noqa: T201
                      part=args.part, jobs=args.jobs)
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
    from .robot.demo_arm import load_demo_robot
    from .robot.formats import read

    robot = load_demo_robot() if args.robot is None else read(args.robot)
    return robot, emodel(robot, method=args.mass, mesh_size=robot.options.mesh_size)


def _pose_from_args(robot, args):
    from .robot.description import pose_from_string

    return pose_from_string(robot, args.pose)


def _add_modes(p: argparse.ArgumentParser) -> None:
    _add_arm_common(p)


@command("modes", "eigenfrequencies and joint energy shares of the arm at a pose", _add_modes)
def _run_modes(args) -> int:
    from .assembly.analyses import modes

    robot, arm = _arm_from_args(args)
    md = modes(arm, _pose_from_args(robot, args))
    names = robot.joint_names
    _print(f"{'mode':>4s} {'freq_Hz':>10s} {'zeta':>7s}  "
           + " ".join(f"{n[-7:]:>7s}" for n in names))
    for r, f in enumerate(md.freq_hz):
        shares = " ".join(f"{e:7.3f}" for e in md.energy[:, r])
        _print(f"{r + 1:4d} {f:10.3f} {md.damping[r]:7.4f}  {shares}")
    if args.output:
        from .studies.plots import plot_mode_energy

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
           + "  ".join(f"{d}+={e * 100:.1f}" for d, e in zip("xyz", rep.error_diag, strict=True)))
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
        from .studies.plots import plot_frf

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
           + "  ".join(f"{d}={s * 100:.1f}%" for d, s in zip("xyz", share, strict=True)))
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
    p.add_argument("--total-mass", type=float, default=None, metavar="KG",
                   help="scale the link densities so the robot weighs KG (solid CAD hulls of "
                        "hollow castings are far too heavy otherwise)")


@command("import-urdf", "write a robot TOML from a URDF (origins, axes, limits, STL meshes)",
         _add_import_urdf)
def _run_import_urdf(args) -> int:
    from .assembly.emodel import total_mass, with_total_mass
    from .robot.formats import toml as robot_toml
    from .robot.formats import urdf

    robot = urdf.read(args.urdf, meshes=args.meshes)
    solid = total_mass(robot, "surface")
    if args.total_mass is not None:
        robot = with_total_mass(robot, args.total_mass)
    robot_toml.write(args.output, robot)
    _print(f"wrote {args.output}: {len(robot.links)} links, {len(robot.joints)} joints, "
           f"{total_mass(robot, 'surface'):.1f} kg (solid CAD: {solid:.1f} kg)")
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
    _print(_table(["", "DOF"], [["full FE model", st.n_full],
                                ["coupled", st.n_coupled],
                                ["superelement", st.n_reduced]]))
    _print(_table(["interface", "region nodes", "position [m]"],
                  [[n, st.region_nodes[n], np.array2string(p, precision=4)]
                   for n, p in zip(se.interface_names, se.interface_positions, strict=True)]))
    if se.n_modes:
        _print(_table(["mode", "fixed-interface freq [Hz]"],
                      [[i + 1, float(f)] for i, f in enumerate(se.freq_hz)]))
    steps = [k for k in ("assemble_couple", "factorise", "constraint_modes", "eigen", "projection",
                         "total") if k in st.seconds]
    _print(_table(["step", "time [s]"], [[k, float(st.seconds[k])] for k in steps], "{:.3f}"))
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
    from .studies.part_study import bar_link, plot_study, study_part, write_csv

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


# --- contact applications (issue 7): circle | chatter | chatter-map ---------------------
def _add_circle(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None,
                   help="robot TOML (with an optional [nonlinear] table) or URDF (default: demo)")
    p.add_argument("--model", default="emodel", choices=["emodel", "cb", "guyan"],
                   help="rigid links (E-model) or flexible links (Craig-Bampton, Guyan)")
    p.add_argument("--compare-models", action="store_true",
                   help="overlay the E-model and the flexible model (cb unless --model guyan)")
    p.add_argument("--mesh-size", type=float, default=None, help="flexible links: tet edge [m]")
    p.add_argument("--modes", type=int, default=None, help="CB modes per link (robot default)")
    p.add_argument("--effect", action="append", default=[],
                   help="extra joint effect, e.g. backlash:j3=0.2mrad (repeatable)")
    p.add_argument("--mass", default="surface", choices=["tets", "surface"],
                   help="E-model mass properties from CAD surfaces (default) or tet meshes")
    p.add_argument("-o", "--output", default=None, help="folder for PNG/CSV output")
    p.add_argument("--rapid", default=None, help="RAPID module (default: the thesis's appendix B)")
    p.add_argument("--proc", default="Path_30", help="procedure name")
    p.add_argument("--loads", default="0,200,400,800", help="bar forces [N], comma-separated")
    p.add_argument("--pull", action="store_true", help="the bar pulls (default: pushes)")
    p.add_argument("--pivot", default=None, help="bar pivot x,y,z [mm] (default: fitted)")
    p.add_argument("--tool", default="tool0", choices=["tool0", "robot"],
                   help="load point: flange (tool0, as programmed) or the robot's TCP")
    p.add_argument("--step", type=float, default=2.0, help="path sampling step [mm]")
    p.add_argument("--measured", default=None,
                   help="measured circle to overlay: path CSV or static-schema CSV")


def _circle_robot(args):
    """Robot and its effects: TOML [nonlinear] table plus ``--effect`` options."""
    from .robot.demo_arm import load_demo_robot
    from .robot.effects import parse_effect
    from .robot.formats import read
    if args.robot is None:
        robot, effects = load_demo_robot(), []
    else:
        robot = read(args.robot)
        effects = list(robot.effects)
    return robot, effects + [parse_effect(e, robot.chain.n_joints) for e in args.effect]


@command("circle", "loaded circle test (LDBB): deviation, polar plot, Z along the path",
         _add_circle)
def _run_circle(args) -> int:
    from importlib.resources import files

    from .assembly.effects import apply_effects
    from .robot.formats.rapid import read_rapid
    from .studies.contact import measured_deviation, predict_circle, rapid_circle
    from .studies.contact.circle_data import static_circle_readings, write_circle_csv
    from .studies.contact.circle_models import circle_arm, nonlinear_solver
    from .studies.contact.plots import plot_circle_polar, plot_circle_top, plot_circle_z

    robot, effects = _circle_robot(args)
    mod = read_rapid(args.rapid or files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")
    if args.proc not in mod.procedures:
        raise ValueError(f"no procedure {args.proc} (module has {sorted(mod.procedures)})")
    pivot = None if args.pivot is None else np.array(args.pivot.split(","), float) * 1e-3
    setup = rapid_circle(robot, mod, args.proc, pivot, args.tool, args.step)
    loads = np.array(args.loads.split(","), dtype=float)
    _print(f"{args.proc}: {len(setup.points)} samples, load point {args.tool}, pivot "
           f"{np.round(setup.pivot * 1e3, 3).tolist()} mm, bar {setup.bar_length.mean() * 1e3:.3f}"
           f" mm, circle R {setup.radius * 1e3:.3f} mm; conf met at "
           f"{int(setup.ik.is_conf_met.sum())}/{len(setup.ik.is_conf_met)} targets")
    for note in setup.ik.notes:
        _print(f"  note: {note}")
    names = [args.model]
    if args.compare_models:
        names = ["emodel", "guyan" if args.model == "guyan" else "cb"]
    ang = np.degrees(setup.angles)
    runs = []
    for name in names:
        arm = circle_arm(robot, name, args.mass, args.mesh_size, args.modes)
        arm, laws = apply_effects(arm, effects)
        pred = predict_circle(arm, setup, loads, args.pull, nonlinear_solver(laws))
        label = {"emodel": "E-model", "cb": "CB", "guyan": "Guyan"}[name]
        runs.append((label, pred))
        _print(f"{label} ({pred.method}{', laws on joints ' if laws else ''}"
               f"{','.join(str(j + 1) for j in sorted(laws))}):")
        for F, b, z in zip(loads, pred.bar, pred.normal, strict=True):
            k = int(np.argmax(np.abs(b)))
            _print(f"  {F:6.0f} N: max |bar| {np.abs(b).max() * 1e3:.4f} mm at {ang[k]:7.1f} deg,"
                   f" max |normal| {np.abs(z).max() * 1e3:.4f} mm")
    meas = None
    if args.measured:
        from .validation import read_measurements

        data = read_measurements(args.measured)
        if hasattr(data, "points"):
            meas = measured_deviation(setup, data.points, data.force)
        elif hasattr(data, "disp"):
            meas = measured_deviation(setup, *static_circle_readings(setup, robot.chain, data))
        else:
            raise ValueError("--measured: give a path CSV (step, x_mm, y_mm, z_mm, f_N) or a "
                             "static CSV (series, step, q1_deg.., fx_N.., dx_mm..)")
        _print(f"measured: {len(meas[0])} readings at {np.unique(meas[3]).tolist()} N, max |bar| "
               f"{np.abs(meas[1]).max() * 1e3:.4f} mm")
    if args.output:
        os.makedirs(args.output, exist_ok=True)
        csv = os.path.join(args.output, f"circle_{args.proc}.csv")
        write_circle_csv(csv, runs)
        _print(f"wrote {csv}")
        (label, pred), rest = runs[0], runs[1:]
        kw = {"label": label if rest else "", "compare": rest}
        out = args.output
        for path in (plot_circle_top(pred, os.path.join(out, "circle_top.png"), **kw),
                     plot_circle_polar(pred, os.path.join(out, "circle_polar.png"), meas, **kw),
                     plot_circle_z(pred, os.path.join(out, "circle_z.png"), meas, **kw)):
            _print(f"wrote {path}")
    return 0


def _add_chatter(p: argparse.ArgumentParser) -> None:
    _add_arm_common(p)
    p.add_argument("--kc", type=float, default=2e6, help="process stiffness K_c*b [N/m]")
    p.add_argument("--dir", type=float, default=30.0, help="force angle from the normal [deg]")
    p.add_argument("--normal", type=float, default=None,
                   help="surface-normal angle from e1 in the plane [deg] (default: worst case)")
    p.add_argument("--cnc-stiffness", type=float, default=5e7, help="CNC stiffness [N/m]")
    p.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")


@command("chatter", "mode-coupling chatter at a pose (2-DOF, closed form + simulation) vs a CNC",
         _add_chatter)
def _run_chatter(args) -> int:
    from .studies.contact import analyse, cnc_model, critical_kcb, plane_model, simulate
    from .studies.contact.chatter import process_vectors
    from .studies.contact.chatter_map import worst_normal
    from .studies.contact.plots import plot_chatter_orbit, plot_chatter_time

    robot, arm = _arm_from_args(args)
    q = _pose_from_args(robot, args)
    pm = plane_model(arm, q)
    normal = args.normal
    if normal is None:
        normal = float(worst_normal(pm.M, pm.C, pm.K, args.dir)[1])
    cnc = cnc_model(args.cnc_stiffness, float(np.trace(pm.M)) / 2, axes=pm.axes)
    n, f = process_vectors(normal, args.dir)
    _print(f"plane e1={np.round(pm.axes[0], 3).tolist()} e2={np.round(pm.axes[1], 3).tolist()}; "
           f"normal {normal:.1f} deg, force {args.dir:.1f} deg from it, K_c b {args.kc:.3g} N/m")
    runs, stable = [], []
    for model in (pm, cnc):
        res = analyse(model, args.kc, args.dir, normal)
        lim = float(critical_kcb(model.M, model.C, model.K, n, f))
        ks = np.linalg.eigvalsh(model.K)
        _print(f"{model.name:5s}: K principal {ks[0]:.3g}/{ks[1]:.3g} N/m, M diag "
               f"{np.diag(model.M).round(1).tolist()} kg, growth {res.growth_rate:+.3f} 1/s, "
               f"limit K_c b {lim:.3g} N/m -> {'stable' if res.is_stable else 'UNSTABLE'}")
        t, x = simulate(model.M, model.C, res.K_total, 1e-5 * n, args.duration)
        stable.append(res.is_stable)
        runs.append((f"{model.name}: {'stable' if res.is_stable else 'chatter'}, growth "
                     f"{res.growth_rate:+.2f} 1/s", t, x))
    verdict = "; ".join(f"{m.name} {'stable' if ok else 'CHATTERS (mode coupling)'}"
                        for m, ok in zip((pm, cnc), stable, strict=True))
    _print(f"verdict: {verdict}")
    if args.output:
        os.makedirs(args.output, exist_ok=True)
        _print(f"wrote {plot_chatter_time(runs, os.path.join(args.output, 'chatter_time.png'))}")
        _print(f"wrote {plot_chatter_orbit(runs, os.path.join(args.output, 'chatter_orbit.png'))}")
    return 0


def _add_chatter_map(p: argparse.ArgumentParser) -> None:
    _add_arm_common(p)
    p.add_argument("--dir", type=float, default=30.0, help="force angle from the normal [deg]")
    p.add_argument("--normal", type=float, default=None,
                   help="surface-normal angle in the plane [deg] (default: worst case)")
    p.add_argument("--n", type=int, default=25, help="grid points per joint")


@command("chatter-map", "limit K_c*b (mode coupling) over joints 2 and 3 (CSV, PNG)",
         _add_chatter_map)
def _run_chatter_map(args) -> int:
    from .studies.contact import chatter_map, recommendation
    from .studies.contact.plots import plot_chatter_map

    robot, arm = _arm_from_args(args)
    q = _pose_from_args(robot, args)
    lo, hi = robot.lower, robot.upper
    cm = chatter_map(arm, q, np.linspace(lo[1], hi[1], args.n), np.linspace(lo[2], hi[2], args.n),
                     args.dir, args.normal, lower=lo, upper=hi)
    for b2, b3, k in cm.best(3):
        _print(f"best: q2={b2:7.1f} deg q3={b3:7.1f} deg limit K_c b={k:.3g} N/m")
    _print(recommendation(cm))
    if args.output:
        os.makedirs(args.output, exist_ok=True)
        G2, G3 = np.meshgrid(np.degrees(cm.q2), np.degrees(cm.q3), indexing="ij")
        csv = os.path.join(args.output, "chatter_map.csv")
        np.savetxt(csv, np.column_stack([G2.ravel(), G3.ravel(), cm.kcb.ravel(),
                                         cm.normal_deg.ravel(), cm.k_weak.ravel()]),
                   delimiter=",", header="q2_deg,q3_deg,kcb_limit_N/m,normal_deg,k_weak_N/m",
                   comments="", fmt="%.9g")
        _print(f"wrote {csv}")
        _print(f"wrote {plot_chatter_map(cm, os.path.join(args.output, 'chatter_map.png'))}")
    return 0


# --- validation: lab | compare | diagnose (issue 6) -----------------------------------
def _validation_arm(args):
    """Robot (with its optional [nonlinear] table) and its E-model."""
    from .assembly.emodel import emodel
    from .robot.demo_arm import load_demo_robot
    from .robot.formats import read

    if args.robot is None:
        robot, effects = load_demo_robot(), []
    else:
        robot = read(args.robot)
        effects = list(robot.effects)
    return robot, emodel(robot, method=args.mass, mesh_size=robot.options.mesh_size), effects


def _add_validation_common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML (default: built-in demo arm)")
    p.add_argument("--mass", default="surface", choices=["tets", "surface"],
                   help="link mass properties from CAD surfaces (default) or tet meshes")
    p.add_argument("--flexible", action="store_true", help="build the flexible model (link "
                   "flexibility); the E-model then takes its masses from the same tet meshes")
    p.add_argument("--flex-mesh", type=float, default=0.06,
                   help="tet size [m] of the flexible model (default 0.06, cached)")


def _flexible_models(args, robot, arm):
    """(E-model, flexible model) when --flexible, else (arm, None)."""
    if not args.flexible:
        return arm, None
    from .assembly.build import BuildOptions
    from .assembly.emodel import emodel
    from .assembly.flexible import flexible_arm

    with _Progress(f"flexible model (mesh {args.flex_mesh} m, cached after the first run)"):
        fa = flexible_arm(robot, BuildOptions(mesh_size=args.flex_mesh, n_modes=4))
    return emodel(robot, method="tets", mesh_size=args.flex_mesh), fa


def _with_links(effects, flexible) -> list:
    """Effects plus the flexible model's links (``links:c=1``) when one was built."""
    from .robot.effects import Effect

    if flexible is None or any(e.kind == "links" for e in effects):
        return list(effects)
    return list(effects) + [Effect("links", None, (("compliance", 1.0),))]


def _parse_noise(text: str, quantity: str = "length") -> float:
    """'15um' -> 1.5e-5 (SI); a bare number is SI."""
    from .validation.units import si_factor

    m = __import__("re").fullmatch(r"([0-9.eE+-]+)\s*([a-z]*)", text.strip())
    if not m:
        raise ValueError(f"noise '{text}': expected a number with a unit like 15um")
    return float(m.group(1)) * (float(si_factor(quantity, m.group(2))) if m.group(2) else 1.0)


def _add_lab(p: argparse.ArgumentParser) -> None:
    _add_validation_common(p)
    p.add_argument("--effect", action="append", default=[],
                   help="hidden effect, e.g. backlash:j2=0.1mrad (repeatable)")
    p.add_argument("--noise", default="15um", help="tracker noise, e.g. 15um")
    p.add_argument("--poses", default="P1,P2,P3", help="named poses")
    p.add_argument("--loads", default="0:800:100", help="load levels [N] start:stop:step")
    p.add_argument("--dirs", default="x,y,z", help="load directions, e.g. x,y,z,-z")
    p.add_argument("--cycles", action="store_true", help="load then unload each series")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--ref-noise", default="0um", help="extra error of each series' reference "
                   "reading, e.g. 45um (tracker re-lock; stated in the sigma column)")
    p.add_argument("--modal", default=None, help="also write natural frequencies to this CSV")
    p.add_argument("--n-modes", type=int, default=4, help="modes per pose in --modal")
    p.add_argument("--freq-noise", type=float, default=0.5, help="frequency noise [%%]")
    p.add_argument("-o", "--output", required=True, help="static CSV to write")


@command("lab", "virtual lab: static series from the model + hidden effects + tracker noise",
         _add_lab)
def _run_lab(args) -> int:
    from .robot.effects import parse_effect
    from .validation import write_modal
    from .validation.lab import LabPlan, parse_dirs, parse_loads, virtual_lab, write_lab
    from .validation.modal import virtual_modal

    robot, arm, base_effects = _validation_arm(args)
    noise = _parse_noise(args.noise)
    effects = list(base_effects) + [parse_effect(s, len(robot.joints)) for s in args.effect]
    args.flexible = args.flexible or any(e.kind == "links" for e in effects)
    arm, flexible = _flexible_models(args, robot, arm)
    plan = LabPlan({p: robot.pose(p) for p in args.poses.split(",")}, parse_loads(args.loads),
                   parse_dirs(args.dirs), args.cycles)
    ref_noise = _parse_noise(args.ref_noise)
    data = virtual_lab(arm, plan, effects, noise, args.seed, flexible, ref_noise)
    truth = {"effects": [e.to_dict() for e in effects], "noise_m": noise, "seed": args.seed,
             "robot": args.robot or "demo", "ref_noise_m": ref_noise}
    if flexible is not None:
        truth["flexible_mesh_m"] = args.flex_mesh
    if args.modal:
        modal = virtual_modal(arm, plan.poses, effects, args.n_modes, args.freq_noise / 100,
                              args.seed, flexible)
        truth["freq_noise"] = args.freq_noise / 100
        _print(f"wrote {write_modal(args.modal, modal, ('virtual lab data (flexarm lab)',))} "
               f"({len(modal.freq_hz)} frequencies)")
    path, tpath = write_lab(args.output, data, truth)
    _print(f"wrote {path} ({len(data.series)} readings, {data.n_series} series) and {tpath}")
    return 0


def _add_compare(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", help="measurement CSV: static, modal or frf (recognised by columns)")
    _add_validation_common(p)
    p.add_argument("--noise", type=float, default=15.0, help="tracker noise [um] (no sigma column)")
    p.add_argument("--freq-noise", type=float, default=0.5, help="frequency noise [%%] (modal)")
    p.add_argument("-o", "--output", default=None, help="report folder (CSV, PNG)")


def _compare_dynamic(args, data) -> int:
    """`compare` on modal or FRF data: error table, chi2_red (modal), plots."""
    from .validation import ModalData
    from .validation import compare_dynamic as cd

    robot, arm, effects = _validation_arm(args)
    arm, flexible = _flexible_models(args, robot, arm)
    effects = _with_links(effects, flexible)
    if isinstance(data, ModalData):
        cmp = cd.compare_modal(arm, data, effects, args.freq_noise / 100, flexible)
        _print(_table(["pose", "mode", "measured_Hz", "model_Hz", "error_Hz", "error_%"],
                      [[r.pose, r.mode, r.measured_hz, r.model_hz, r.error_hz,
                        r.error_pct] for r in cmp.table], "{:.3f}"))
        _print(f"chi2_red = {cmp.chi2_red:.3f} (band {cmp.band[0]:.3f}-{cmp.band[1]:.3f} for "
               f"{args.freq_noise}% frequency noise), RMS error {cmp.rms_pct:.2f}%")
        write = cd.write_modal_report
    else:
        cmp = cd.compare_frf(arm, data, effects, flexible)
        _print(_table(["pose", "in", "out", "rms_log10|H|", "peak_meas_Hz", "peak_model_Hz",
                       "peak_err_%"], [[r.pose, r.input, r.output, r.rms_log10_mag,
                                        r.peak_meas_hz, r.peak_model_hz,
                                        r.peak_error_pct] for r in cmp.table], "{:.3f}"))
        write = cd.write_frf_report
    if args.output:
        for p in write(args.output, cmp):
            _print(f"wrote {p}")
    return 0


@command("compare", "model predictions vs static measurements: errors, chi2_red, plots",
         _add_compare)
def _run_compare(args) -> int:
    from .validation import FrfData, ModalData, read_measurements
    from .validation.compare import compare_static, write_report

    data = read_measurements(args.data)
    if isinstance(data, (ModalData, FrfData)):
        return _compare_dynamic(args, data)
    robot, arm, effects = _validation_arm(args)
    arm, flexible = _flexible_models(args, robot, arm)
    effects = _with_links(effects, flexible)
    cmp = compare_static(arm, data, effects, args.noise * 1e-6, flexible)
    _print(_table(["series", "mean_abs_mm", "max_abs_mm", "relative", "max_meas_mm"],
                  [[r.series, r.mean_abs_mm, r.max_abs_mm, r.relative,
                    r.max_meas_mm] for r in cmp.table], "{:.4f}"))
    lo, hi = cmp.band
    _print(f"chi2_red = {cmp.chi2_red:.3f} (band {lo:.3f}-{hi:.3f} for the stated noise), "
           f"RMS = {cmp.rms * 1e6:.1f} um")
    if args.output:
        for p in write_report(args.output, cmp):
            _print(f"wrote {p}")
    return 0


def _add_diagnose(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", help="static measurement CSV")
    _add_validation_common(p)
    p.add_argument("--noise", type=float, default=15.0, help="tracker noise [um] (no sigma column)")
    p.add_argument("--apply", action="store_true", help="write a robot TOML with the accepted "
                   "effects and fitted parameters (-o)")
    p.add_argument("-o", "--output", default=None, help="robot TOML for --apply")
    p.add_argument("--report", default=None, help="folder for the history CSV/JSON/PNG")
    p.add_argument("--noise-model", default="shared", choices=["shared", "independent"],
                   help="shared reference reading (GLS, default) or independent rows (only "
                   "to show the shared-reference trap)")
    p.add_argument("--modal", default=None, help="measured natural frequencies CSV (joins the "
                   "fits; implies --flexible)")
    p.add_argument("--freq-noise", type=float, default=0.5, help="frequency noise [%%]")


@command("diagnose", "find which physical effect the model misses in static measurements",
         _add_diagnose)
def _run_diagnose(args) -> int:
    from .robot.formats import write as write_robot
    from .validation import read_measurements
    from .validation.diagnose import diagnose
    from .validation.history import robot_with_effects, write_history

    if args.apply and not args.output:
        raise ValueError("--apply needs -o NEW_ROBOT.toml")
    robot, arm, effects = _validation_arm(args)
    if effects:
        raise ValueError("diagnose starts from a linear model: the robot file already has "
                         "a [nonlinear] table")
    data = read_measurements(args.data)
    modal = None if args.modal is None else read_measurements(args.modal)
    args.flexible = args.flexible or modal is not None
    arm, flexible = _flexible_models(args, robot, arm)
    dg = diagnose(arm, data, args.noise * 1e-6, args.noise_model, poses=robot.poses, modal=modal,
                  flexible=flexible, freq_noise=args.freq_noise / 100)
    ident = dg.identifiability
    _print(f"identifiability: condition {ident.condition:.3g}, singular "
           f"values {', '.join(f'{v:.3g}' for v in ident.singular_values)}")
    for j, s in ident.sign_changes.items():
        _print(f"  {j} torque changes sign in: {', '.join(s) if s else 'no series'}")
    for k, v in ident.leave_one_pose_out.items():
        _print(f"  leave-one-pose-out chi2_red on {k}: {v:.3f}")
    for i, st in enumerate(dg.steps):
        _print(f"\nv{i} {st.label}: chi2_red {st.chi2_red:.3f} (band {st.band[0]:.3f}-"
               f"{st.band[1]:.3f}), RMS fitted {st.rms_fit * 1e6:.1f} um, held-out "
               f"{st.rms_heldout * 1e6:.1f} um")
        if st.candidates:
            _print(_table(["candidate", "status", "dBIC", "unique", "norm", "detail"],
                          [[c.label, c.status, f"{c.dbic:.1f}", f"{c.unique:.2f}",
                            f"{c.norm:.1f}", c.detail] for c in st.candidates]))
        if st.winner is not None:
            _print(("ACCEPTED: " if st.accepted else "best, not accepted: ") + st.explanation)
    for n in dg.notes:
        _print(f"note: {n}")
    if args.report:
        for p in write_history(args.report, dg):
            _print(f"wrote {p}")
    if args.apply:
        write_robot(args.output, robot_with_effects(robot, arm, dg.final_effects))
        _print(f"wrote {args.output}")
    return 0


# --- flexible arm (issue 5): build | compare-models ------------------------------------
def _robot_arg(args):
    from .robot.demo_arm import load_demo_robot
    from .robot.formats import read

    return load_demo_robot() if args.robot is None else read(args.robot)


def _add_build(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML (default: built-in demo arm)")
    p.add_argument("--method", default="cb", choices=["cb", "guyan"], help="reduction")
    p.add_argument("--modes", type=int, default=None, help="CB modes per link (robot default)")
    p.add_argument("--coupling", default="rbe2", choices=["rbe2", "rbe3"])
    p.add_argument("--mesh-size", type=float, default=None, help="tet edge [m] (robot default)")


@command("build", "mesh and reduce every link of a robot (cached superelements)", _add_build)
def _run_build(args) -> int:
    from .assembly.build import BuildOptions, build_robot

    robot = _robot_arg(args)
    opts = BuildOptions(args.method, args.modes, args.coupling, args.mesh_size)
    builds = build_robot(robot, opts, progress=lambda s: print(s, file=sys.stderr))  # noqa: T201
    _print(f"{'link':<14} {'tets':>7} {'DOF':>7} {'reduced':>7} {'time_s':>7}  "
           f"fixed-interface f [Hz]")
    for lb in builds:
        f = " ".join(f"{v:.0f}" for v in lb.freq_hz[:5]) or "-"
        src = "cache" if lb.is_cached else f"{lb.seconds:7.1f}"
        kind = "rigid" if lb.superelement is None else lb.n_reduced
        _print(f"{lb.name:<14} {lb.n_tets:>7} {lb.n_fe_dofs:>7} {kind:>7} {src:>7}  {f}")
    return 0


def _add_compare_models(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML (default: built-in demo arm)")
    p.add_argument("--poses", default="P1,P2,P3", help="comma-separated pose names")
    p.add_argument("--modes", type=int, default=None, help="CB modes per link (robot default)")
    p.add_argument("--coupling", default="rbe2", choices=["rbe2", "rbe3"])
    p.add_argument("--mesh-size", type=float, default=None, help="tet edge [m] (robot default)")
    p.add_argument("--no-full-fe", action="store_true", help="skip the full-FE reference")
    p.add_argument("-o", "--output", default="flexarm-compare", help="folder for CSV and PNG")


@command("compare-models", "E-model vs Guyan vs CB vs CB+wrist vs full FE at poses (CSV, PNG)",
         _add_compare_models)
def _run_compare_models(args) -> int:
    from .studies.compare_models import compare_models

    robot = _robot_arg(args)
    rep = compare_models(robot, [s for s in args.poses.split(",") if s.strip()], args.modes,
                         args.coupling, args.mesh_size, full_fe=not args.no_full_fe,
                         out_dir=args.output,
                         progress=lambda s: print(s, file=sys.stderr))  # noqa: T201
    _print(rep.text())
    for f in rep.files:
        _print(f"wrote {f}")
    return 0


# --- flexible arm (issue 5): study | show-arm ------------------------------------------
def _floats(text: str) -> list[float]:
    return [float(s) for s in text.split(",") if s.strip()]


def _add_study(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML (default: built-in demo arm)")
    p.add_argument("--pose", default="P1", help="pose name or 'q1,...,qn' in degrees")
    p.add_argument("--preset", default=None, choices=["small", "full"],
                   help="named sweep (explicit --sizes/--modes/--couplings override it)")
    p.add_argument("--sizes", default=None,
                   help="tet edges [m], e.g. 0.06,0.045,0.03 (default 1.5x and 1x the robot's)")
    p.add_argument("--modes", default=None, help="CB modes per link, 0 = Guyan (0,5,10,20)")
    p.add_argument("--couplings", default=None, help="rbe2,rbe3,k<N> (rbe2,rbe3,k4,k8)")
    p.add_argument("--reference-coupling", default="rbe2", choices=["rbe2", "rbe3"])
    p.add_argument("-o", "--output", default="flexarm-study", help="folder for CSV and PNGs")


@command("study", "accuracy of the whole arm vs node count, CB modes and interface "
         "representation against full FE (CSV, PNGs, verdict)", _add_study)
def _run_study(args) -> int:
    from .studies.arm_study import PRESETS, run_study

    robot = _robot_arg(args)
    pre = PRESETS[args.preset or "full"]
    sizes = _floats(args.sizes) if args.sizes else pre["sizes"]
    modes = [int(v) for v in _floats(args.modes)] if args.modes else pre["modes"]
    couplings = ([s.strip() for s in args.couplings.split(",") if s.strip()]
                 if args.couplings else pre["couplings"])
    res = run_study(robot, args.pose, sizes, modes, couplings, args.output,
                    progress=lambda s: print(s, file=sys.stderr, flush=True),  # noqa: T201
                    reference_coupling=args.reference_coupling)
    ref = res.reference
    _print(f"reference: full FE, {ref.n_dofs} DOF at {ref.mesh_size * 1e3:.0f} mm "
           f"({ref.coupling}), {ref.seconds:.1f} s")
    _print(_table(["size_mm", "coupling", "model", "DOF", "FE_DOF", "f_err_max_%",
                   "f_err_mean_%", "C_err_max_%", "build_s", "solve_ms"],
                  [[f"{r.mesh_size * 1e3:.0f}", r.coupling, r.label, r.n_reduced, r.n_fe_dofs,
                    100 * r.freq_err_max, 100 * r.freq_err_mean, 100 * r.C_err_max,
                    r.build_seconds, 1e3 * r.solve_seconds] for r in res.rows],
                  floatfmt="{:.3g}"))
    _print(res.verdict)
    for f in res.files:
        _print(f"wrote {f}")
    return 0


def _add_show_arm(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML (default: built-in demo arm)")
    p.add_argument("--pose", default="P1", help="pose name or 'q1,...,qn' in degrees")
    p.add_argument("--model", default="cb", choices=["cb", "guyan", "emodel"])
    p.add_argument("--modes", type=int, default=None, help="CB modes per link (robot default)")
    p.add_argument("--coupling", default="rbe2", choices=["rbe2", "rbe3"])
    p.add_argument("--mesh-size", type=float, default=None, help="tet edge [m] (robot default)")
    p.add_argument("--mode", type=int, default=1, help="arm mode number (1-based)")
    p.add_argument("--amplitude", type=float, default=0.06,
                   help="largest drawn displacement / arm size")
    p.add_argument("--ellipsoid", action="store_true", help="draw the TCP compliance ellipsoid")
    p.add_argument("--interactive", action="store_true", help="open a window (needs a display)")
    p.add_argument("-o", "--output", default=None, help="picture .png or .gif")


@command("show-arm", "picture of the assembled arm deformed by a mode at a pose (PNG, GIF)",
         _add_show_arm)
def _run_show_arm(args) -> int:
    from .robot.description import pose_from_string
    from .studies.render_arm import arm_model, render_arm_mode

    if args.output is None and not args.interactive:
        args.output = f"arm_mode{args.mode}.png"
    robot = _robot_arg(args)
    q = pose_from_string(robot, args.pose)
    arm, builds = arm_model(robot, args.model, args.modes, args.coupling, args.mesh_size,
                            progress=lambda s: print(s, file=sys.stderr))  # noqa: T201
    out = render_arm_mode(robot, q, args.mode, args.output, args.model, args.ellipsoid,
                          args.pose, arm=arm, builds=builds, amplitude=args.amplitude,
                          interactive=args.interactive)
    if out is not None:
        _print(f"wrote {out}")
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
