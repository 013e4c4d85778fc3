"""Commands on one part: ``mesh``, ``modal``, ``reduce``, ``show``, ``study-part``."""

from __future__ import annotations

import argparse
import os

from ._common import DISPLACEMENT, Progress, command, names, out, say, set_quiet, wrote
from ._numbers import count, counts, number

_MATERIAL_HELP = "steel | cast_iron | aluminium | nafems | 'E,nu,rho' in SI units"
#: The names of ``flexarm.reduction.formats.registry`` (a test holds them equal): the
#: registry itself loads h5py and SciPy, too slow for building the parser.
_SE_FORMATS = ("h5", "npz", "mtx", "dmig", "op4")


# --- mesh ------------------------------------------------------------------------------
def _add_mesh(p: argparse.ArgumentParser) -> None:
    p.add_argument("surface", help="CAD surface: STL, OBJ or PLY")
    p.add_argument("--units", default="m", help="length unit of the CAD file: m, mm, cm, in")
    p.add_argument("--size", type=number("length", "m", 0, 10, open_low=True), required=True,
                   help="target edge length [m], e.g. 0.01 or 10mm")
    p.add_argument("--order", type=int, choices=(1, 2), default=1, help="1 = Tet4, 2 = Tet10")
    p.add_argument("--no-optimize", action="store_true", help="skip fTetWild optimisation")
    p.add_argument("--no-cache", action="store_true", help="ignore the tetrahedralisation cache")
    p.add_argument("--mesher", choices=("tetwild", "gmsh"), default="tetwild",
                   help="tetwild (robust on dirty CAD) or gmsh (deterministic; pip install gmsh)")
    p.add_argument("-o", "--output", required=True, help="volume mesh: .vtu, .msh, .npz")


@command("mesh", "tetrahedralise a CAD surface (pytetwild) and report mesh quality", _add_mesh)
def _run_mesh(args) -> int:
    from ..meshes import mesh_part, write_volume_mesh

    with Progress(f"meshing {args.surface} (edge {args.size * 1e3:g} mm, "
                  f"Tet{4 if args.order == 1 else 10})") as pr:
        mesh, quality = mesh_part(
            args.surface, units=args.units, size=args.size, order=args.order,
            optimize=not args.no_optimize, cache=not args.no_cache, progress=pr.note,
            mesher=args.mesher,
        )
    write_volume_mesh(args.output, mesh)
    out(quality.table())
    out(f"wrote {args.output}")
    return 0


# --- modal -----------------------------------------------------------------------------
def _add_modal(p: argparse.ArgumentParser) -> None:
    p.add_argument("mesh", help="volume mesh: .vtu, .msh, .npz")
    p.add_argument("--material", default="steel", help=_MATERIAL_HELP)
    p.add_argument("--fix", default=None,
                   help="clamped nodes, e.g. 'x=min', 'z<0.01', a node-set name; "
                        "omit for a free part")
    p.add_argument("-n", "--modes", type=count(1, 100_000), default=10,
                   help="number of modes (elastic), at most what the part's DOF allow")
    p.add_argument("--backend", default=None, help="sparse solver: pardiso | cholmod | splu")
    p.add_argument("--csv", default=None, help="also write the table to this CSV file")


@command("modal", "natural frequencies of one part (free or clamped)", _add_modal)
def _run_modal(args) -> int:
    from ..fe import material_from_string, select_nodes
    from ..meshes import read_volume_mesh
    from ..studies.part_modes import mode_limit, part_modes

    material = material_from_string(args.material)
    mesh = read_volume_mesh(args.mesh).check(args.mesh)
    if args.fix:
        try:  # a bad selection is an error of this argument, named as such
            fixed = select_nodes(mesh, args.fix)
        except ValueError as exc:
            raise ValueError(f"{args.mesh}: --fix {exc}") from None
        _check_clamp(args.mesh, args.fix, mesh.points[fixed])
    n_free = mesh.n_dofs - 3 * (len(set(fixed.tolist())) if args.fix else 0)
    if args.modes > mode_limit(n_free, not args.fix):  # else a dense solve of every mode
        raise ValueError(f"-n/--modes {args.modes}: {args.mesh} has {n_free} free DOF, at "
                         f"most {mode_limit(n_free, not args.fix)} elastic modes")
    with Progress(f"modes of {mesh.n_tets} Tet{4 if mesh.order == 1 else 10} "
                  f"({mesh.n_dofs} DOF)") as pr:
        res = part_modes(mesh, material, args.modes, args.fix, args.backend, progress=pr.note)
    out(f"{args.mesh}: {mesh.n_tets} tets, {mesh.n_dofs} DOF, material {material.name} "
        f"(E {material.E:.4g} Pa, nu {material.nu:g}, rho {material.rho:g} kg/m^3)")
    out(f"support: {res.support()}" + (f"; mass {res.mass:.6g} kg" if res.is_free else ""))
    if res.is_free:
        out(f"rigid-body modes: {res.n_rigid} (a free part has 6)")
    out(res.text())
    if args.csv:
        res.write_csv(args.csv)
    return 0


def _check_clamp(path, fix: str, points) -> None:
    """Clamped nodes must hold the part against rotation too: at least three, not on one
    line (else the stiffness is singular); says how many nodes the selection found."""
    import numpy as np

    n = len(points)
    say(f"--fix '{fix}': {n} node{'s' if n != 1 else ''} clamped")
    centred = np.asarray(points, dtype=float) - np.mean(points, axis=0)
    s = np.linalg.svd(centred, compute_uv=False) if n > 1 else np.zeros(1)
    if n < 3 or s[1] <= 1e-9 * max(s[0], 1e-300):
        raise ValueError(f"{path}: --fix '{fix}' clamps {n} node{'s' if n != 1 else ''}"
                         f"{' on one line' if n >= 3 else ''}: the part can still rotate "
                         "(singular stiffness); select a face region, e.g. 'x<0.01'")


# --- reduce ----------------------------------------------------------------------------
def _add_reduce(p: argparse.ArgumentParser) -> None:
    p.add_argument("mesh", help="volume mesh of one link: .vtu, .msh, .npz (link frame, m)")
    p.add_argument("--interface", action="append", default=[], metavar="NAME:cx,cy,cz,ax,ay,az,r,w",
                   help="cylinder region [m]: centre, axis, outer radius r, half-width w "
                        "(or ...,r_min,r_max,w); repeat per interface, in DOF order")
    p.add_argument("--node-set", action="append", default=[], metavar="NAME",
                   help="a node set of the mesh as an interface (after the cylinders)")
    p.add_argument("--coupling", default="rbe2", choices=["rbe2", "rbe3", "nodes"],
                   help="rbe2 = rigid spider, rbe3 = weighted average, nodes = keep region nodes")
    p.add_argument("--masters", type=count(1), default=None,
                   help="with --coupling nodes: region nodes kept per interface (default all)")
    p.add_argument("--method", default="cb", choices=["guyan", "cb"])
    p.add_argument("--modes", type=count(0, 10_000), default=20,
                   help="fixed-interface modes (cb)")
    p.add_argument("--diagonal", action="store_true",
                   help="modal block exactly M = I, K = diag(omega^2)")
    p.add_argument("--material", default="steel", help=_MATERIAL_HELP)
    p.add_argument("--volume-nodes", action="store_true",
                   help="regions may hold interior nodes (default: surface nodes only)")
    p.add_argument("--backend", default=None,
                   help="sparse solver: pardiso | cholmod | splu, or petsc to reduce across "
                        "the ranks of mpiexec -n N (PETSc/MUMPS + SLEPc)")
    p.add_argument("--precision", default=None, choices=["double", "single"],
                   help="precision of the sparse factor: single halves its memory, every "
                        "solve refined to double accuracy (default: double when it fits, "
                        "else single)")
    p.add_argument("-o", "--output", required=True, help="superelement file (.h5 default)")
    p.add_argument("--format", default=None, choices=_SE_FORMATS,
                   help="file format (default: from the extension)")


@command("reduce", "reduce a meshed link to a superelement (RBE2/RBE3, Guyan/Craig-Bampton)",
         _add_reduce)
def _run_reduce(args) -> int:
    from ..fe import material_from_string
    from ..meshes import read_volume_mesh
    from ..reduction import NodeSetRegion, formats, parse_cylinder, reduce_with_stats
    from ..reduction.report import reduction_text

    regions = [parse_cylinder(t) for t in args.interface]
    regions += [NodeSetRegion(n) for n in args.node_set]
    if not regions:
        raise ValueError("give at least one --interface NAME:cx,cy,cz,ax,ay,az,r,w or --node-set")
    material = material_from_string(args.material)
    formats.format_of(args.output, args.format)  # a bad extension fails before the work
    if args.backend == "petsc":  # one report, from MPI rank 0
        from ..fe.petsc_assembly import world

        set_quiet(world().Get_rank() != 0)
    mesh = read_volume_mesh(args.mesh).check(args.mesh)
    with Progress(f"reducing {mesh.n_dofs} DOF ({args.coupling}, {args.method})"):
        se, st = reduce_with_stats(
            mesh, material, regions, args.coupling, args.method, args.modes,
            n_masters=args.masters, diagonal=args.diagonal,
            surface_only=not args.volume_nodes, backend=args.backend,
            precision=args.precision)
    if se is None:  # another MPI rank: rank 0 writes the superelement
        return 0
    formats.write(args.output, se, args.format)
    out(f"{args.mesh}: {mesh.n_tets} Tet{4 if mesh.order == 1 else 10}, material "
        f"{material.name}, mass {se.mass:.6g} kg, COM {se.center_of_mass.round(6)} m")
    out(reduction_text(se, st))
    if st.precision == "single":
        out("factor in single precision, solves refined to double accuracy")
    out(f"wrote {args.output}")
    return 0


# --- show ------------------------------------------------------------------------------
def _add_show(p: argparse.ArgumentParser) -> None:
    p.add_argument("superelement", help="superelement file (.h5 or .npz for pictures)")
    p.add_argument("--mode", type=count(1), default=None, help="mode number to draw (1-based)")
    p.add_argument("--boundary", default=None, choices=["fixed", "free"],
                   help="fixed-interface (default when available) or free-free modes")
    p.add_argument("-o", "--output", default=None,
                   help="picture .png or .gif (animation), or the mode shape as .vtu/.vtk "
                        "for ParaView")
    p.add_argument("--frames", type=count(2, 200), default=24, help="GIF frames per period")
    p.add_argument("--max-displacement", type=DISPLACEMENT, default=None, metavar="M",
                   help=".vtu/.vtk: scale the shape to this largest displacement [m] "
                        "(default: mass-normalised); stated in the file's field data")
    p.add_argument("--interactive", action="store_true", help="open a window (needs a display)")


@command("show", "summarise a superelement and draw its mode shapes (PNG, GIF, window)",
         _add_show)
def _run_show(args) -> int:
    from ..reduction import formats
    from ..reduction.report import superelement_text

    se = formats.read(args.superelement)
    out(superelement_text(se, args.superelement))
    if args.mode is None:
        if args.output or args.interactive:
            raise ValueError("--mode N is needed to draw a picture")
        return 0
    from ..reduction.render import MODE_EXTENSIONS, render_mode, write_mode

    if args.output and os.path.splitext(args.output)[1].lower() in MODE_EXTENSIONS:
        out(f"wrote {write_mode(se, args.mode, args.output, args.boundary, args.max_displacement)}")
        if not args.interactive:
            return 0
        args.output = None
    path = render_mode(se, args.mode, args.output, args.boundary, n_frames=args.frames,
                       interactive=args.interactive)
    if path is not None:
        out(f"wrote {path}")
    return 0


# --- convert ---------------------------------------------------------------------------
def _add_convert(p: argparse.ArgumentParser) -> None:
    p.add_argument("superelement", help="superelement file or Matrix Market folder")
    p.add_argument("-o", "--output", required=True,
                   help="superelement to write: .h5, .npz, .mtx (folder), .bdf/.dmig/.pch, "
                        ".op4 (matrices only)")
    p.add_argument("--format", default=None, choices=_SE_FORMATS,
                   help="format of the output (default: from its extension)")


@command("convert", "rewrite a superelement in another format (no new reduction)",
         _add_convert)
def _run_convert(args) -> int:
    from ..reduction import formats

    out(f"wrote {formats.convert(args.superelement, args.output, args.format)}")
    return 0


# --- study-part ------------------------------------------------------------------------
def _add_study_part(p: argparse.ArgumentParser) -> None:
    p.add_argument("--mesh", default=None,
                   help="volume mesh to study (default: built-in steel bars along x)")
    p.add_argument("--interface", action="append", default=[],
                   metavar="NAME:cx,cy,cz,ax,ay,az,r,w",
                   help="two regions with --mesh; the first one is clamped")
    p.add_argument("--divisions", default="12x2x2,24x3x3",
                   help="built-in bar meshes (cells along x, y, z), comma-separated")
    p.add_argument("--modes", type=counts(0, 1000), default="0,5,10,20,40",
                   help="CB mode counts (0 = Guyan)")
    p.add_argument("--representations", default="rbe2,rbe3,k4,k8,k16,all",
                   help="interface representations: rbe2, rbe3, k4, k8, k16, all")
    p.add_argument("--material", default="steel")
    p.add_argument("-o", "--output", default="study-part", help="output folder")


def _divisions(text: str) -> list[tuple[int, int, int]]:
    from ..fe.quantities import parse_count

    out_ = []
    for d in names(text):
        cells = d.lower().split("x")
        if len(cells) != 3:
            raise ValueError(f"--divisions entries must look like 12x2x2, got '{d}'")
        out_.append(tuple(parse_count(v, f"--divisions {d}: cells", 1, 1000) for v in cells))
    return out_


@command("study-part", "accuracy of reduced links vs the full FE model (CSV and log-log PNG)",
         _add_study_part)
def _run_study_part(args) -> int:
    from ..fe import material_from_string
    from ..studies.part_study import run_part_study

    material = material_from_string(args.material)
    n_modes = args.modes
    reps = names(args.representations)
    mesh = None
    if args.mesh:
        from ..meshes import read_volume_mesh
        from ..reduction import parse_cylinder

        if len(args.interface) != 2:
            raise ValueError("with --mesh give exactly two --interface regions")
        mesh = (os.path.basename(args.mesh), read_volume_mesh(args.mesh).check(args.mesh),
                [parse_cylinder(t) for t in args.interface])
    divisions = [] if mesh else _divisions(args.divisions)
    with Progress(f"study: {max(1, len(divisions))} meshes x {len(reps)} representations x "
                  f"{len(n_modes)} mode counts"):
        res = run_part_study(material, reps, n_modes, divisions, mesh, args.output)
    out(res.text())
    wrote(res.files)
    return 0
