"""
A stiffness map over joints 2 and 3
===================================

The TCP stiffness along y and the first frequency of the demo arm's E-model over a
(q2, q3) grid, the other joints at P1's angles (``flexarm map``).
"""

import tempfile

import numpy as np
from _show import show

from flexarm.assembly import ArmSpec, build_arm
from flexarm.assembly.maps import plot_map, stiffness_map
from flexarm.robot import load_robot

robot = load_robot()
arm = build_arm(robot, ArmSpec("emodel")).model
q2 = np.radians(np.linspace(-60, 120, 37))
q3 = np.radians(np.linspace(-150, 60, 43))
m = stiffness_map(arm, robot.pose("P1"), q2, q3, label="E-model", pose_name="P1")
files = plot_map(m, tempfile.mkdtemp(), surfaces=False)
show(*[p for p in files if "Kyy" in p.name or "f1" in p.name])
