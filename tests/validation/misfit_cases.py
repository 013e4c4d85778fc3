"""Virtual-lab data with effects outside the candidate library (and with the new
candidates' effects), shared by the residual-structure, misfit and candidate tests."""

from __future__ import annotations

import numpy as np

from flexarm.robot.effects import parse_effect
from flexarm.validation.data.load_plan import LabPlan, parse_dirs, parse_loads
from flexarm.validation.lab.faults import (
    with_drift,
    with_joint_law,
    with_outliers,
    with_stated_sigma,
)
from flexarm.validation.lab.virtual_lab import virtual_lab

from .helpers import PERTURB

SIGMA = 15e-6
#: Drift of the tracker per reading [m] (about 5 µm, in file order).
DRIFT = (3e-6, 0.0, 4e-6)
#: Glitches: three readings off by 0.4 mm.
N_OUTLIERS, OUTLIER_SIZE = 3, 0.4e-3
#: Noise 1.7 times the stated 15 µm.
NOISE_FACTOR = 1.7


def softening(tau):
    """A smooth joint law outside the library: joint 2 turns 0.1 mrad x (tau / 2500 N m)^3
    more (softening with load; the hardening candidate needs the opposite sign)."""
    return 1e-4 * (tau / 2500.0) ** 3


#: Case -> (expected structure, hidden effect specs).
MISFIT_CASES = {
    "frame": ("frame", ("frame:rz=1.5deg",)),
    "drift": ("drift", ()),
    "outliers": ("outliers", ()),
    "noise": ("scale", ()),
    "joint_law": ("joint_law", ()),
    "tool": ("tool", ("tool:cxx=1e-7,cyy=1e-7,czz=3e-7",)),
}

#: Balancer scenario: joint-2 angles [deg] of the five series poses (P1 otherwise).
BALANCER_Q2_DEG = (-20, 0, 20, 40, 60)
BALANCER = "balancer:j2=2e6,s=1e6"
TOOL = "tool:cxx=1e-7,cyy=1e-7,czz=3e-7"
FRAME = "frame:rz=1.5deg,scale=0.003"


def standard_plan(robot, loads="0:800:100") -> LabPlan:
    return LabPlan({p: robot.pose(p) for p in ("P1", "P2", "P3")}, parse_loads(loads),
                   parse_dirs("x,y,z,-x,-y,-z"))


def balancer_plan(robot) -> LabPlan:
    q0 = np.asarray(robot.pose("P1"), float)
    poses = {}
    for a in BALANCER_Q2_DEG:
        q = q0.copy()
        q[1] = np.radians(a)
        poses[f"Q{a}"] = q
    return LabPlan(poses, parse_loads("0:800:100"), parse_dirs("x,y,z,-x,-y,-z"))


def lab_data(arm, plan, effects=(), seed=1, noise=SIGMA):
    pert = [parse_effect(f"stiffness:j{j + 1}={s}") for j, s in enumerate(PERTURB)]
    return virtual_lab(arm, plan, pert + [parse_effect(e) for e in effects], noise, seed)


def misfit_data(robot, arm, case: str, seed: int):
    """Data of misfit case ``case`` (:data:`MISFIT_CASES`), and the glitched rows (outliers)."""
    plan = standard_plan(robot)
    effects = MISFIT_CASES[case][1] if case in MISFIT_CASES else ()
    noise = SIGMA * (NOISE_FACTOR if case == "noise" else 1.0)
    data = lab_data(arm, plan, effects, seed, noise)
    rows = np.zeros(0, int)
    if case == "noise":
        data = with_stated_sigma(data, SIGMA)
    elif case == "drift":
        data = with_drift(data, DRIFT)
    elif case == "outliers":
        data, rows = with_outliers(data, N_OUTLIERS, OUTLIER_SIZE, seed)
    elif case == "joint_law":
        data = with_joint_law(data, arm, 1, softening)
    return data, rows
