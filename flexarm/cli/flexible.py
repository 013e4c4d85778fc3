"""The flexible arm: ``build``, ``compare-models``, ``study``, ``show-arm``, ``show-regions``."""

from __future__ import annotations

import argparse
from pathlib import Path

from ._common import (
    DISPLACEMENT,
    MESH_SIZE,
    add_flexible_args,
    add_robot_args,
    arm_at_pose,
    command,
    names,
    out,
    pose_from,
    robot_from,
    say,
    wrote,
)
from ._numbers import count, counts, number, numbers


# --- build -----------------------------------------------------------------------------
def _add_build(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML or URDF (default: built-in demo arm)")
    p.add_argument("--method", default="cb", choices=["cb", "guyan"], help="reduction")
    add_flexible_args(p)
    p.add_argument("-j", "--jobs", type=count(1, 256), default=None,
                   help="processes meshing the links side by side (default: one per core; "
                        "1: every link in this process, in order)")
    p.add_argument("--pin", default=None, metavar="OUT.toml",
                   help="also write OUT.toml, the robot file naming the elements of this "
                        "build (in OUT_tets/, .vtu): built in any cache, it gives this model")


@command("build", "mesh and reduce every link of a robot (cached superelements); a table "
         "of the mesher, elements and time per link", _add_build)
def _run_build(args) -> int:
    from ..assembly.build import BuildOptions, robot_build

    if args.pin is not None and Path(args.pin).suffix.lower() != ".toml":
        raise ValueError(f"--pin: {args.pin}: the pinned robot file must be a .toml")
    robot = robot_from(args)
    opts = BuildOptions(args.method, args.modes, args.coupling, args.mesh_size)
    out(robot_build(robot, opts, progress=say, jobs=args.jobs).text())
    _check_pairs(robot, args.mesh_size)
    if args.pin is not None:
        from ..assembly.pin_meshes import pin_meshes

        out("")
        out(pin_meshes(robot, args.pin, args.mesh_size, progress=say).text())
    return 0


def _check_pairs(robot, mesh_size) -> None:
    """The seat pairs on the meshes just built (a table), and one warning per region to
    review and per pair whose seats do not face each other."""
    import warnings

    from ..studies.show_regions import show_regions

    meshed = [lk.name for i, lk in enumerate(robot.links)  # a rigid base is not meshed
              if lk.mesh is not None and (i > 0 or "base" in lk.regions)]
    res = show_regions(robot, mesh_size=mesh_size, links=meshed)
    if not res.pairs:
        return
    out("")
    out(res.text().split("\n\n", 1)[-1])
    for row in res.rows:
        if row.status.startswith("review"):
            warnings.warn(f"links.{row.link}.regions.{row.region}: marked review = true (a "
                          "suggestion where no seat was found): confirm or replace it",
                          stacklevel=1)
    for row in res.pairs:
        if not row.ok:
            warnings.warn(f"{row.pair.joint}: its seats on {row.pair.parent} and "
                          f"{row.pair.child} do not pair up: {row.status}", stacklevel=1)


# --- compare-models --------------------------------------------------------------------
def _add_compare_models(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML or URDF (default: built-in demo arm)")
    p.add_argument("--poses", default=None,
                   help="pose names, comma-separated (P1,P2,P3), or poses in degrees "
                        "separated by ';' (\"0,52,-19,12,-15,-11;home\") (default: P1,P2,P3, "
                        "else the robot's named poses)")
    add_flexible_args(p)
    p.add_argument("--no-full-fe", action="store_true", help="skip the full-FE reference")
    p.add_argument("-o", "--output", default="flexarm-compare", help="folder for CSV and PNG")


@command("compare-models", "E-model vs Guyan vs CB vs CB+wrist vs full FE at poses (CSV, PNG)",
         _add_compare_models)
def _run_compare_models(args) -> int:
    from ..robot import pose_from_string
    from ..studies.compare_models import compare_models

    robot = robot_from(args)
    if args.poses is None:  # an imported robot has no P1..P3
        poses = ([p for p in ("P1", "P2", "P3") if p in robot.poses] or list(robot.poses)
                 or [",".join("0" * len(robot.joints))])
    elif ";" in args.poses:
        poses = [t.strip() for t in args.poses.split(";") if t.strip()]
    else:
        poses = names(args.poses)
    for pose in poses:  # a bad pose fails before any link is meshed
        try:
            pose_from_string(robot, pose)
        except ValueError as exc:
            raise ValueError(f"--poses: {exc}") from None
    rep = compare_models(robot, poses, args.modes, args.coupling,
                         args.mesh_size, full_fe=not args.no_full_fe, out_dir=args.output,
                         progress=say)
    out(rep.text())
    wrote(rep.files)
    return 0


# --- study -----------------------------------------------------------------------------
def _add_study(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML or URDF (default: built-in demo arm)")
    p.add_argument("--pose", default=None, help="pose name or 'q1,...,qn' in degrees (default: "
                   "P1, else the robot's first named pose, else zeros)")
    p.add_argument("--preset", default="full", choices=["small", "full"],
                   help="named sweep (explicit --sizes/--modes/--couplings override it)")
    p.add_argument("--sizes", type=numbers("length", "m", 0, 2, open_low=True), default=None,
                   help="tet edges [m], e.g. 0.06,0.045,0.03 (default 1.5x and 1x the robot's)")
    p.add_argument("--modes", type=counts(0, 500), default=None,
                   help="CB modes per link, 0 = Guyan (0,5,10,20)")
    p.add_argument("--couplings", default=None, help="rbe2,rbe3,k<N> (rbe2,rbe3,k4,k8)")
    p.add_argument("--reference-coupling", default="rbe2", choices=["rbe2", "rbe3"])
    p.add_argument("--tet10", action="store_true",
                   help="also solve the full FE with Tet10 elements on the finest mesh: a lower "
                   "bound of the Tet4 mesh error (about 6x the reference's DOF)")
    p.add_argument("-o", "--output", default="flexarm-study", help="folder for CSV and PNGs")


@command("study", "accuracy of the whole arm vs node count, CB modes and interface "
         "representation against full FE (CSV, PNGs, verdict)", _add_study)
def _run_study(args) -> int:
    from ..studies.arm_study import run_study

    robot = robot_from(args)
    pose_from(robot, args)  # the default pose, and a bad one fails before any meshing
    res = run_study(robot, args.pose,
                    sizes=args.sizes, modes=args.modes,
                    couplings=names(args.couplings) if args.couplings else None,
                    out_dir=args.output, progress=say, preset=args.preset,
                    reference_coupling=args.reference_coupling, tet10=args.tet10)
    out(res.text())
    wrote(res.files)
    return 0


# --- show-arm --------------------------------------------------------------------------
def _add_show_arm(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, ("emodel", "cb", "guyan"))
    p.add_argument("--mode", type=count(1), default=1, help="arm mode number (1-based)")
    p.add_argument("--amplitude", type=number("ratio", "", 0, 1, open_low=True), default=0.06,
                   help="largest drawn displacement / arm size")
    p.add_argument("--max-displacement", type=DISPLACEMENT, default=None, metavar="M",
                   help=".vtu/.vtk: scale the shape to this largest displacement [m] "
                        "(default: mass-normalised); stated in the file's field data")
    p.add_argument("--ellipsoid", action="store_true", help="draw the TCP compliance ellipsoid")
    p.add_argument("--interactive", action="store_true", help="open a window (needs a display)")
    p.add_argument("-o", "--output", default=None,
                   help="picture .png or .gif, or the mode shape on the links' surfaces as "
                   ".vtu/.vtk for ParaView (point data mode_shape) (default: arm_mode<N>.png)")


@command("show-arm", "picture of the assembled arm deformed by a mode at a pose (PNG, GIF; "
         "VTU/VTK mesh)", _add_show_arm)
def _run_show_arm(args) -> int:
    from ..reduction.render import MODE_EXTENSIONS
    from ..studies.render_arm import render_arm_mode, write_arm_mode

    if args.output is None and not args.interactive:
        args.output = f"arm_mode{args.mode}.png"
    is_mesh = args.output is not None and Path(args.output).suffix.lower() in MODE_EXTENSIONS
    if is_mesh and (args.ellipsoid or args.interactive):
        raise ValueError("--ellipsoid and --interactive draw pictures; a .vtu/.vtk output "
                         "holds the mode shape only")
    arm, q = arm_at_pose(args)
    if is_mesh:
        path = write_arm_mode(arm, q, args.mode, args.output, args.pose, args.max_displacement)
        out(f"wrote {path}")
        return 0
    path = render_arm_mode(arm, q, args.mode, args.output,
                           args.ellipsoid, args.pose, amplitude=args.amplitude,
                           interactive=args.interactive)
    if path is not None:
        out(f"wrote {path}")
    return 0


# --- show-regions ----------------------------------------------------------------------
def _add_show_regions(p: argparse.ArgumentParser) -> None:
    p.add_argument("--robot", default=None, help="robot TOML or URDF (default: built-in demo arm)")
    p.add_argument("--mesh-size", type=MESH_SIZE, default=None,
                   help="tet edge of the link meshes [m] (default: the robot's)")
    p.add_argument("--links", default=None, help="comma-separated link names (default: all)")
    p.add_argument("-o", "--output", default=None,
                   help="folder for regions_<link>.png and regions.csv (default: table only)")


@command("show-regions", "each link's interface regions on its tet mesh: FE nodes, area, "
         "offsets from the joint axis (table; PNG per link and CSV with -o)", _add_show_regions)
def _run_show_regions(args) -> int:
    from ..studies.show_regions import show_regions

    res = show_regions(robot_from(args), args.output, args.mesh_size, progress=say,
                       links=names(args.links) if args.links else None)
    out(res.text())
    wrote(res.files)
    return 0 if res.ok else 1
