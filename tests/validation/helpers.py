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


def lab_shapes(robot, n_modes: int = 12):
    """``n_modes`` modes at P1-P3 of ``robot``'s E-model: frequencies, damping ratios and
    shapes as the virtual lab measures them."""
    from flexarm.validation.lab.virtual_lab import run_lab

    return run_lab(robot, poses="P1,P2,P3", loads="0:100:100", dirs="z", modal=True,
                   n_modes=n_modes).shapes


def noisy_damping(shapes, seed: int, noise: float = 0.03):
    """``shapes`` with relative Gaussian noise ``noise`` (seeded) on every damping ratio."""
    from dataclasses import replace

    rng = np.random.default_rng(seed)
    return replace(shapes, damping_ratio=shapes.damping_ratio * (
        1 + noise * rng.standard_normal(len(shapes.damping_ratio))))


def lab_damping(robot, seed: int, n_modes: int = 12, noise: float = 0.03):
    """:func:`lab_shapes` with :func:`noisy_damping`."""
    return noisy_damping(lab_shapes(robot, n_modes), seed, noise)
