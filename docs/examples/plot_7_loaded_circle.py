"""
The loaded circle
=================

The thesis's ball-bar circle (its RAPID module) pushed with 0 to 800 N: the path's
deviation from the programmed circle on the E-model (``flexarm circle``).
"""

import tempfile

from _show import show

from flexarm.robot import load_robot
from flexarm.studies.contact import run_circle

circle = run_circle(load_robot(), loads=(0, 400, 800))
print(circle.text())
show(*[p for p in circle.write(tempfile.mkdtemp()) if p.suffix == ".png"][:2])
