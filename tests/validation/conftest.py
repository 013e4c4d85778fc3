"""Shared fixtures for the diagnosis tests: the demo E-model and a lab helper."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.effects import parse_effect
from flexarm.validation.data.load_plan import LabPlan, parse_dirs, parse_loads
from flexarm.validation.lab.virtual_lab import virtual_lab

from .helpers import PERTURB

#: Coarse mesh [m] of the flexible model in the link-flexibility tests.
FLEX_MESH = 0.06


@pytest.fixture(scope="session")
def demo():
    from flexarm.assembly.emodel import emodel
    from flexarm.robot.demo_arm import load_demo_robot

    robot = load_demo_robot()
    return robot, emodel(robot, method="surface")

@pytest.fixture(scope="session")
def lab(demo):
    robot, arm = demo

    def make(effects=(), poses=("P1", "P2", "P3"), dirs="x,y,z,-x,-y,-z", cycles=False,
             seed=1, noise=15e-6, perturb=PERTURB, model=None, flexible=None,
             loads="0:800:100", ref_noise=0.0):
        plan = LabPlan({p: robot.pose(p) for p in poses}, parse_loads(loads),
                       parse_dirs(dirs), cycles)
        pert = [parse_effect(f"stiffness:j{j + 1}={s}") for j, s in enumerate(perturb)]
        return virtual_lab(arm if model is None else model, plan,
                           pert + [parse_effect(e) for e in effects], noise, seed, flexible,
                           ref_noise)

    return make


@pytest.fixture(scope="session")
def flex(demo):
    """(E-model, flexible model) of the demo arm on a coarse mesh (superelement cache).

    Both use the same tet meshes for the link masses, so the flexible model's rigid
    limit is exactly this E-model.
    """
    from flexarm.assembly.build import BuildOptions
    from flexarm.assembly.emodel import emodel
    from flexarm.assembly.flexible import flexible_arm

    robot = demo[0]
    return (emodel(robot, method="tets", mesh_size=FLEX_MESH),
            flexible_arm(robot, BuildOptions(mesh_size=FLEX_MESH, n_modes=4)))

def covers(value: float, sd: float, truth: float, z: float = 2.58) -> bool:
    return abs(value - truth) <= z * sd + 1e-15


def noise_alone(problem, data, clean, modal_clean=None) -> tuple[float, float, int]:
    """The truth's own fit to the data: (chi^2, RMS [m] of the relative residuals, n_obs).

    ``clean``: the same lab data without noise (``noise=0``, same seed and effects);
    ``modal_clean``: the noiseless frequencies, when ``problem`` holds modal data.
    This chi^2 is chi^2(n_obs) distributed on every seed, so it tells an unlucky noise
    draw (the truth itself outside the band) from a wrong final model.
    """
    r = data.disp - clean.disp
    z = problem.whiten(r)
    chi = float(z @ z)
    if modal_clean is not None:
        f = np.asarray(modal_clean.freq_hz, float)[problem.modal_keep]
        chi += float((((problem.f_meas - f) / problem.f_sd) ** 2).sum())
    return chi, float(np.sqrt(np.mean(r[~problem.is_ref] ** 2))), problem.n_obs

np.seterr(all="ignore")
