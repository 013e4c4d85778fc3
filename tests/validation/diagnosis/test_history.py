"""robot_with_effects: the joints whose springs a fit writes are no longer placeholders."""

from __future__ import annotations

from dataclasses import replace

from flexarm.assembly.emodel import emodel
from flexarm.robot.effects import parse_effect
from flexarm.validation.diagnosis.history import robot_with_effects


def test_identified_joints_lose_the_placeholder_mark(demo):
    robot, _ = demo
    guess = replace(robot, joints=tuple(
        replace(j, model=replace(j.model, source="placeholder"),
                emodel=None if i == 1 else j.emodel) for i, j in enumerate(robot.joints)))
    arm = emodel(guess, method="surface")
    effects = [parse_effect("stiffness:j3=1.3"), parse_effect("tilt:j2=1e7"),
               parse_effect("backlash:j1=0.1mrad"), parse_effect("base:k=2e7")]
    new = robot_with_effects(guess, arm, effects)
    marks = [j.model.is_placeholder for j in new.joints]
    assert marks == [True, True, False, True, True, True]  # a tilt fit leaves the torsion unknown
    assert new.joints[2].model.torsion == guess.joints[2].model.torsion * 1.3
    assert new.joints[2].emodel is not None and not new.joints[2].emodel.is_placeholder
    assert new.joints[1].emodel is None and new.joints[1].model.tilt < float("inf")
