"""Exports of the arm for other tools: ``export-arm`` (state space, OP4),
``export-exudyn`` (a flexible-multibody model), and two time-domain tests on that model:
``exudyn-impulse`` (a hammer test) and ``exudyn-circle`` (the loaded circle in motion)."""

from __future__ import annotations

import argparse

from ._common import (
    Progress,
    add_robot_args,
    arm_at_pose,
    arm_from,
    command,
    out,
    robot_from,
    say,
    wrote,
)
from ._numbers import count, number, numbers

#: A simulated time and its step [s].
_TIME = number("time", "s", 0, 100, open_low=True)
_STEP = number("time", "s", 0, 1, open_low=True)

_MODELS = ("emodel", "guyan", "cb", "full")


# --- export-arm ------------------------------------------------------------------------
def _add_export_arm(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, _MODELS)
    p.add_argument("--format", default=None, choices=["ss", "op4"],
                   help="ss = state-space A, B, C, D with modal data (.mat, .npz); op4 = "
                        "the reduced arm's K, M, damping, TCP map and every link "
                        "superelement as Nastran OP4 (default: from the extension)")
    p.add_argument("--n-modes", type=count(1, 100_000), default=None,
                   help="state space: keep the lowest N modes, the rest as static residual "
                        "in D (default: every mode of a reduced arm)")
    p.add_argument("-o", "--output", required=True, help="arm_P1.mat | .npz | .op4")


@command("export-arm", "the arm at a pose as a state-space model (.mat/.npz) or as Nastran "
         "OP4 matrices", _add_export_arm)
def _run_export_arm(args) -> int:
    from ..studies.export_arm import export_arm, export_format

    fmt = export_format(args.output, args.format, args.model)  # fails before the work
    arm, q = arm_at_pose(args)
    ex = export_arm(arm, q, args.output, fmt, args.n_modes)
    out(f"{arm.spec.label} arm at {args.pose}:")
    out(ex.text())
    wrote(ex.paths)
    return 0


# --- export-exudyn ---------------------------------------------------------------------
def _add_export_exudyn(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, ("emodel", "cb", "guyan"))
    p.add_argument("--no-gravity", action="store_true", help="leave gravity out of the model")
    p.add_argument("--no-check", action="store_true",
                   help="skip the check against flexarm (Exudyn's eigenfrequencies and "
                        "static TCP deflection under 800 N in Y, gravity off)")
    p.add_argument("--self-contained", action=argparse.BooleanOptionalAction, default=True,
                   help="write the script with the matrices and mode bases beside it "
                        "(<stem>.npz, one <stem>_<i>_<link>.npz per flexible link): it runs "
                        "with exudyn and numpy alone (default); --no-self-contained: a "
                        "script that imports flexarm and rebuilds the arm from the robot "
                        "file and the cache")
    p.add_argument("-o", "--output", required=True,
                   help="arm_exudyn.py: a script that builds the Exudyn mbs")


@command("export-exudyn", "the arm as an Exudyn flexible-multibody model (a script with its "
         "matrices, runs without flexarm), checked against flexarm's frequencies and "
         "compliance", _add_export_exudyn)
def _run_export_exudyn(args) -> int:
    from ..studies.exudyn.model import exudyn_check, ffrf_links, require_exudyn
    from ..studies.exudyn.script import write_exudyn_script
    from ..studies.exudyn.standalone import write_standalone

    if not str(args.output).endswith(".py"):
        raise ValueError(f"{args.output}: the Exudyn model is written as a Python script (.py)")
    if args.self_contained or not args.no_check:
        require_exudyn()  # before the links are built
    arm, q = arm_at_pose(args)
    links = None
    if args.self_contained or not args.no_check:
        links = ffrf_links(arm, say)  # shared by the check and the files
    if not args.no_check:
        with Progress("Exudyn model (gravity off): eigenvalues and static solve"):
            chk = exudyn_check(arm, q, links=links, progress=say)
        out(f"{arm.spec.label} arm at {args.pose}, Exudyn vs flexarm:")
        out(chk.text())
    gravity = None if args.no_gravity else (0.0, 0.0, -9.80665)
    if args.self_contained:
        wrote(write_standalone(args.output, arm, q, args.pose, gravity, links))
    else:
        wrote([write_exudyn_script(args.output, arm.robot.name, args.robot, arm.spec, q,
                                   args.pose, gravity)])
    return 0


# --- exudyn-impulse --------------------------------------------------------------------
def _add_exudyn_impulse(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, ("emodel", "cb", "guyan"))
    p.add_argument("--direction", type=numbers("ratio", "", -1e6, 1e6, n=3), default="1,1,1",
                   help="pulse direction x,y,z (base frame)")
    p.add_argument("--duration", type=_TIME, default=3.0, help="simulated time [s]")
    p.add_argument("--dt", type=_STEP, default=5e-4, help="time step [s] (0.5ms: with a unit)")
    p.add_argument("-n", "--n-modes", type=count(1, 100), default=3, help="modes to compare")
    p.add_argument("-o", "--output", default=None, help="folder for impulse.png")


@command("exudyn-impulse", "a TCP hammer test on the arm's Exudyn model (gravity off): FFT "
         "peaks and log-decrement damping against flexarm's modes, U/F against the FRF",
         _add_exudyn_impulse)
def _run_exudyn_impulse(args) -> int:
    from ..studies.exudyn.impulse import impulse_test
    from ..studies.exudyn.model import require_exudyn

    direction = args.direction
    if not any(direction):
        raise ValueError(f"--direction {','.join(f'{v:g}' for v in direction)}: all zero, "
                         "no direction")
    if not args.dt < args.duration:
        raise ValueError(f"--dt and --duration must satisfy 0 < dt < duration [s], got "
                         f"{args.dt:g} and {args.duration:g}")
    require_exudyn()
    arm, q = arm_at_pose(args)
    with Progress(f"Exudyn: {args.duration:g} s after a TCP pulse, step {args.dt:g} s"):
        res = impulse_test(arm, q, direction, args.n_modes, args.duration, args.dt,
                           progress=say)
    out(f"{arm.spec.label} arm at {args.pose}, TCP impulse along "
        f"{','.join(f'{v:g}' for v in direction)}:")
    out(res.text())
    if args.output:
        wrote(res.write(args.output))
    return 0


# --- exudyn-circle ---------------------------------------------------------------------
def _add_exudyn_circle(p: argparse.ArgumentParser) -> None:
    add_robot_args(p, ("emodel", "cb", "guyan"), pose=False)
    p.add_argument("--rapid", default=None, help="RAPID module (default: the thesis's appendix B)")
    p.add_argument("--proc", default="Path_30", help="procedure name")
    p.add_argument("--force", type=number("force", "N", 0, 1e5), default=200.0,
                   help="bar force [N]")
    p.add_argument("--pull", action="store_true", help="the bar pulls (default: pushes)")
    p.add_argument("--speed", type=number("speed", "mm/s", 0, 1e4, open_low=True), default=None,
                   help="TCP speed [mm/s] (default: the program's vNNN)")
    p.add_argument("--dt", type=_STEP, default=2e-3, help="time step [s]")
    p.add_argument("-o", "--output", default=None, help="folder for path_<proc>.png")


@command("exudyn-circle", "the loaded circle in time on the arm's Exudyn model (joints "
         "driven through their gear springs, gravity on) against the quasi-static circle",
         _add_exudyn_circle)
def _run_exudyn_circle(args) -> int:
    from ..studies.exudyn.model import require_exudyn
    from ..studies.exudyn.path import exudyn_circle

    require_exudyn()
    arm = arm_from(args, robot_from(args))
    speed = None if args.speed is None else args.speed * 1e-3
    with Progress(f"Exudyn: {args.proc}, with and without the bar force"):
        res = exudyn_circle(arm, args.rapid, args.proc, args.force, args.pull, speed,
                            dt=args.dt, progress=say)
    out(f"{arm.spec.label} arm:")
    out(res.text())
    if args.output:
        wrote(res.write(args.output))
    return 0
