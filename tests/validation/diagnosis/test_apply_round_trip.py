"""``diagnose --apply`` writes every accepted effect: the written robot file, read back and
compared with the same data, gives the diagnosis's final chi-square to 1e-6, for every
kind of candidate (springs built into the joints, base and wrist; joint laws in
``[nonlinear]``; tool, balancer and measurement frame in ``[[effects]]``).  The kinds
found with vibration data (added mass, load cell, reflector, foundation per axis) are
checked where they are diagnosed, ``test_search_new_causes.py``
(:func:`assert_round_trip`)."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.formats import read, write
from flexarm.validation import compare
from flexarm.validation.diagnosis.history import robot_with_effects
from flexarm.validation.diagnosis.search import diagnose

from ..misfit_cases import BALANCER, FRAME, TOOL, balancer_plan, lab_data, standard_plan

SIGMA = 15e-6

#: kind accepted -> (hidden effects, load/unload cycles, balancer poses)
CASES = {
    "backlash": (("backlash:j2=0.1mrad",), False, False),
    "hardening": (("hardening:j1=0.5,t=400Nm",), False, False),
    "hysteresis": (("hysteresis:j2=0.1mrad,r=300Nm",), True, False),
    "base": (("base:k=1e7",), False, False),
    "wrist": (("wrist:c45=0.5",), False, False),
    "tool": ((TOOL,), False, False),
    "frame": ((FRAME,), False, False),
    "balancer": ((BALANCER,), False, True),
}


@pytest.mark.parametrize("kind", sorted(CASES))
def test_the_written_file_gives_the_final_chi2(demo, kind, tmp_path):
    robot, arm = demo
    hidden, cycles, balancer = CASES[kind]
    plan = balancer_plan(robot) if balancer else standard_plan(robot)
    if cycles:
        from dataclasses import replace

        plan = replace(plan, cycles=True)
    data = lab_data(arm, plan, hidden, seed=3)
    dg = diagnose(arm, data, SIGMA, heldout=False)
    assert kind in [e.kind for e in dg.accepted], dg.text()
    path = tmp_path / "identified.toml"
    write(path, robot_with_effects(robot, arm, dg.final_effects))
    back = read(path)
    cmp = compare(data, back, noise_um=SIGMA * 1e6)
    final = dg.final
    assert cmp.chi2_red * cmp.problem.n_obs == pytest.approx(final.chi2_red * final.dof,
                                                             rel=1e-6)
    nominal = compare(data, robot, noise_um=SIGMA * 1e6)
    assert cmp.chi2_red < nominal.chi2_red


#: kind accepted -> hidden effect, found with vibration data (6 modes at P1-P3, 0.3 %)


def assert_round_trip(robot, arm, data, dg, poses, tmp_path) -> None:
    """The file ``diagnose --apply`` writes for ``dg`` gives its final static chi-square
    to 1e-6 and its natural frequencies at ``poses`` to 1e-6 (an added mass as a lumped
    mass of its link, a foundation per axis as the base spring, the load cell and
    reflector in ``[[effects]]``)."""
    from flexarm.assembly.analyses import natural_frequencies
    from flexarm.assembly.effects import apply_effects
    from flexarm.validation.models import DEFAULT_OPTIONS, validation_models
    from flexarm.validation.static.fit import Problem

    path = tmp_path / "identified.toml"
    write(path, robot_with_effects(robot, arm, dg.final_effects))
    back = read(path)
    pb = Problem(arm, data, SIGMA)
    r = pb.wy() - pb.wpredict(dg.final_effects)
    cmp = compare(data, back, noise_um=SIGMA * 1e6)
    assert cmp.chi2_red * cmp.problem.n_obs == pytest.approx(float(r @ r), rel=1e-6)
    fitted, _ = apply_effects(arm, dg.final_effects)
    rebuilt = validation_models(back, DEFAULT_OPTIONS).arm
    for q in poses.values():
        assert np.allclose(natural_frequencies(rebuilt, q), natural_frequencies(fitted, q),
                           rtol=1e-6)
