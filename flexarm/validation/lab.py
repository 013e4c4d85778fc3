"""Virtual lab: static load-deflection series from a model plus hidden effects and noise.

The lab reproduces the thesis's LDBB + laser-tracker procedure (chapter 3.4): at each
pose and load direction a series of readings at increasing load (optionally loading
then unloading); the tracker measures the TCP position with independent noise at each
reading, and the file holds the displacement relative to the series' first reading, so
the *reference reading's* noise is shared by every row of its series.  The truth
(effects, stiffness errors, seed) goes to a separate JSON file that ``diagnose``
never reads.
"""

from __future__ import annotations

import json
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..assembly.effects import apply_effects
from ..assembly.linkflex import links_arm, split_links
from ..assembly.statics import relative_deflection
from ..assembly.system import ArmModel
from ..fe.files import atomic_path
from ..robot.effects import Effect
from .formats import write_static
from .measurements import StaticData

__all__ = ["LabPlan", "parse_dirs", "parse_loads", "virtual_lab", "write_lab"]

log = logging.getLogger(__name__)

_AXES = {"x": 0, "y": 1, "z": 2}


def parse_loads(text: str) -> np.ndarray:
    """Load levels [N] from ``"0:800:100"`` (start:stop:step, inclusive) or ``"0,200,400"``."""
    if ":" in text:
        a, b, c = (float(v) for v in text.split(":"))
        if c <= 0 or b < a:
            raise ValueError(f"loads '{text}': need start <= stop and step > 0")
        return np.arange(a, b + c / 2, c)
    return np.array([float(v) for v in text.split(",")])


def parse_dirs(text: str) -> list[tuple[str, np.ndarray]]:
    """Load directions from ``"x,y,z,-z"``: (label, unit vector in the base frame)."""
    out = []
    for d in (t.strip().lower() for t in text.split(",") if t.strip()):
        sign = -1.0 if d.startswith("-") or d.endswith("-") else 1.0
        axis = d.strip("+-")
        if axis not in _AXES:
            raise ValueError(f"direction '{d}': expected x, y, z with optional sign")
        v = np.zeros(3)
        v[_AXES[axis]] = sign
        out.append((("-" if sign < 0 else "+") + axis, v))
    return out


@dataclass(frozen=True)
class LabPlan:
    """An experiment: poses (name -> q [rad]), load levels [N], directions, cycles."""

    poses: dict
    loads: np.ndarray
    dirs: list
    cycles: bool = False

    def rows(self) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
        """Series labels, steps, q (n, 6) [rad], force (n, 3) [N] of every reading."""
        levels = np.asarray(self.loads, dtype=float)
        if self.cycles:
            levels = np.r_[levels, levels[-2::-1]]
        series, steps, qs, forces = [], [], [], []
        for pname, q in self.poses.items():
            for dname, v in self.dirs:
                for k, f in enumerate(levels):
                    series.append(f"{pname}_{dname}")
                    steps.append(k)
                    qs.append(q)
                    forces.append(f * v)
        return series, np.array(steps), np.array(qs, float), np.array(forces, float)


def virtual_lab(arm: ArmModel, plan: LabPlan, effects: list[Effect] = (), noise: float = 15e-6,
                seed: int = 0, flexible: ArmModel | None = None,
                ref_noise: float = 0.0) -> StaticData:
    """Measured-like static data of ``arm`` with hidden ``effects`` and tracker ``noise`` [m].

    ``ref_noise`` [m] adds an extra error to each series' reference reading only (the
    tracker re-locked on the reflector, or a reference averaged over a shorter window);
    it is shared by every row of the series, like the reference's ordinary noise.

    A ``links`` effect (link flexibility) needs ``flexible``, the robot's flexible model.

    Examples
    --------
    >>> from flexarm.assembly.emodel import emodel
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> robot = load_demo_robot()
    >>> arm = emodel(robot, method="surface")
    >>> plan = LabPlan({"P1": robot.pose("P1")}, np.array([0.0, 100.0]), parse_dirs("z"))
    >>> virtual_lab(arm, plan, noise=0.0).disp.shape
    (2, 3)
    """
    series, steps, q, force = plan.rows()
    c, rest = split_links(effects)
    truth, laws = apply_effects(links_arm(arm, flexible, c), rest)
    u = relative_deflection(truth, q, force, None, series, laws)
    rng = np.random.default_rng(seed)
    e = noise * rng.standard_normal(u.shape)
    labels = np.array(series)
    ref = np.flatnonzero(np.r_[True, labels[1:] != labels[:-1]])
    start = ref[np.cumsum(np.r_[True, labels[1:] != labels[:-1]]) - 1]
    if ref_noise > 0:
        e[ref] += ref_noise * rng.standard_normal((len(ref), 3))
    disp = u + e - e[start]
    disp[ref] = 0.0
    sigma = np.full(len(u), noise)
    sigma[ref] = np.hypot(noise, ref_noise)  # the file states the reference's uncertainty
    log.info("virtual lab: %d readings in %d series, %d effects", len(u), len(ref), len(effects))
    return StaticData(series=series, steps=steps, q=q, force=force, disp=disp,
                      sigma=sigma if noise > 0 else None)


def write_lab(path, data: StaticData, truth: dict) -> tuple[Path, Path]:
    """Write the data file and ``<stem>.truth.json`` next to it; returns both paths."""
    path = Path(path)
    write_static(path, data, comments=("virtual lab data (flexarm lab)",))
    tpath = path.with_suffix(".truth.json")
    with atomic_path(tpath) as tmp:
        tmp.write_text(json.dumps(truth, indent=2, sort_keys=True))
    return path, tpath
