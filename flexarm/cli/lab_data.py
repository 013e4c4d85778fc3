"""Lab data as test rigs write it: ``ema`` (modal parameters from measured FRFs)."""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

from ._common import add_measured_pose_args, command, out, wrote
from ._numbers import band, count, number


def _add_ema(p: argparse.ArgumentParser) -> None:
    p.add_argument("frf", help="universal file with FRFs (58 datasets; .uff or .unv)")
    p.add_argument("-o", "--output", required=True,
                   help="modal data with shapes to write: CSV (.csv) or universal file (.uff)")
    p.add_argument("--band", type=band("frequency", "Hz", 0, 1e5), default=None,
                   help="frequency band of the fit [Hz], LO:HI (default: every measured line)")
    p.add_argument("--max-order", type=count(1, 200), default=40,
                   help="highest LSCF order (model orders 2 ... 2x this)")
    p.add_argument("--min-stable", type=number("ratio", "", 0, 1, open_low=True), default=0.25,
                   help="share of the orders at which a pole column must be stable [-]")
    p.add_argument("--robot", default=None, help="robot TOML or URDF whose named poses "
                   "--pose may use (default: the built-in demo arm)")
    add_measured_pose_args(p)


@command("ema", "modal parameters (frequency, damping, shapes) from measured FRFs: LSCF + "
         "LSFD, stabilisation diagram, synthesised vs measured FRF", _add_ema)
def _run_ema(args) -> int:
    from ..validation.dynamic.ema import run_ema

    lo, hi = args.band or (None, None)
    uff = None
    if args.pose is not None or args.response is not None:
        from ..validation.data.formats import UffOptions
        from ..validation.models import load

        uff = UffOptions.at(load(args.robot), args.pose, args.response)
    res = run_ema(args.frf, lo, hi, args.max_order, args.min_stable, uff)
    out(res.text())
    output = Path(args.output)
    wrote([res.write(output, comments=(f"flexarm ema {args.frf}",))])
    wrote(res.write_plots(output.parent / output.stem))
    points = Path(args.frf).with_suffix(".points.csv")  # the lab's points table goes along
    if points.exists() and output.suffix.lower() != ".uff":
        wrote([shutil.copyfile(points, output.with_suffix(".points.csv"))])
    return 0
