"""The pictures of the vibration-lab guide's IRB 4600 section, made by its commands.

Imports the ABB IRB 4600 from its published URDF (``../shared/data/irb4600``), hides a
20 kg mass on link 3 (a cable package) in the virtual lab, and runs the chain a lab would:

    flexarm import-urdf irb4600_60_205.urdf --total-mass 425 -o irb.toml
    flexarm lab --robot irb.toml --poses "P1;P2;P3" --modal lab.uff --n-modes 4 \\
        --effect mass:l3=20kg -o static.csv
    flexarm ema lab.uff -o modal.csv
    flexarm check-damping modal.csv --robot irb.toml --plot damping.png
    flexarm diagnose static.csv --robot irb.toml --modal modal.csv --report diag

and copies the pose-Q1 pictures of each step into ``docs/images/irb_lab_*.png``.

Run: ``python docs/irb_lab_pictures.py`` (about two minutes on 2 cores); ``--out DIR``
writes elsewhere.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from lab_pictures import make_pictures  # noqa: E402

URDF = HERE.parents[1] / "shared/data/irb4600/urdf/irb4600_60_205.urdf"
#: The thesis's poses P1-P3 [deg]; an imported robot has no names for them.
POSES = "0,52,-19,12,-15,-11;0,0,66,0,-66,0;0,32,20,101,-98,-35"
STEPS = (
    ["import-urdf", str(URDF), "--total-mass", "425", "-o", "irb.toml"],
    ["lab", "--robot", "irb.toml", "--poses", POSES, "--modal", "lab.uff", "--n-modes", "4",
     "--effect", "mass:l3=20kg", "-o", "static.csv"],
    ["ema", "lab.uff", "-o", "modal.csv"],
    ["check-damping", "modal.csv", "--robot", "irb.toml", "--plot", "damping.png"],
    ["diagnose", "static.csv", "--robot", "irb.toml", "--modal", "modal.csv",
     "--report", "diag"],
)
PICTURES = {
    "modal.stabilisation_Q1.png": "irb_lab_ema_stabilisation.png",
    "modal.frf_Q1.png": "irb_lab_ema_frf.png",
    "damping.png": "irb_lab_check_damping.png",
    "diag/history.png": "irb_lab_diagnose_history.png",
}

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE / "images")
    for path in make_pictures(parser.parse_args().out, STEPS, PICTURES):
        print(f"wrote {path}")  # noqa: T201
