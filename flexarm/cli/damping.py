"""Damping in the model: ``fit-damping`` (joint damping from measured modal damping) and
``check-damping`` (which joints miss damping)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ._common import command, out, wrote
from ._numbers import number


def _add_fit_damping(p: argparse.ArgumentParser) -> None:
    p.add_argument("modal", help="modal data with damping ratios (CSV or universal file, e.g. "
                                 "from 'flexarm ema')")
    p.add_argument("--robot", default=None,
                   help="robot TOML or URDF (default: the built-in IRB 4600-class demo arm)")
    p.add_argument("-o", "--output", required=True,
                   help="robot file (.toml) to write with the fitted joint damping; the "
                        "measured vs fitted plot goes next to it (<stem>.damping.png)")
    p.add_argument("--method", default="auto",
                   choices=["auto", "constant", "rayleigh", "joints", "modal"],
                   help="fit to write: one ratio for all joints, one Rayleigh law for all "
                        "joints, one ratio per joint; auto = lowest AICc; modal = the "
                        "identified ratios themselves, per pose, in a [modal_damping] table "
                        "(the FRF at those poses uses them)")
    _add_max_hz(p)


def _add_max_hz(p: argparse.ArgumentParser) -> None:
    p.add_argument("--max-hz", type=number("frequency", "Hz", 0, 1e5, open_low=True),
                   default=None,
                   help="leave out modes above this frequency [Hz], e.g. the upper edge of "
                        "the FRF band 'ema' identified them in (default: use every mode)")
    p.add_argument("--pose", default=None,
                   help="pose a universal file without flexarm's pose mark was measured at: "
                        "a named pose of the robot file or q1,...,q6 [deg]")


@command("fit-damping", "joint damping ratios (or a Rayleigh law) fitted to measured modal "
         "damping across poses, written into a robot file", _add_fit_damping)
def _run_fit_damping(args) -> int:
    from ..robot.formats import write as write_robot
    from ..validation.dynamic.damping_fit import fit_damping

    output = Path(args.output)
    if output.suffix.lower() != ".toml":
        raise ValueError(f"--output {output}: the robot file must be a .toml")
    if args.method == "modal":
        from ..validation.dynamic.pose_damping import store_modal_damping

        stored = store_modal_damping(args.modal, args.robot, max_hz=args.max_hz,
                                     pose=args.pose)
        out(stored.text())
        write_robot(output, stored.robot)
        wrote([output])
        return 0
    res = fit_damping(args.modal, args.robot, args.method, max_hz=args.max_hz, pose=args.pose)
    out(res.text())
    write_robot(output, res.robot)
    wrote([output, res.plot(output.with_name(output.stem + ".damping.png"))])
    return 0


def _add_check_damping(p: argparse.ArgumentParser) -> None:
    p.add_argument("modal", help="modal data with damping ratios (CSV or universal file)")
    p.add_argument("--robot", default=None,
                   help="robot TOML or URDF under test (default: the built-in demo arm)")
    p.add_argument("--sigma-pct", type=number("ratio", "%", 0, 100, open_low=True,
                                              open_high=True), default=5.0,
                   help="relative scatter of an identified damping ratio [%%]")
    p.add_argument("--alpha", type=number("ratio", "", 0, 1, open_low=True, open_high=True),
                   default=0.01,
                   help="chance of accepting a joint on damping-correct data (at most)")
    p.add_argument("--plot", type=Path, default=None, metavar="PNG",
                   help="also draw each mode's measured/model damping ratio against each "
                        "joint's energy share")
    _add_max_hz(p)


@command("check-damping", "which joints miss damping: measured ratios that rise in the "
         "modes one joint dominates, at every pose", _add_check_damping)
def _run_check_damping(args) -> int:
    from ..validation.dynamic.damping_check import diagnose_damping

    res = diagnose_damping(args.modal, args.robot, args.sigma_pct / 100, args.alpha,
                           max_hz=args.max_hz, pose=args.pose)
    out(res.text())
    if args.plot is not None:
        wrote([res.plot(args.plot)])
    return 0
