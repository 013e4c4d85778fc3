"""Contact applications: ``circle`` (loaded circle test), ``chatter``, ``chatter-map``."""

from __future__ import annotations

import argparse
import dataclasses

from ._common import (
    add_robot_args,
    arm_at_pose,
    arm_spec_from,
    command,
    out,
    robot_from,
    say,
    wrote,
)
from ._numbers import count, effect, number, numbers

#: Angles in the cutting plane [deg]: any sign, up to a turn either way.
_PLANE_ANGLE = number("angle", "deg", -360, 360)

#: The circle test runs on the E-model or the flexible arm.
_MODELS = ("emodel", "cb", "guyan")


# --- circle ----------------------------------------------------------------------------
def _add_circle(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MODELS, pose=False)
    p.add_argument("--compare-models", action="store_true",
                   help="overlay the E-model and the flexible model (cb unless --model guyan)")
    p.add_argument("--effect", action="append", default=[], type=effect,
                   help="joint effect on top of the robot file's [nonlinear] table, e.g. "
                        "backlash:j3=0.2mrad (repeatable)")
    p.add_argument("-o", "--output", default=None, help="folder for PNG/CSV output")
    p.add_argument("--rapid", default=None, help="RAPID module (default: the thesis's appendix B)")
    p.add_argument("--proc", default="Path_30", help="procedure name")
    p.add_argument("--loads", type=numbers("force", "N", 0, 1e5), default="0,200,400,800",
                   help="bar forces [N], comma-separated")
    p.add_argument("--pull", action="store_true", help="the bar pulls (default: pushes)")
    p.add_argument("--pivot", type=numbers("length", "mm", -1e4, 1e4, n=3, result="m"),
                   default=None, help="bar pivot x,y,z [mm] (default: fitted)")
    p.add_argument("--tool", default="tool0", choices=["tool0", "robot"],
                   help="load point: flange (tool0, as programmed) or the robot's TCP")
    p.add_argument("--step", type=number("length", "mm", 0, 1000, open_low=True), default=2.0,
                   help="path sampling step [mm]")
    p.add_argument("--measured", default=None,
                   help="measured circle to overlay: path CSV or static-schema CSV")


@command("circle", "loaded circle test (LDBB): deviation, polar plot, Z along the path",
         _add_circle)
def _run_circle(args) -> int:
    from ..robot.effects import parse_effect
    from ..studies.contact import run_circle

    robot = robot_from(args)
    models = [args.model]
    if args.compare_models:
        models = ["emodel", "guyan" if args.model == "guyan" else "cb"]
    effects = []
    for text in args.effect:  # values were checked by the option's type; joints are now
        try:
            effects.append(parse_effect(text, robot.chain.n_joints))
        except ValueError as exc:  # "effect 'SPEC': ...", the option's name and value
            raise ValueError(f"--{exc}") from None
    res = run_circle(robot, effects, models, args.rapid, args.proc, args.loads, args.pull,
                     args.pivot, args.tool, args.step, args.measured, arm_spec_from(args),
                     progress=say)
    out(res.text())
    if args.output:
        wrote(res.write(args.output))
    return 0


# --- chatter ---------------------------------------------------------------------------
def _add_chatter(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MODELS + ("full",))
    p.add_argument("--kc", type=number("stiffness", "N/m", 0, 1e10), default=2e6,
                   help="process stiffness K_c*b [N/m] (5e5, 0.5N/um)")
    p.add_argument("--dir", type=_PLANE_ANGLE, default=30.0,
                   help="force angle from the normal [deg]")
    p.add_argument("--normal", type=_PLANE_ANGLE, default=None,
                   help="surface-normal angle from e1 in the plane [deg] (default: worst case)")
    p.add_argument("--cnc-stiffness", type=number("stiffness", "N/m", 0, 1e12, open_low=True),
                   default=5e7, help="CNC stiffness [N/m]")
    p.add_argument("--duration", type=number("time", "s", 0, 100, open_low=True), default=2.0,
                   help="simulated time [s]")
    p.add_argument("-o", "--output", default=None,
                   help="folder for chatter_time.csv and the PNGs")


@command("chatter", "mode-coupling chatter at a pose (2-DOF, closed form + simulation) vs a CNC",
         _add_chatter)
def _run_chatter(args) -> int:
    from ..studies.contact import run_chatter

    arm, q = arm_at_pose(args)
    st = run_chatter(arm.model, q, args.kc, args.dir, args.normal,
                     args.cnc_stiffness, args.duration)
    out(st.text())
    if args.output:
        wrote(st.write(args.output, f"{arm.spec.label} at {args.pose}"))
    return 0


# --- chatter-map -----------------------------------------------------------------------
def _add_chatter_map(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MODELS)
    p.add_argument("--dir", type=_PLANE_ANGLE, default=30.0,
                   help="force angle from the normal [deg]")
    p.add_argument("--normal", type=_PLANE_ANGLE, default=None,
                   help="surface-normal angle in the plane [deg] (default: worst case)")
    p.add_argument("--n", type=count(2, 200), default=25, help="grid points per joint")
    p.add_argument("-o", "--output", default=None, help="folder for the CSV and PNG")


@command("chatter-map", "limit K_c*b (mode coupling) over joints 2 and 3 (CSV, PNG)",
         _add_chatter_map)
def _run_chatter_map(args) -> int:
    from ..studies.contact import chatter_limits_map, write_chatter_map

    arm, q = arm_at_pose(args)
    cm = chatter_limits_map(arm.model, q, arm.robot.lower,
                            arm.robot.upper, args.n, args.dir, args.normal)
    from ..assembly.maps import grid_poses
    from ..robot.collision import CollisionChecker

    # a pose the robot cannot take is never recommended, like one at a joint limit
    hits = CollisionChecker(arm.robot).colliding(grid_poses(cm.q_fixed, (1, 2), cm.q2, cm.q3))
    if hits.any():
        out(f"{int(hits.sum())} of {hits.size} grid poses collide (links with each other or "
            "the floor): never recommended")
        excluded = hits if cm.is_excluded is None else cm.is_excluded | hits
        cm = dataclasses.replace(cm, is_excluded=excluded)
    out(cm.text())
    if args.output:
        wrote(write_chatter_map(args.output, cm, f"{arm.spec.label} at {args.pose}"))
    return 0
