"""Lab data as test rigs write it: ``ema`` (modal parameters from measured FRFs)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ._common import add_measured_pose_args, command, out, wrote
from ._numbers import Reader, band, count, number


def _split(text: str, what: str | None = None):
    from ..validation.dynamic.ema_bands import parse_split

    return parse_split(text)


def _add_ema(p: argparse.ArgumentParser) -> None:
    p.add_argument("frf", help="universal file with FRFs (58 datasets; .uff or .unv)")
    p.add_argument("-o", "--output", required=True,
                   help="modal data with shapes to write: CSV (.csv) or universal file (.uff)")
    p.add_argument("--band", type=band("frequency", "Hz", 0, 1e5), default=None,
                   help="frequency band of the fit [Hz], LO:HI (default: every measured line)")
    p.add_argument("--max-order", type=count(1, 200), default=40,
                   help="highest LSCF order: modes one fit's denominator can hold")
    p.add_argument("--split", type=Reader(_split, "split"), default="auto",
                   help="sub-bands of a wide band, fitted apart and their poles merged: "
                        "auto (from the lines and the expected modes), a number, or none")
    p.add_argument("--coherence", default="weight", choices=["weight", "ignore"],
                   help="weight each FRF line by gamma^2/(1-gamma^2) of its coherence when "
                        "the file has one (default), or weight all lines alike")
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
    from ..validation.dynamic.ema_output import write_ema

    res = run_ema(args.frf, lo, hi, args.max_order, args.min_stable, uff, split=args.split,
                  weighted=args.coherence == "weight")
    out(res.text())
    output = Path(args.output)
    # the lab's points table goes along
    wrote(write_ema(output.parent, output.name, res, comments=(f"flexarm ema {args.frf}",),
                    points=Path(args.frf).with_suffix(".points.csv")))
    return 0
