"""Correcting a program: ``compensate`` (a deflection-compensated RAPID module, KRL pair or
CSV of poses, from a RAPID module or a CSV of poses) and ``history`` (the loop's error
history from its measured paths)."""

from __future__ import annotations

import argparse

from ._common import (
    add_krl_config_arg,
    add_robot_args,
    arm_spec_from,
    command,
    krl_config_from,
    out,
    robot_from,
    say,
    wrote,
)
from ._numbers import number, numbers

#: The compensation runs on the E-model or the flexible arm.
_MODELS = ("emodel", "cb", "guyan")


def _add_compensate(p: argparse.ArgumentParser) -> None:
    p.add_argument("program", help="RAPID module (.mod) to correct, or a CSV of poses "
                   "(x_mm,y_mm,z_mm[,qw,qx,qy,qz or rx_deg,ry_deg,rz_deg][,target]; the path "
                   "CSV lab --program writes is one): a MoveL through them")
    add_robot_args(p, _MODELS, pose=False)
    p.add_argument("--force", required=True,
                   help="process force: base:fx=..,fy=..,fz=.. (base frame), tool:fz=300 "
                        "(tool frame), ballbar:800N[,pull] (the circle test's bar), or a CSV "
                        "of per-target forces (target,fx_N,fy_N,fz_N[,mx_Nm,my_Nm,mz_Nm])")
    p.add_argument("-o", "--output", required=True,
                   help="compensated program to write: .mod (RAPID), .src (KUKA KRL, with "
                        "its .dat) or .csv (poses)")
    p.add_argument("--format", default=None, choices=["rapid", "krl", "csv"],
                   help="program format (default: from the suffix of -o)")
    p.add_argument("--orientation", type=numbers("ratio", "", -1.0, 1.0, n=4), default=None,
                   metavar="QW,QX,QY,QZ",
                   help="with a CSV of positions only: the tool orientation of every pose, "
                        "a unit quaternion in the base frame (0,0,1,0: tool0 pointing down)")
    p.add_argument("--ptp-speed", type=number("ratio", "%", 0, 100, open_low=True),
                   default=None, metavar="PCT",
                   help="KRL: $VEL_AXIS of the PTP moves [%%] (default 10 %%, said in a "
                        "comment: a RAPID MoveJ speed is the TCP's)")
    add_krl_config_arg(p)
    p.add_argument("--krl-template", default=None, metavar="DAT",
                   help="KRL .dat whose S and T are kept for targets whose joints are not "
                        "known (default S 2 T 0)")
    p.add_argument("--csv", default=None,
                   help="per-target deviation before/after (default: OUTPUT with .csv, "
                        "or OUTPUT_deviation.csv for a CSV program)")
    p.add_argument("--png", default=None,
                   help="top view and polar deviation (default: OUTPUT with .png)")
    p.add_argument("--proc", action="append", default=None,
                   help="procedure to compensate (repeatable; default: every procedure)")
    p.add_argument("--pivot", type=numbers("length", "mm", -1e4, 1e4, n=3, result="m"),
                   default=None,
                   help="ball-bar pivot x,y,z [mm] (default: fitted to the module's circles)")
    p.add_argument("--tool", default="program", choices=["program", "tool0", "robot"],
                   help="what the targets are read as: the instructions' tool (tool0 or a "
                        "tooldata of the module), the flange, or the robot file's TCP")
    p.add_argument("--no-gravity", action="store_true",
                   help="compensate the process load only (relative to the unloaded run), "
                        "not the gravity sag")
    p.add_argument("--split", type=number("length", "mm", 0, 1e5, open_low=True), default=None,
                   metavar="MM",
                   help="split MoveL/MoveC longer than MM into equal sub-motions through new "
                        "robtargets, so the path follows a deflection that changes along a "
                        "motion (default: keep the module's structure)")
    p.add_argument("--step", type=number("length", "mm", 0, 1000, open_low=True), default=2.0,
                   help="path sampling step [mm]")
    p.add_argument("--effect", action="append", default=[],
                   help="joint effect on top of the robot file's, e.g. backlash:j2=0.1mrad "
                        "(repeatable)")


@command("compensate", "shift a program's targets (a RAPID module or a CSV of poses) so "
         "the loaded tool lands on the programmed path", _add_compensate)
def _run_compensate(args) -> int:
    from ..robot.effects import parse_effect
    from ..robot.formats.krl import read_status_turn
    from ..studies.compensation import compensate
    from ..studies.compensation.program.program_out import output_files, program_format

    fmt = program_format(args.output, args.format)  # bad names fail before the work
    output_files(args.output, fmt, args.csv, args.png)
    for option, value in (("--krl-template", args.krl_template), ("--ptp-speed",
                                                                  args.ptp_speed)):
        if value is not None and fmt != "krl":
            raise ValueError(f"{option} goes with a KRL program (-o NAME.src), not {fmt}")
    template = None if args.krl_template is None else read_status_turn(args.krl_template)
    robot = robot_from(args)
    procs = None if args.proc is None else [n.strip() for p in args.proc for n in p.split(",")
                                            if n.strip()]
    res = compensate(args.program, robot, args.force, procs=procs, spec=arm_spec_from(args),
                     effects=[parse_effect(e, robot.chain.n_joints) for e in args.effect],
                     tool=None if args.tool == "program" else args.tool,
                     gravity=not args.no_gravity, pivot=args.pivot, step_mm=args.step,
                     split_mm=args.split, orientation=args.orientation,
                     krl_config=krl_config_from(args, args.program), progress=say)
    out(res.text())
    wrote(res.write(args.output, args.csv, args.png, fmt, template, args.ptp_speed))
    return 0


def _add_history(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="PATH.csv",
                   help="measured paths (step,x_mm,y_mm,z_mm,f_N, what lab --program writes), "
                        "one per step of the loop, in order (and per procedure)")
    p.add_argument("--program", required=True,
                   help="the original program (what the part needs), not a compensated one: "
                        "a RAPID module, a KRL .src or a CSV of poses")
    p.add_argument("--label", action="append", default=None,
                   help="step label of each path, in order (repeatable; default: the file "
                        "names); paths of several procedures with one label form one step")
    p.add_argument("--proc", default=None,
                   help="the procedure (default: the one each file names in a '# procedure:' "
                        "comment, as lab --program writes it, else the one nearest to its "
                        "readings)")
    p.add_argument("-o", "--output", required=True,
                   help="the picture (.png, .svg or .pdf): bars of the RMS and peak "
                        "deviation per step, and the polar deviation of each step")
    p.add_argument("--csv", default=None, help="the figures (default: OUTPUT with .csv)")
    add_krl_config_arg(p)


@command("history", "the compensation loop's error history: RMS and peak deviation of the "
         "measured path at each step (picture and CSV)", _add_history)
def _run_history(args) -> int:
    from pathlib import Path

    from ..studies.compensation.lab.history import PICTURE_SUFFIXES, path_history

    picture = Path(args.output)
    if picture.suffix.lower() not in PICTURE_SUFFIXES:
        raise ValueError(f"-o {picture.name}: the picture ends in "
                         f"{', '.join(PICTURE_SUFFIXES)}")
    res = path_history(args.paths, args.program, args.label, args.proc,
                       krl_config=krl_config_from(args, args.program))
    out(res.text())
    wrote(res.write(picture, args.csv))
    return 0
