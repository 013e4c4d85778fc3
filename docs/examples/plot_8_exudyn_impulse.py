"""
A hammer test in Exudyn
=======================

The demo arm's E-model as an Exudyn multibody model, hit at the TCP at P1: the spectrum
of the response against flexarm's modes and receptance (``flexarm exudyn-impulse``;
needs ``pip install "flexarm[mbs]"``).
"""

import tempfile

from _show import show

from flexarm.assembly import ArmSpec, build_arm
from flexarm.robot import load_robot
from flexarm.studies.exudyn.impulse import impulse_test

robot = load_robot()
arm = build_arm(robot, ArmSpec("emodel"))
test = impulse_test(arm, robot.pose("P1"), n=3, duration=2.0)
print(test.text())
show(*[p for p in test.write(tempfile.mkdtemp()) if p.suffix == ".png"])
