"""The pictures of the README's "From a vibration lab" section, made by its commands.

Runs, in a temporary folder, the section's steps with a base compliance hidden in the
virtual lab (so that ``compare`` and ``diagnose`` have something to show):

    flexarm lab --poses P1,P2 --modal lab.uff --n-modes 6 --effect base:k=4e7 -o static.csv
    flexarm ema lab.uff -o modal.csv
    flexarm compare modal.csv -o mac
    flexarm diagnose static.csv --modal modal.csv --shape-noise 0.5 --report diag

and copies the pose-P1 pictures of each step into ``docs/images/lab_*.png``.

Run: ``python docs/lab_pictures.py`` (about a minute with the flexible model in the
superelement cache, minutes on the first run); ``--out DIR`` writes elsewhere.
"""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
from pathlib import Path

from flexarm.cli import main as flexarm

STEPS = (
    ["lab", "--poses", "P1,P2", "--modal", "lab.uff", "--n-modes", "6",
     "--effect", "base:k=4e7", "-o", "static.csv"],
    ["ema", "lab.uff", "-o", "modal.csv"],
    ["compare", "modal.csv", "-o", "mac"],
    ["diagnose", "static.csv", "--modal", "modal.csv", "--shape-noise", "0.5",
     "--report", "diag"],
)
#: Picture of a step -> its name in the README's image folder.
PICTURES = {
    "modal.stabilisation_P1.png": "lab_ema_stabilisation.png",
    "modal.frf_P1.png": "lab_ema_frf.png",
    "mac/mac_P1.png": "lab_compare_mac.png",
    "diag/history.png": "lab_diagnose_history.png",
}


def make_pictures(out: Path, steps=STEPS, pictures=None) -> list[Path]:
    """Run ``steps`` (flexarm command lines) in a temporary folder; copy ``pictures``
    (default :data:`PICTURES`) into ``out``."""
    out = out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    here = Path.cwd()
    written = []
    with tempfile.TemporaryDirectory() as tmp:
        os.chdir(tmp)
        try:
            for step in steps:
                if flexarm(step + ["-q"]) != 0:
                    raise SystemExit(f"flexarm {' '.join(step)} failed")
            for src, name in (PICTURES if pictures is None else pictures).items():
                written.append(Path(shutil.copyfile(src, out / name)))
        finally:
            os.chdir(here)
    return written


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "images")
    for path in make_pictures(parser.parse_args().out):
        print(f"wrote {path}")  # noqa: T201
