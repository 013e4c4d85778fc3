"""
Modal identification and MAC
============================

FRFs of the demo arm at P1 (receptance at 12 points per hammer hit at the TCP, 2 %
noise), identified by LSCF and LSFD: the stabilisation diagram, then the identified shapes
against the model's by MAC (``flexarm ema``, ``flexarm compare``).
"""

import tempfile
from pathlib import Path

import numpy as np
from _show import show

from flexarm.assembly import ArmSpec, build_arm
from flexarm.robot import load_robot
from flexarm.validation.dynamic.compare_shapes import compare_shapes
from flexarm.validation.dynamic.ema import run_ema
from flexarm.validation.dynamic.shapes import default_points
from flexarm.validation.lab.modal_lab import virtual_frfs

robot = load_robot()
arm = build_arm(robot, ArmSpec("emodel")).model
points = default_points(robot)
frfs = virtual_frfs(arm, {"P1": robot.pose("P1")}, points, [(601, "y"), (601, "z")],
                    np.linspace(1.0, 60.0, 600), seed=1)
ema = run_ema(frfs)
print(ema.text())
out = Path(tempfile.mkdtemp())
plots = ema.write_plots(out / "ema")
files = compare_shapes(arm, ema.modal(), points).write(out)
show(plots[0], *[p for p in files if p.name.startswith("mac_")])
