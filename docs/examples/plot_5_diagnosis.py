"""
Finding the missing effect
==========================

Virtual tracker data of an arm whose joint 2 has 0.1 mrad of backlash the model lacks:
the diagnosis names it, and the error of each model version falls to the noise
(``flexarm lab``, ``flexarm diagnose --report``).
"""

import tempfile

from _show import show

from flexarm.validation import run_diagnosis, run_lab

lab = run_lab(effects=["backlash:j2=0.1mrad"], dirs="x,y,z,-x,-y,-z", seed=3)
run = run_diagnosis(lab.data)
print(run.diagnosis.misfit.headline())
show(*[p for p in run.write_history(tempfile.mkdtemp()) if p.suffix == ".png"])
