"""The main job: ``demo``."""

from __future__ import annotations

import argparse

from ._common import command, out, say
from ._numbers import count


def _add_demo(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", default="flexarm-demo", help="output folder")
    p.add_argument("--part", action="store_true",
                   help="also run the single-part pipeline (full FE modes of one cast link)")
    p.add_argument("-j", "--jobs", type=count(1, 64), default=2,
                   help="processes (default 2: on a first run the accuracy study's full-FE "
                        "references and the E-model run beside the other steps; 1: every step "
                        "in order, in this process)")


@command("demo", "the main job on the built-in robot: tables and pictures in flexarm-demo/",
         _add_demo)
def _run_demo(args) -> int:
    from ..studies.demo import run_demo

    result = run_demo(args.output, progress=say, part=args.part, jobs=args.jobs)
    for key, value in result.figures.items():
        out(f"{key:>28s}  {value:.6g}")
    out(f"demo finished in {result.seconds:.1f} s: open {result.folder / 'index.md'}")
    return 0
