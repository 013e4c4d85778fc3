"""Test planning: ``plan-test`` (series that separate standing hypotheses)."""

from __future__ import annotations

import argparse

from ._common import command, out, wrote
from ._numbers import count, effects, number
from .validation import LOADS, _add_validation_common, _options


def _add_plan(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", help="static measurement CSV (the data so far)")
    _add_validation_common(p)
    p.add_argument("--hypotheses", type=effects, required=True,
                   help="2 to 4 effects separated by ';', e.g. 'tilt:j1=5e7;stiffness:j2=1'")
    p.add_argument("--series", type=count(1, 100), default=6,
                   help="budget: series to plan (default 6)")
    p.add_argument("--loads", type=LOADS, default="0:800:100",
                   help="load levels [N] start:stop:step or a comma list")
    p.add_argument("--no-cycles", action="store_true", help="load only (default: load and "
                   "unload each series)")
    p.add_argument("--poses", type=count(1, 100_000), default=150,
                   help="candidate poses drawn in the joint limits (default 150)")
    p.add_argument("--seed", type=count(0, 2**32 - 1), default=0,
                   help="seed of the candidate poses")
    p.add_argument("--min-height", type=number("length", "m", -10, 10), default=0.3,
                   help="lowest TCP height above the base [m] of a candidate pose")
    p.add_argument("-o", "--output", required=True,
                   help="folder for plan.csv (template), plan.mod (RAPID), plan_expected.png")


@command("plan-test", "plan static series (poses, load directions) that separate 2-4 "
         "hypotheses by their expected ΔBIC; writes a CSV template and a RAPID module",
         _add_plan)
def _run_plan(args) -> int:
    from ..validation.planning.plan_test import plan_test

    plan = plan_test(args.robot, args.data, args.hypotheses, args.series, loads=args.loads,
                     cycles=not args.no_cycles, n_poses=args.poses, seed=args.seed,
                     min_height=args.min_height, options=_options(args))
    out(plan.text())
    wrote(plan.write(args.output, str(args.robot or "demo")))
    return 0
