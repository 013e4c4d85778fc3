"""The ABB IRB 4600-60/2.05 as published (``../shared/data/irb4600``, ROS-Industrial,
Apache-2.0), imported the way a user would: ``flexarm import-urdf``.

The description is read from the shared folder and never copied into the project;
tests that need it skip when it is absent.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest

URDF = Path(__file__).resolve().parents[2] / "shared/data/irb4600/urdf/irb4600_60_205.urdf"
#: the thesis's pose P1 [deg] (q1..q6), which an imported robot has no name for
P1 = "0,52,-19,12,-15,-11"
P2 = "0,0,66,0,-66,0"
#: tet edge [m] of the default-suite builds (the robot's own is 0.03 m)
COARSE = 0.08
#: the datasheet mass [kg]
MASS = 425.0


def import_irb(folder: Path, *options: str) -> tuple[Path, str, str]:
    """``flexarm import-urdf URDF --total-mass 425 [options] -o folder/irb.toml``:
    the TOML written, and what the command printed to stdout and stderr."""
    from flexarm.cli import main

    if not URDF.is_file():
        pytest.skip(f"no IRB 4600 description at {URDF}")
    toml = Path(folder) / "irb.toml"
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["import-urdf", str(URDF), "--total-mass", str(MASS), *options,
                     "-o", str(toml)])
    assert code == 0, err.getvalue()
    return toml, out.getvalue(), err.getvalue()
