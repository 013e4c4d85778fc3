"""
Craig-Bampton against the full model
====================================

A bar link reduced onto its two end faces: the error of the reduced model's
frequencies and end compliance against the unreduced FE model, per interface
representation and number of fixed-interface modes (``flexarm study-part``).
"""

import tempfile

from _show import show

from flexarm.fe import MATERIALS
from flexarm.studies.part_study import run_part_study

out = tempfile.mkdtemp()
study = run_part_study(MATERIALS["steel"], representations=("rbe2", "rbe3"),
                       mode_counts=(0, 5, 10, 20), divisions=((12, 2, 2),), out_dir=out)
print(study.text())
show(*[p for p in study.files if str(p).endswith(".png")])
