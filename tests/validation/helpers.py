"""Data builders shared by the validation tests and the CLI tests of its commands."""

from __future__ import annotations

import numpy as np

from flexarm.assembly.analyses import frf
from flexarm.assembly.effects import apply_effects
from flexarm.validation import FrfData

#: Truth stiffness errors of the lab arm vs the model given to diagnose (±30 %).
PERTURB = (1.3, 0.7, 1.3, 0.7, 1.3, 0.7)


def frf_data(arm, robot, effects=()) -> FrfData:
    """Receptances yy and zz of ``arm`` (plus ``effects``) at P1, 40 lines 2-60 Hz."""
    truth, _ = apply_effects(arm, list(effects))
    q = robot.pose("P1")
    f = np.linspace(2.0, 60.0, 40)
    H = frf(truth, q, f)
    rows = [("y", "y"), ("z", "z")]
    n = len(f)
    return FrfData(poses=["P1"] * (n * len(rows)), q=np.tile(q, (n * len(rows), 1)),
                   inputs=np.repeat([i for i, _ in rows], n),
                   outputs=np.repeat([o for _, o in rows], n), freq_hz=np.tile(f, len(rows)),
                   receptance=np.concatenate([H[:, "xyz".index(o), "xyz".index(i)]
                                              for i, o in rows]))
