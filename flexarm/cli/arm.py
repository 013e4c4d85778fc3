"""The robot file and analyses of an arm at a pose: ``import-urdf``, ``seats``, ``modes``,
``compliance``, ``frf``, ``map``."""

from __future__ import annotations

import argparse
import dataclasses
import os
import warnings

from ._common import (
    add_robot_args,
    arm_at_pose,
    arm_from,
    command,
    out,
    wrote,
)
from ._numbers import count, number, or_word

#: Every arm analysis runs on the E-model, the flexible arm or the full-FE arm (solved
#: pose by pose: a map over thousands of poses is for the reduced models).
_MODELS = ("emodel", "cb", "guyan", "full")
_MAP_MODELS = ("emodel", "cb", "guyan")


# --- import-urdf -----------------------------------------------------------------------
def _add_import_urdf(p: argparse.ArgumentParser) -> None:
    p.add_argument("urdf", help="robot.urdf")
    p.add_argument("-o", "--output", required=True,
                   help="robot.toml to write (derived link meshes go to <stem>_meshes/ next "
                        "to it; published meshes are referenced by relative path)")
    p.add_argument("--meshes", default="collision", choices=["collision", "visual"],
                   help="which URDF geometry becomes the link CAD (STL, OBJ, PLY, DAE)")
    p.add_argument("--total-mass", type=number("mass", "kg", 0, 1e5, open_low=True),
                   default=None, metavar="KG",
                   help="the robot's datasheet mass: the link densities are scaled so it "
                        "weighs KG (solid CAD hulls of hollow castings are far too heavy)")
    p.add_argument("--wall", type=or_word("auto", number("length", "m", 0, 1, open_low=True)),
                   default=None, metavar="M|auto",
                   help="hollow every solid link hull to walls this thick [m] (8mm: with a "
                        "unit), or 'auto': "
                        "the wall that makes the robot weigh --total-mass (stiffer-to-truth "
                        "than scaling the density of a solid hull)")
    p.add_argument("--no-regions", action="store_true",
                   help="do not look for the bearing seats on the link CAD")
    p.add_argument("--seat", action="append", default=[],
                   metavar="LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w",
                   help="a bearing seat given by hand (repeatable): the cylinder about the "
                        "axis (ax,ay,az) through (cx,cy,cz), radii r_min..r_max, half width "
                        "w along the axis (metres, link frame); it replaces what the finder "
                        "would write, and the other link's seat is paired with it")


@command("import-urdf", "write a robot TOML from a URDF (origins, axes, limits, meshes, tool "
         "frame; placeholder joint stiffness)", _add_import_urdf)
def _run_import_urdf(args) -> int:
    from ..robot.formats import write
    from ..robot.seat_review import parse_seat
    from ..studies.import_urdf import derived_meshes_dir, import_urdf
    from ..studies.seat_check import build_problems

    wall = args.wall
    seats = [parse_seat(text) for text in args.seat]  # a bad one fails before any work
    imported = import_urdf(args.urdf, args.meshes, args.total_mass,
                           derived_dir=derived_meshes_dir(args.output), wall=wall,
                           regions=not args.no_regions, seats=seats)
    write(args.output, imported.robot)
    out(f"wrote {args.output}: {imported.summary()}")
    for line in imported.report(args.output):
        out(line)
    problems = () if args.no_regions else build_problems(imported.robot)
    if problems:  # the file stays, to be fixed; the exit code says it cannot be built yet
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise ValueError(f"{args.output} cannot be built: {problems[0]}{more}; give the "
                         f"seat with --seat LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w")
    return 0


# --- seats -----------------------------------------------------------------------------
def _add_seats(p: argparse.ArgumentParser) -> None:
    p.add_argument("robot", help="robot.toml whose bearing seats to edit")
    p.add_argument("-o", "--output", required=True, help="robot.toml to write (may be the same)")
    p.add_argument("--seat", action="append", default=[],
                   metavar="LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w",
                   help="a bearing seat given by hand (repeatable; metres, link frame): it "
                        "replaces the region of that name, review mark included")
    p.add_argument("--redetect", default=None, metavar="all|LINK[,LINK...]",
                   help="find the seats of these links again on their CAD (the hand-given "
                        "ones kept, the seat across each joint paired with them)")


@command("seats", "edit the bearing seats of a robot file: give seats by hand, find others "
         "again on the CAD", _add_seats)
def _run_seats(args) -> int:
    from ..robot.formats import read, write
    from ..robot.seat_review import parse_seat
    from ..studies.seat_check import build_problems
    from ..studies.seat_edit import edit_seats

    seats = [parse_seat(text) for text in args.seat]  # a bad one fails before any work
    redetect = [] if args.redetect is None else [
        n.strip() for n in args.redetect.split(",") if n.strip()]
    if not seats and not redetect:
        raise ValueError("nothing to do: give --seat LINK:JOINT=... or --redetect LINKS")
    edit = edit_seats(read(args.robot), seats, redetect)
    problems = build_problems(edit.robot)
    write(args.output, edit.robot)
    for line in edit.lines():
        out(line)
    out(f"wrote {args.output}")
    if problems:  # written, to be fixed; the exit code says it cannot be built yet
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise ValueError(f"{args.output} cannot be built: {problems[0]}{more}; give the "
                         f"seat with --seat LINK:JOINT=cx,cy,cz,ax,ay,az,r_min,r_max,w")
    return 0


# --- modes -----------------------------------------------------------------------------
def _add_modes(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MODELS)
    p.add_argument("-n", "--n-modes", type=count(1, 100_000), default=None,
                   help="modes to list (default 24, or all the model has)")
    p.add_argument("-o", "--output", default=None, help="folder for mode_energy.csv and .png")


@command("modes", "eigenfrequencies and joint energy shares of the arm at a pose", _add_modes)
def _run_modes(args) -> int:
    from ..assembly.analyses import modes
    from ..studies.plots import write_mode_energy

    arm, q = arm_at_pose(args)
    md = modes(arm.model, q)
    # only a count the user asked for is worth a warning: the default lists what there is
    if args.n_modes is not None and args.n_modes > md.freq_hz.size:
        warnings.warn(f"--n-modes {args.n_modes}: the {arm.spec.label} arm has only "
                      f"{md.freq_hz.size} modes; listing all {md.freq_hz.size}", stacklevel=1)
    out(md.text(arm.robot.joint_names, 24 if args.n_modes is None else args.n_modes))
    if args.output:
        wrote(write_mode_energy(args.output, md.freq_hz, md.energy, arm.robot.joint_names,
                                f"{arm.spec.label} strain energy per joint at {args.pose}"))
    return 0


# --- compliance ------------------------------------------------------------------------
def _add_compliance(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MODELS)
    p.add_argument("--force", type=number("force", "N", 0, 1e6, open_low=True), default=800.0,
                   help="load per direction [N] (0.8kN: with a unit)")
    p.add_argument("-o", "--output", default=None, help="folder for compliance.csv")


@command("compliance", "TCP compliance, full vs diagonal stiffness, identification (eq. 3.12)",
         _add_compliance)
def _run_compliance(args) -> int:
    from ..studies.compliance import compliance_report

    arm, q = arm_at_pose(args)
    rep = compliance_report(arm.model, q, args.force)
    out(rep.text())
    if args.output:
        wrote([rep.write_csv(os.path.join(args.output, "compliance.csv"))])
    return 0


# --- frf -------------------------------------------------------------------------------
def _add_frf(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MODELS)
    p.add_argument("--fmax", type=number("frequency", "Hz", 0, 1e5, open_low=True),
                   default=100.0, help="highest frequency [Hz]")
    p.add_argument("-o", "--output", default=None, help="folder for the Bode PNG and CSV")


@command("frf", "TCP receptance (Bode) per direction with modal damping", _add_frf)
def _run_frf(args) -> int:
    from ..studies.frf import frf_report

    arm, q = arm_at_pose(args)
    rep = frf_report(arm.model, q, args.fmax,
                     title=f"{arm.spec.label} TCP receptance at {args.pose}")
    out(rep.text())
    if args.output:
        wrote(rep.write(args.output))
    return 0


# --- map -------------------------------------------------------------------------------
def _grid_collisions(robot, m):
    """(na, nb) bool: the map's grid poses where links collide or touch the floor."""
    from ..assembly.maps import grid_poses
    from ..robot.collision import CollisionChecker

    return CollisionChecker(robot).colliding(grid_poses(m.q_fixed, m.joints, m.a, m.b))


def _add_map(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MAP_MODELS)
    p.add_argument("--n", type=count(2, 1000), default=60, help="grid points per joint")
    p.add_argument("--no-frequencies", action="store_true", help="skip the first eigenfrequency")
    p.add_argument("-o", "--output", default=None, help="folder for map.csv and the PNGs")


@command("map", "TCP stiffness Kxx, Kyy, Kzz and f1 over joints 2 and 3 (CSV, PNG; with a "
         "flexible model also its ratio to the E-model)", _add_map)
def _run_map(args) -> int:
    from ..assembly.maps import limits_map, plot_map, write_csv, write_ratio

    arm, q = arm_at_pose(args)
    m = limits_map(arm.model, q, arm.robot.lower, arm.robot.upper,
                   args.n, frequencies=not args.no_frequencies, label=arm.spec.label,
                   pose_name=args.pose)
    m = dataclasses.replace(m, collides=_grid_collisions(arm.robot, m))
    out(m.summary())
    if args.output:
        wrote([write_csv(os.path.join(args.output, "map.csv"), m)])
        wrote(plot_map(m, args.output))
        if args.model != "emodel":  # how much the flexible links soften the arm
            robot = arm.robot
            rigid = arm_from(args, robot, "emodel")
            wrote(write_ratio(m, limits_map(rigid.model, q, robot.lower, robot.upper, args.n,
                                            frequencies=False, label=rigid.spec.label,
                                            pose_name=args.pose), args.output))
    return 0
