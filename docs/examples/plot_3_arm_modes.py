"""
The arm's modes at a pose
=========================

The demo arm's E-model (rigid links on joint springs) at the thesis's pose P1: its first
frequencies, how their strain energy is shared among the joints, and the first mode
drawn on the links' CAD (``flexarm modes`` and ``flexarm show-arm``).
"""

import tempfile
from pathlib import Path

from _show import show

from flexarm.assembly import ArmSpec, build_arm
from flexarm.assembly.analyses import modes
from flexarm.robot import load_robot
from flexarm.studies.plots import plot_mode_energy
from flexarm.studies.render_arm import render_arm_mode

robot = load_robot()
arm = build_arm(robot, ArmSpec("emodel"))
q = robot.pose("P1")
m = modes(arm.model, q)
print(", ".join(f"{f:.2f}" for f in m.freq_hz), "Hz")

out = Path(tempfile.mkdtemp())
plot_mode_energy(out / "energy.png", m.freq_hz, m.energy, robot.joint_names,
                 "E-model, pose P1: strain energy per joint")
render_arm_mode(arm, q, mode=1, path=out / "mode1.png", pose_name="P1")
show(out / "energy.png", out / "mode1.png")
